//! Does a second harmonic in the in-plane translation lift the contact
//! margin's cap on the saddle? (`results/synthesis.md`'s saddle row; the
//! answer and its reason are in [`platefield::synth`]'s docs.)
//!
//! For each translation — the seed's circle at the x/y limits; tilted
//! ellipses (y's phase off by β); and the circle's harmonic 1 at (1 − f) of
//! the limit plus a harmonic 2 of f on x, on y or on both (phases in steps
//! of 45°), each axis scaled back onto its limit — the margin's cap k of
//! [`margin_cap`] (simulated linear response, linear programme) with the
//! tilts' harmonic 2 free and held at zero, and the translation's own drift
//! (the ratchet). The best four are then re-simulated with the programme's
//! tilts on a 7 × 7 grid (realised ŝ, shape error, least N at rest).

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

use super::square;
use crate::synthesis::{limits_of, sequenced};
use platefield::error::{Error, Result};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::synth::contact::kinematic_least_normal;
use platefield::synth::margin_cap::{margin_cap, tilt_response, MarginCap};
use platefield::synth::objective::realised;
use platefield::synth::params::Coefficients;
use platefield::synth::seed::{seed, AffineFit};
use platefield::synth::ShakerLimits;
use platefield_report::table::Table;

/// What every translation is judged on.
struct Setup {
    settings: FieldSettings,
    limits: ShakerLimits,
    /// The 21 × 21 region the margin is kept over.
    region: Grid,
    /// The 7 × 7 grid of the re-simulation, and the target there.
    coarse: Grid,
    target_values: Vec<[f64; 2]>,
    /// The target's affine gradient over the region.
    m: [[f64; 2]; 2],
}

/// One translation scanned: its group (the table's row), its label and
/// coefficients.
struct Candidate {
    group: String,
    label: String,
    translation: Coefficients,
}

/// A scanned translation's cap with all tilt harmonics free, the cap with
/// harmonic 1 only, and the translation's own drift (m/s).
struct Capped {
    cap: MarginCap,
    harmonic_1: f64,
    drift: [f64; 2],
}

/// Circle harmonic 1 of amplitude `a1` (counter-clockwise, y's phase off
/// by `beta`) plus harmonic 2 (amplitude, phase) per in-plane axis, each
/// axis scaled onto the linear limit.
fn translation(limits: &ShakerLimits, a1: f64, beta: f64, h2: [(f64, f64); 2]) -> Coefficients {
    let lim = limits.linear[0];
    let mut c = Coefficients::zero(limits.period, limits.harmonics);
    c.set(0, 1, a1, PI / 2.0);
    c.set(1, 1, a1, beta);
    for (a, (amp, phase)) in h2.into_iter().enumerate() {
        if amp > 0.0 {
            c.set(a, 2, amp, phase);
        }
        let p = c.peak(a);
        for cs in &mut c.c[a] {
            *cs = [cs[0] * lim / p, cs[1] * lim / p];
        }
    }
    c
}

/// The harmonic-2 translations of fraction `f` on x, y or both, every 45°.
fn harmonic_2(limits: &ShakerLimits, f: f64, on_x: bool, on_y: bool) -> Vec<Candidate> {
    let lim = limits.linear[0];
    let axes = format!(
        "{}{}",
        if on_x { " x" } else { "" },
        if on_y { " y" } else { "" }
    );
    let group = format!("harmonic 2 of {f:.2} on{axes}");
    let mut out = Vec::new();
    for i in 0..8 {
        for j in 0..(if on_x && on_y { 8 } else { 1 }) {
            let px = f64::from(i) * PI / 4.0;
            let py = if on_x && on_y {
                f64::from(j) * PI / 4.0
            } else {
                px
            };
            let h2 = [
                (if on_x { f * lim } else { 0.0 }, px),
                (if on_y { f * lim } else { 0.0 }, py),
            ];
            out.push(Candidate {
                group: group.clone(),
                label: format!(
                    "{group}, phases {:.0}° {:.0}°",
                    px.to_degrees(),
                    py.to_degrees()
                ),
                translation: translation(limits, lim * (1.0 - f), 0.0, h2),
            });
        }
    }
    out
}

/// Every translation scanned, the circle first.
fn candidates(limits: &ShakerLimits) -> Vec<Candidate> {
    let lim = limits.linear[0];
    let mut out = vec![Candidate {
        group: "circle".into(),
        label: "circle".into(),
        translation: translation(limits, lim, 0.0, [(0.0, 0.0); 2]),
    }];
    for beta in [-30.0f64, -15.0, 15.0, 30.0] {
        let group = format!("ellipse, y phase {beta:+.0}°");
        out.push(Candidate {
            label: group.clone(),
            group,
            translation: translation(limits, lim, beta.to_radians(), [(0.0, 0.0); 2]),
        });
    }
    for f in [0.05, 0.1, 0.2, 0.35] {
        for (on_x, on_y) in [(true, false), (false, true), (true, true)] {
            out.extend(harmonic_2(limits, f, on_x, on_y));
        }
    }
    out
}

/// The caps of translation `tr`, or `None` without a steady state or a
/// solution.
fn caps(s: &Setup, tr: &Coefficients) -> Option<Capped> {
    let h = s.limits.harmonics as usize;
    let g = s.settings.gravity;
    let r = tilt_response(tr, &s.region, &s.settings, h)?;
    let cap = margin_cap(&r, s.m, &s.limits, &s.region, g, h)?;
    let harmonic_1 = margin_cap(&r, s.m, &s.limits, &s.region, g, 1)?.strength;
    Some(Capped {
        cap,
        harmonic_1,
        drift: r.drift,
    })
}

