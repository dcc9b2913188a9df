//! The contact margin's cap on an affine target's strength for a given
//! in-plane translation, measured by simulated linear response and a linear
//! programme (the derivation it tests is in the [module documentation](super),
//! "Why a second harmonic does not lift the margin's cap").
//!
//! **Linear response.** For a fixed translation (the in-plane signals of
//! `translation`, any harmonics), each tilt coefficient j — α_x or α_y,
//! harmonic 1..=H, the sin or the cos slot of [`super::params`] — is set
//! alone to `PROBE_TILT` rad/s², and the steady-state velocity of a part
//! is simulated at the four points ±h on x and on y from the region's
//! centre (h = `PROBE_OFFSET` of the region's half-width and
//! half-height). The central differences give r_j, the velocity gradient
//! [∂v_x/∂x, ∂v_x/∂y, ∂v_y/∂x, ∂v_y/∂y] per rad/s² of coefficient j. This
//! is the simulator's own first-order answer: the slip direction ê(t) the
//! translation makes (uniform or not), the slip speed, the part's
//! velocity modulation and every model term are in it; only the
//! nonlinearity of large tilts is not (at the margin the realised
//! gradient falls somewhat short of it on the saddle).
//!
//! **The programme.** Maximise k over the tilt coefficients c subject to
//!
//! ```text
//! Σ_j c_j r_j = k (M₁₁, M₁₂, M₂₁, M₂₂)             (the target's gradient)
//! |α_x(t) y_c − α_y(t) x_c| ≤ (1 − m) g           (every corner c of the region)
//! |α_x(t)| ≤ limit, |α_y(t)| ≤ limit              (the tilt peaks)
//! ```
//!
//! at `TIMES` instants of the period, with α(t) = Σ_h c sin(hωt) +
//! s cos(hωt) linear in c: the corner rows are N − g at the corners
//! without a_z ([`super::seed`]'s margin check). Solved with Clarabel
//! (zero and non-negative cones). k is then the largest strength the
//! margin and the peaks allow that translation to first order in the
//! tilts, with the tilts' harmonics 1..=`harmonics` all free.

use std::f64::consts::PI;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use super::limits::ShakerLimits;
use super::params::Coefficients;
use crate::field::{FieldSettings, Grid};
use crate::motion::Motion;

/// Tilt amplitude of one linear-response probe (rad/s²): small against the
/// ≈ 150 rad/s² at the margin, large against the simulator's tolerances.
pub(crate) const PROBE_TILT: f64 = 20.0;
/// Probe points' offset from the centre, as a fraction of the region's
/// half-width (x) and half-height (y).
pub(crate) const PROBE_OFFSET: f64 = 0.5;
/// Instants per period of the programme's margin and peak rows.
pub(crate) const TIMES: usize = 256;

/// Largest constraint violation accepted in a programme's solution,
/// relative to its right-hand sides' scale (Clarabel's default tolerances
/// are 1e-8).
pub(crate) const FEASIBILITY: f64 = 1e-6;

/// Signal indices of the tilts α_x, α_y ([`super::params::AXIS_NAMES`]).
const TILTS: [usize; 2] = [3, 4];

/// One tilt coefficient: signal index, harmonic index (0 = harmonic 1),
/// slot (0: the sin coefficient c, 1: the cos coefficient s).
pub(crate) type TiltSlot = (usize, usize, usize);

/// The tilt coefficients of `harmonics` harmonics, in a fixed order.
pub(crate) fn tilt_slots(harmonics: usize) -> Vec<TiltSlot> {
    let mut out = Vec::with_capacity(4 * harmonics);
    for a in TILTS {
        for h in 0..harmonics {
            for slot in 0..2 {
                out.push((a, h, slot));
            }
        }
    }
    out
}

