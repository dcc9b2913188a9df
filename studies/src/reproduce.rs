//! Regenerates the section II results under `results/`: the paper's Fig. 3
//! (steady-state velocity against distance from the axis), the
//! time-to-travel analysis (eq. 22), the effect of each term the paper's
//! analysis drops, and the integrator's convergence table.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::Vector2;

use super::linesink::{LineSink, Wave};
use platefield::dynamics::{Friction, Model, Numerics, PartPhysics, PartState, Simulator};
use platefield::error::{Error, Result};
use platefield::output::write_atomic;
use platefield_report::plot::{LegendPosition, LinePlot, Series};
use platefield_report::table::Table;

const T: f64 = 0.03;
const MU: f64 = 0.3;
const G: f64 = 9.81;

fn shaker(wave: Wave, accel: f64, depth: f64) -> LineSink {
    LineSink {
        wave,
        accel,
        depth,
        period: T,
        friction: Friction::uniform(MU),
        gravity: G,
    }
}

/// The Fig. 3 cases: (label, shaker).
pub(crate) fn fig3_cases() -> Vec<(&'static str, LineSink)> {
    vec![
        ("square_a180_h5cm", shaker(Wave::Square, 180.0, 0.05)),
        ("sine_a220_h5cm", shaker(Wave::Sine, 220.0, 0.05)),
        ("sine_a220_h2cm", shaker(Wave::Sine, 220.0, 0.02)),
        ("sine_a220_h1cm", shaker(Wave::Sine, 220.0, 0.01)),
    ]
}

fn cell(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:.9e}"))
}

/// Writes `linesink_fig3.csv` and `linesink_fig3.svg`; returns the CSV text.
pub(crate) fn fig3(out: &Path) -> Result<String> {
    let rs: Vec<f64> = (0..=50).map(|i| i as f64 * 0.001).collect();
    let numerics = Numerics::default();
    let cases = fig3_cases();
    let eq_ref = &cases[0].1;
    let mut header = vec![
        "r_m".to_string(),
        "eq21".into(),
        "eq17_square_a180_h5cm".into(),
    ];
    let mut columns: Vec<Vec<Option<f64>>> = vec![
        rs.iter().map(|&r| Some(eq_ref.eq21(r))).collect(),
        rs.iter().map(|&r| eq_ref.eq17(r)).collect(),
    ];
    for (label, ls) in &cases {
        for model in [Model::PAPER, Model::FULL] {
            let rows = ls.rows(&rs, model, numerics);
            header.push(format!("{label}_{}", model.name()));
            columns.push(rows.iter().map(|r| r.v_ss).collect());
            header.push(format!("{label}_{}_stick_fraction", model.name()));
            columns.push(rows.iter().map(|r| r.stick_fraction).collect());
        }
    }
    let mut csv = header.join(",") + "\n";
    for (i, r) in rs.iter().enumerate() {
        let cells: Vec<String> = columns.iter().map(|c| cell(c[i])).collect();
        let _ = writeln!(csv, "{r:.4},{}", cells.join(","));
    }
    write_atomic(&out.join("linesink_fig3.csv"), csv.as_bytes())?;
    let mut plot =
        LinePlot::new("LineSink steady-state velocity (paper Fig. 3): T = 0.03 s, μ = 0.3")
            .labels("distance from axis r (cm)", "v_ss (mm/s)")
            .legend(LegendPosition::BottomLeft);
    for (name, col) in header.iter().skip(1).zip(&columns) {
        if name.ends_with("stick_fraction") {
            continue;
        }
        let pts: Vec<[f64; 2]> = rs
            .iter()
            .zip(col)
            .filter_map(|(r, v)| v.map(|v| [r * 100.0, v * 1e3]))
            .collect();
        let mut series = Series::new(name.clone(), pts);
        if name.starts_with("eq") {
            series = series.dashed();
        }
        plot = plot.series(series);
    }
    write_atomic(&out.join("linesink_fig3.svg"), plot.to_svg().as_bytes())?;
    Ok(csv)
}