/// `tr` with the programme's tilts of `cap`, re-simulated on the coarse
/// grid: one line of realised ŝ, shape error and least N.
fn resimulated(s: &Setup, tr: &Coefficients, cap: &MarginCap) -> String {
    let mut c = tr.clone();
    for a in [3, 4] {
        c.c[a] = cap.tilts.c[a].clone();
    }
    let motion = Motion::Signals(c.to_signals());
    let f = Field::compute(&motion, &s.coarse, FieldKind::Velocity, &s.settings, &|| {});
    let r = realised(&f, &s.target_values);
    let least = kinematic_least_normal(&motion, &s.region, &s.settings);
    format!(
        "re-simulated 7 × 7: ŝ {:.4} s⁻¹ at shape {:.1} % ({} invalid), least N {:.2} m/s² (margin {:.2})",
        r.strength,
        100.0 * r.shape_error,
        r.invalid,
        least,
        s.limits.contact_margin * s.settings.gravity,
    )
}

/// The saddle's setup: its sequenced schedule's limits (harmonics 1 and 2)
/// and the closed-form seed's strength.
fn setup(cache: &Path) -> Result<(Setup, f64)> {
    let target = Target::load(Path::new("targets/saddle.json"))?;
    let schedule = sequenced(&target, cache)?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, 2)?;
    let region = square(21);
    let seeded = seed(
        &target.field,
        &region,
        &limits,
        settings.friction,
        settings.gravity,
    )?;
    let coarse = square(7);
    let target_values = coarse
        .points()
        .iter()
        .map(|p| target.field.eval(*p))
        .collect();
    let m = AffineFit::of(&target.field, &region).m;
    let s = Setup {
        settings,
        limits,
        region,
        coarse,
        target_values,
        m,
    };
    Ok((s, seeded.strength))
}

/// The table of one row per group: its best cap, the ratio to the
/// circle's, the phases that reach it, what the tilts' harmonic 2 adds at
/// most, the best one's drift.
fn group_table(scanned: &[(Candidate, Capped)], circle: f64) -> Table {
    let mut table = Table::new([
        "translation",
        "best cap (s⁻¹)",
        "× the circle's",
        "reached by",
        "tilts' harmonic 2 adds at most (s⁻¹)",
        "its drift (m/s)",
    ]);
    let mut groups: Vec<&str> = Vec::new();
    for (c, _) in scanned {
        if !groups.contains(&c.group.as_str()) {
            groups.push(&c.group);
        }
    }
    for g in groups {
        let members = scanned.iter().filter(|(c, _)| c.group == g);
        let gain = members
            .clone()
            .map(|(_, k)| k.cap.strength - k.harmonic_1)
            .fold(f64::NEG_INFINITY, f64::max);
        let best = members.max_by(|a, b| a.1.cap.strength.total_cmp(&b.1.cap.strength));
        if let Some((c, k)) = best {
            table.row([
                g.to_string(),
                format!("{:.4}", k.cap.strength),
                format!("{:.3}", k.cap.strength / circle),
                c.label.clone(),
                format!("{gain:.4}"),
                format!("({:+.5}, {:+.5})", k.drift[0], k.drift[1]),
            ]);
        }
    }
    table
}

/// The section of `probes.md`.
pub(crate) fn section(cache: &Path) -> Result<String> {
    let (s, seed_strength) = setup(cache)?;
    let mut scanned = Vec::new();
    let mut failed = Vec::new();
    for c in candidates(&s.limits) {
        match caps(&s, &c.translation) {
            Some(k) => scanned.push((c, k)),
            None => failed.push(c.label),
        }
    }
    let circle = match scanned.first() {
        Some((c, k)) if c.group == "circle" => k.cap.strength,
        _ => return Err(Error::NotConverged("the circle's margin cap".into())),
    };
    let gain = scanned
        .iter()
        .map(|(_, k)| k.cap.strength - k.harmonic_1)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut md = format!(
        "\n## The saddle's margin cap against a translation harmonic 2\n\n\
         `targets/saddle.json` under its sequenced schedule's limits (harmonics 1 and 2, contact \
         margin 0.1 g): {} translations scanned, {} without a steady state or a solution{}. \
         The circle's cap {circle:.4} s⁻¹ (the closed-form seed's strength {seed_strength:.4}); \
         over all translations the tilts' harmonic 2 adds at most {gain:.4} s⁻¹.\n\n",
        scanned.len() + failed.len(),
        failed.len(),
        if failed.is_empty() {
            String::new()
        } else {
            format!(" ({})", failed.join("; "))
        }
    );
    md.push_str(&group_table(&scanned, circle).markdown());
    md.push_str("\nThe circle and the four best, with the programme's tilts:\n\n");
    let _ = writeln!(
        md,
        "- circle: {}",
        resimulated(&s, &scanned[0].0.translation, &scanned[0].1.cap)
    );
    scanned.sort_by(|a, b| b.1.cap.strength.total_cmp(&a.1.cap.strength));
    for (c, k) in scanned.iter().take(4) {
        let _ = writeln!(
            md,
            "- {}: cap {:.4} = {:.3} × the circle's; {}",
            c.label,
            k.cap.strength,
            k.cap.strength / circle,
            resimulated(&s, &c.translation, &k.cap)
        );
    }
    Ok(md)
}