/// The simulated linear response of a translation (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct TiltResponse {
    /// The coefficients probed.
    pub slots: Vec<TiltSlot>,
    /// Per slot, the velocity gradient per rad/s².
    pub gradient: Vec<[f64; 4]>,
    /// Steady drift at the centre of the translation alone (m/s): the
    /// ratchet a second harmonic makes.
    pub drift: [f64; 2],
}

/// The linear response of `translation` (its tilts are replaced; its
/// in-plane and other signals kept) over `region`, tilts of `harmonics`
/// harmonics; `None` when a probe has no steady state.
pub fn tilt_response(
    translation: &Coefficients,
    region: &Grid,
    settings: &FieldSettings,
    harmonics: usize,
) -> Option<TiltResponse> {
    let mut base = translation.clone();
    for a in TILTS {
        base.c[a].iter_mut().for_each(|cs| *cs = [0.0; 2]);
    }
    let centre = [
        0.5 * (region.x[0] + region.x[1]),
        0.5 * (region.y[0] + region.y[1]),
    ];
    let h = [
        PROBE_OFFSET * 0.5 * (region.x[1] - region.x[0]),
        PROBE_OFFSET * 0.5 * (region.y[1] - region.y[0]),
    ];
    let m0 = Motion::Signals(base.to_signals());
    let drift = settings.simulator(&m0).steady_state(centre).ok()?.velocity;
    let slots = tilt_slots(harmonics.min(base.harmonics()));
    let mut gradient = Vec::with_capacity(slots.len());
    for &(a, k, slot) in &slots {
        let mut c = base.clone();
        c.c[a][k][slot] = PROBE_TILT;
        let m = Motion::Signals(c.to_signals());
        let sim = settings.simulator(&m);
        let v = |dx: f64, dy: f64| {
            sim.steady_state([centre[0] + dx, centre[1] + dy])
                .ok()
                .map(|s| s.velocity)
        };
        let (xp, xm) = (v(h[0], 0.0)?, v(-h[0], 0.0)?);
        let (yp, ym) = (v(0.0, h[1])?, v(0.0, -h[1])?);
        let (dx, dy) = (2.0 * h[0] * PROBE_TILT, 2.0 * h[1] * PROBE_TILT);
        gradient.push([
            (xp[0] - xm[0]) / dx,
            (yp[0] - ym[0]) / dy,
            (xp[1] - xm[1]) / dx,
            (yp[1] - ym[1]) / dy,
        ]);
    }
    Some(TiltResponse {
        slots,
        gradient,
        drift,
    })
}

/// The programme's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct MarginCap {
    /// Largest strength k (first order in the tilts).
    pub strength: f64,
    /// The tilts that realise it (other signals zero).
    pub tilts: Coefficients,
}