/// Effect of each term the paper drops, for the sine wave at h = 5 cm:
/// the relative change of v_ss when each switch alone is turned on, and
/// the full model. Writes `linesink_terms.md`.
pub fn terms(out: &Path) -> Result<String> {
    let ls = shaker(Wave::Sine, 220.0, 0.05);
    let rs = [0.01, 0.02, 0.03, 0.04];
    let numerics = Numerics::default();
    let variants: [(&str, Model); 6] = [
        ("paper", Model::PAPER),
        (
            "+centripetal",
            Model {
                centripetal: true,
                ..Model::PAPER
            },
        ),
        (
            "+tilt",
            Model {
                tilt: true,
                ..Model::PAPER
            },
        ),
        (
            "+coriolis",
            Model {
                coriolis: true,
                ..Model::PAPER
            },
        ),
        (
            "+moving",
            Model {
                moving: true,
                ..Model::PAPER
            },
        ),
        ("full", Model::FULL),
    ];
    let mut md = String::from(
        "# LineSink: what each term the paper drops changes\n\n\
         Sine angular acceleration A = 220 rad/s², axis 5 cm below, T = 0.03 s, μ = 0.3.\n\
         Steady-state velocity (mm/s) and, in brackets, the change relative to the paper model.\n\
         Regenerate: `platefield study reproduce`.\n\n",
    );
    let mut table = Table::new(["r (cm)"].into_iter().chain(variants.iter().map(|v| v.0)));
    for &r in &rs {
        let base = ls.rows(&[r], Model::PAPER, numerics)[0].v_ss;
        let mut row = vec![format!("{:.0}", r * 100.0)];
        for (_, model) in &variants {
            let v = ls.rows(&[r], *model, numerics)[0].v_ss;
            row.push(match (v, base) {
                (Some(v), Some(b)) => {
                    format!("{:.4} ({:+.2} %)", v * 1e3, (v - b) / b.abs() * 100.0)
                }
                _ => "contact lost".into(),
            });
        }
        table.row(row);
    }
    md.push_str(&table.markdown());
    md.push_str(
        "\nReading: the centripetal term ψ'²·(r − h) adds a small steady horizontal push \
         toward the axis and raises N; the gravity tilt adds g·sin ψ along the plate, \
         which is zero-mean for a symmetric oscillation but correlates with N; Coriolis \
         2Ω×u changes N in proportion to the slip speed; letting the part move during the \
         cycle samples the field over its within-cycle excursion. All are percent-level \
         at the paper's parameters, as the paper assumes.\n",
    );
    write_atomic(&out.join("linesink_terms.md"), md.as_bytes())?;
    Ok(md)
}

/// Result of the time-to-travel run.
#[derive(Debug, Clone)]
pub struct Travel {
    /// (r, ln(r0/r), t) at each threshold crossing.
    pub points: Vec<(f64, f64, f64)>,
    /// Fitted t = intercept + slope·ln(r0/r).
    pub slope: f64,
    /// Intercept of the fit.
    pub intercept: f64,
    /// Coefficient of determination of the fit.
    pub r2: f64,
}

/// A free part (full model) released at rest at 4 cm under the sine
/// LineSink (A = 220, h = 5 cm): time to reach each radius against
/// ln(r0/r), which eq. 22 predicts to be a line of slope 1/k.
pub fn travel(out: &Path) -> Result<Travel> {
    let ls = shaker(Wave::Sine, 220.0, 0.05);
    let motion = ls.motion();
    let sim = Simulator::new(
        &motion,
        PartPhysics::new(ls.friction, G, Model::FULL),
        Numerics::default(),
    );
    let r0 = 0.04;
    let thresholds: Vec<f64> = (1..=7).map(|i| r0 - 0.005 * i as f64).collect();
    let mut state = PartState::new(Vector2::new(r0, 0.0), Vector2::zeros());
    let anchor = state.r;
    let mut points = Vec::new();
    let (mut t, mut prev_x) = (0.0, r0);
    let mut next = 0;
    while next < thresholds.len() {
        if t > 100.0 {
            return Err(Error::NotConverged(format!(
                "travel: part did not reach r = {} m within 100 s",
                thresholds[next]
            )));
        }
        sim.advance(t, t + T, &mut state, &anchor, None)
            .map_err(|c| Error::ContactLost(c.to_string()))?;
        t += T;
        let x = state.r.x;
        while next < thresholds.len() && x <= thresholds[next] {
            // Linear interpolation between cycle ends.
            let f = (prev_x - thresholds[next]) / (prev_x - x);
            let tc = t - T + f * T;
            points.push((thresholds[next], (r0 / thresholds[next]).ln(), tc));
            next += 1;
        }
        prev_x = x;
    }
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.1).sum::<f64>() / n;
    let my = points.iter().map(|p| p.2).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.1 - mx) * (p.2 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.1 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_res: f64 = points
        .iter()
        .map(|p| (p.2 - intercept - slope * p.1).powi(2))
        .sum();
    let ss_tot: f64 = points.iter().map(|p| (p.2 - my).powi(2)).sum();
    let r2 = 1.0 - ss_res / ss_tot;
    let mut csv = String::from("r_m,ln_r0_over_r,t_s,t_fit_s\n");
    for p in &points {
        let _ = writeln!(
            csv,
            "{:.4},{:.9},{:.9},{:.9}",
            p.0,
            p.1,
            p.2,
            intercept + slope * p.1
        );
    }
    let _ = writeln!(csv, "# fit: t = {intercept:.6} + {slope:.6} ln(r0/r), R^2 = {r2:.6}; k = 1/slope = {:.6} 1/s; eq. 21 k = 3 mu T A / 8 = {:.6} 1/s (square-wave value, for scale)", 1.0 / slope, 3.0 * MU * T * 220.0 / 8.0);
    write_atomic(&out.join("linesink_travel.csv"), csv.as_bytes())?;
    Ok(Travel {
        points,
        slope,
        intercept,
        r2,
    })
}