/// The largest strength of the gradient `m` (`m[i][j]` = ∂f_i/∂q_j) that
/// `response`'s translation reaches under `limits`' tilt peaks and contact
/// margin over `region`, with tilt harmonics above `harmonics` held at
/// zero; `None` when the solver fails.
pub fn margin_cap(
    response: &TiltResponse,
    m: [[f64; 2]; 2],
    limits: &ShakerLimits,
    region: &Grid,
    gravity: f64,
    harmonics: usize,
) -> Option<MarginCap> {
    let nb = response.slots.len();
    let kcol = nb;
    let mut rows = Rows::default();
    let target = [m[0][0], m[0][1], m[1][0], m[1][1]];
    for (i, t) in target.iter().enumerate() {
        let mut e: Vec<(usize, f64)> = (0..nb).map(|j| (j, response.gradient[j][i])).collect();
        e.push((kcol, -t));
        rows.push(&e, 0.0);
    }
    for (j, &(_, h, _)) in response.slots.iter().enumerate() {
        if h >= harmonics {
            rows.push(&[(j, 1.0)], 0.0);
        }
    }
    let zero_rows = rows.b.len();
    let room = (1.0 - limits.contact_margin) * gravity;
    let corners = [
        [region.x[0], region.y[0]],
        [region.x[1], region.y[0]],
        [region.x[0], region.y[1]],
        [region.x[1], region.y[1]],
    ];
    let lim = limits.axes();
    let w = 2.0 * PI / limits.period;
    for i in 0..TIMES {
        let t = limits.period * i as f64 / TIMES as f64;
        // Basis value of slot j at t, on its own axis.
        let value = |j: usize| {
            let (_, h, slot) = response.slots[j];
            let p = w * (h + 1) as f64 * t;
            if slot == 0 {
                p.sin()
            } else {
                p.cos()
            }
        };
        for sign in [-1.0, 1.0] {
            // N − g at corner q: α_x y − α_y x.
            for q in &corners {
                let e: Vec<(usize, f64)> = (0..nb)
                    .map(|j| {
                        let along = if response.slots[j].0 == TILTS[0] {
                            q[1]
                        } else {
                            -q[0]
                        };
                        (j, sign * along * value(j))
                    })
                    .collect();
                rows.push(&e, room);
            }
            for a in TILTS {
                let e: Vec<(usize, f64)> = (0..nb)
                    .filter(|&j| response.slots[j].0 == a)
                    .map(|j| (j, sign * value(j)))
                    .collect();
                rows.push(&e, lim[a]);
            }
        }
    }
    let n = nb + 1;
    let nrows = rows.b.len();
    let a = CscMatrix::new_from_triplets(
        nrows,
        n,
        rows.ri.clone(),
        rows.ci.clone(),
        rows.vals.clone(),
    );
    let p = CscMatrix::zeros((n, n));
    let mut q = vec![0.0; n];
    q[kcol] = -1.0;
    let cones = [
        SupportedConeT::ZeroConeT(zero_rows),
        SupportedConeT::NonnegativeConeT(nrows - zero_rows),
    ];
    let settings = DefaultSettings {
        verbose: false,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&p, &q, &a, &rows.b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) {
        return None;
    }
    // Clarabel's answer checked on the rows themselves: equalities and
    // inequalities within FEASIBILITY of the right-hand sides' scale.
    let scale = TILTS.iter().fold(room, |s, &a| s.max(lim[a]));
    if rows.violation(&sol.x, zero_rows) > FEASIBILITY * (1.0 + scale) {
        return None;
    }
    let mut tilts = Coefficients::zero(limits.period, limits.harmonics);
    for (j, &(a, h, slot)) in response.slots.iter().enumerate() {
        if let Some(cs) = tilts.c[a].get_mut(h) {
            cs[slot] = sol.x[j];
        }
    }
    Some(MarginCap {
        strength: sol.x[kcol],
        tilts,
    })
}

/// Sparse rows `Σ vals·x[cols] + s = b`, assembled in order.
#[derive(Default)]
struct Rows {
    ri: Vec<usize>,
    ci: Vec<usize>,
    vals: Vec<f64>,
    b: Vec<f64>,
}

impl Rows {
    /// The largest violation at `x` of the first `zero_rows` rows as
    /// equalities (|a·x − b|) and of the rest as a·x ≤ b.
    fn violation(&self, x: &[f64], zero_rows: usize) -> f64 {
        let mut ax = vec![0.0; self.b.len()];
        for ((&r, &c), &v) in self.ri.iter().zip(&self.ci).zip(&self.vals) {
            ax[r] += v * x[c];
        }
        ax.iter()
            .zip(&self.b)
            .enumerate()
            .map(|(r, (a, b))| {
                if r < zero_rows {
                    (a - b).abs()
                } else {
                    (a - b).max(0.0)
                }
            })
            .fold(0.0, f64::max)
    }

    fn push(&mut self, entries: &[(usize, f64)], b: f64) {
        let row = self.b.len();
        for &(j, v) in entries {
            if v != 0.0 {
                self.ri.push(row);
                self.ci.push(j);
                self.vals.push(v);
            }
        }
        self.b.push(b);
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use super::*;
    use crate::request::FieldSpec;
    use crate::synth::seed::{seed, AffineFit};

    /// The saddle row's limits in `results/synthesis.md` (the sequenced
    /// schedule's peaks, 2 harmonics, margin 0.1 g).
    fn saddle_limits() -> ShakerLimits {
        ShakerLimits {
            period: 0.030_063,
            linear: [10.920, 10.920, 0.109],
            angular: [218.4, 218.4, 0.0],
            harmonics: 2,
            ..ShakerLimits::lab_class()
        }
    }

    /// The circle at the x/y limits with (when `h2` > 0) its harmonic 1
    /// cut to (1 − `h2`) of the limit and a harmonic 2 of `h2` on x at
    /// phase `px` and on y at phase `py`, each axis scaled onto its limit.
    fn translation(l: &ShakerLimits, h2: f64, px: f64, py: f64) -> Coefficients {
        let a = l.linear[0];
        let mut c = Coefficients::zero(l.period, l.harmonics);
        c.set(0, 1, a * (1.0 - h2), FRAC_PI_2);
        c.set(1, 1, a * (1.0 - h2), 0.0);
        for (axis, phase) in [(0, px), (1, py)] {
            if h2 > 0.0 {
                c.set(axis, 2, a * h2, phase);
            }
            let p = c.peak(axis);
            c.c[axis]
                .iter_mut()
                .for_each(|cs| *cs = [cs[0] * a / p, cs[1] * a / p]);
        }
        c
    }

    /// The saddle's margin cap (module docs of `synth`, "Why a second
    /// harmonic does not lift the margin's cap"): for the seed's circle the
    /// programme's cap is the closed-form seed's strength within 2 % and
    /// the tilts' harmonic 2 adds < 0.5 %; no translation with a harmonic 2
    /// of 10 % of the limit (on x, on y, or a circle at 2ω either way, the
    /// ratchet-free choice) comes within 1 % of the circle's cap
    /// (`platefield study probes` scans more: the best is 0.997 of it); and the
    /// programme's tilts keep the peaks.
    #[test]
    fn second_harmonic_translation_does_not_lift_the_saddle_cap() {
        let l = saddle_limits();
        let settings = FieldSettings::default();
        let region = Grid {
            x: [-0.04, 0.04],
            y: [-0.04, 0.04],
            n: [21, 21],
        };
        let field = FieldSpec::Saddle {
            center: [0.0, 0.0],
            strength: 1.0,
            angle: 0.0,
        };
        let m = AffineFit::of(&field, &region).m;
        let g = settings.gravity;
        let cap = |c: &Coefficients, h: usize| {
            let r = tilt_response(c, &region, &settings, 2).expect("steady states");
            margin_cap(&r, m, &l, &region, g, h).expect("a solution")
        };
        let closed_form = seed(&field, &region, &l, settings.friction, g)
            .expect("a seed")
            .strength;
        let circle = translation(&l, 0.0, 0.0, 0.0);
        let k0 = cap(&circle, 2);
        let k1 = cap(&circle, 1).strength;
        assert!(
            (k0.strength / closed_form - 1.0).abs() < 0.02,
            "circle's cap {} against the closed form {closed_form}",
            k0.strength
        );
        assert!(k0.strength < 1.005 * k1, "{} against {k1}", k0.strength);
        for a in [3, 4] {
            assert!(k0.tilts.peak(a) <= l.angular[a - 3] * (1.0 + 1e-6));
        }
        let q = std::f64::consts::FRAC_PI_4;
        for (px, py) in [(0.0, 0.0), (2.0 * q, 2.0 * q), (q, 3.0 * q), (3.0 * q, q)] {
            let k = cap(&translation(&l, 0.1, px, py), 2).strength;
            assert!(
                k < 0.99 * k0.strength,
                "phases {px} {py}: cap {k} against the circle's {}",
                k0.strength
            );
        }
    }
}