/// Convergence of the steady-state velocity with the number of RK4 steps
/// per cycle, for the sine cases (where the integration is not exact),
/// against a converged run with 2¹⁴ steps. Writes `linesink_convergence.md`.
pub fn convergence(out: &Path) -> Result<String> {
    let steps = [4usize, 8, 16, 32, 64, 128, 256];
    let reference = 16384;
    let mut md = String::from(
        "# Integrator convergence (sine LineSink, A = 220 rad/s², T = 0.03 s, μ = 0.3)\n\n\
         Relative error of v_ss against a run with 16384 steps per cycle; `order` is \
         log2(e(n/2)/e(n)). Events (stick, slip) are located to 1e-14 T in every run.\n\
         Regenerate: `platefield study reproduce`.\n\n",
    );
    let mut table = Table::new([
        "case",
        "model",
        "r (cm)",
        "steps/cycle",
        "v_ss (m/s)",
        "rel. error",
        "order",
    ]);
    for (label, ls) in fig3_cases().into_iter().skip(1) {
        for model in [Model::PAPER, Model::FULL] {
            let r = 0.02;
            let at = |n: usize| {
                ls.rows(
                    &[r],
                    model,
                    Numerics {
                        steps_per_cycle: n,
                        ..Numerics::default()
                    },
                )[0]
                .v_ss
            };
            let vref = at(reference).ok_or_else(|| {
                Error::ContactLost(format!("{label}: no steady state at r = {r}"))
            })?;
            let mut prev: Option<f64> = None;
            for &n in &steps {
                let v = at(n).unwrap_or(f64::NAN);
                let e = ((v - vref) / vref).abs();
                let order = prev
                    .filter(|p| *p > 0.0 && e > 0.0)
                    .map_or("".to_string(), |p| format!("{:.2}", (p / e).log2()));
                table.row([
                    label.to_string(),
                    model.name().to_string(),
                    format!("{:.0}", r * 100.0),
                    n.to_string(),
                    format!("{v:.9e}"),
                    format!("{e:.2e}"),
                    order,
                ]);
                prev = Some(e);
            }
        }
    }
    md.push_str(&table.markdown());
    write_atomic(&out.join("linesink_convergence.md"), md.as_bytes())?;
    Ok(md)
}

/// Default output folder of `platefield study reproduce`.
pub const DIR: &str = "results";

/// All section II results, written under `out`; returns the summary
/// (the files written, the time-to-travel fit).
pub fn linesink_results(out: &Path) -> Result<String> {
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.display().to_string(),
        source: e,
    })?;
    let mut s = String::new();
    fig3(out)?;
    let _ = writeln!(s, "wrote {}", out.join("linesink_fig3.csv").display());
    terms(out)?;
    let _ = writeln!(s, "wrote {}", out.join("linesink_terms.md").display());
    let t = travel(out)?;
    let _ = writeln!(
        s,
        "wrote {} (t = {:.4} + {:.4} ln(r0/r), R² = {:.5})",
        out.join("linesink_travel.csv").display(),
        t.intercept,
        t.slope,
        t.r2
    );
    convergence(out)?;
    let _ = writeln!(s, "wrote {}", out.join("linesink_convergence.md").display());
    Ok(s)
}
