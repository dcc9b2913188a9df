//! The refinement objective: one re-simulation of a candidate motion.
//!
//! A parameter vector (`params::Layout`) becomes coefficients,
//! each axis scaled down onto its limit where its summed peak exceeds it
//! (so every simulated motion is within the limits), and the steady-state
//! velocity field R of the motion is computed on the coarse grid
//! ([`Field::compute`]). Against the target t at the same points:
//!
//! ```text
//! realised strength ŝ = ⟨R, t⟩ / ⟨t, t⟩,   shape error e = ‖R − ŝ t‖ / ‖ŝ t‖
//! cost = −ŝ / s_ref                                   (maximise strength)
//!      + 20 · max(0, e − budget)                      (shape first)
//!      + 1 · Σ_axes max(0, peak/limit − 1)            (excess clamped away)
//!      + 100 · max(0, m + 0.01 − N_min/g)             (contact margin, MARGIN_SAFETY kept)
//!      + 10 · (invalid samples / samples)             (contact lost, not converged)
//! ```
//!
//! s_ref is the seed's predicted strength, so the strength term is of order
//! one; a shape error 5 points over budget costs as much as the whole
//! strength. e is capped at 10 (ŝ ≤ 0 makes it infinite). N_min is the
//! smaller of `kinematic_least_normal` and `orbit_least_normal` over
//! the coarse grid (the same check the final full-grid result gets); its
//! weight makes a 1 % of g violation cost as much as the whole strength.
//!
//! **Residuals** (what `super::least_squares` minimises, ½‖r‖²): the
//! cost's terms as a sum of squares, with s_g the strength scale
//! (`Objective::with_goal`, s_ref by default) and a = `STRENGTH_REACH`:
//!
//! ```text
//! r = ( 20 · e · (R_i − ŝ t_i)/‖R − ŝ t‖   for every coarse point i,
//!       a − ŝ/s_g,
//!       excess,  10 · max(0, m + 0.01 − N_min/g),  √10 · √(invalid / samples) )
//! ```
//!
//! **The shape block steers by the whole shape error**: its
//! norm is 20 e, its direction the residual field (where the shape is
//! wrong), below the budget as well as above it (`shape_block` with
//! budget 0). The budget is the cost's: the search keeps the evaluation of
//! least *cost*, so the residuals steer it and the cost judges it. With
//! the cost's hinge 20 · max(0, e − budget) as the block, the
//! linearisation would see no shape inside the budget: the first
//! Gauss–Newton step goes for strength alone and leaves the budget far
//! behind (with the hinge block, line_sink_30's first step lands far over
//! the budget, is rejected and the run creeps on at a large damping;
//! squeeze_trans leaves the budget along its whole path and the cost keeps
//! a point next to the start), and just over the
//! budget the square ½ (20 (e − budget))² is flat where the cost's hinge
//! is steep. Always on, the block's square ½ (20 e)² makes
//! the run a balance of shape against strength whose rate it sees at every
//! step: Gauss–Newton rests where 400 e ∂e = (a − ŝ/s_g)/s_g ∂ŝ. The
//! strength row asks for up to a = 4 times the strength scale, so that
//! balance sits near the cost's budget rather than below it (by the
//! played check of `design --method auto` on line_sink_30 and
//! squeeze_trans, a = 2 leaves strength unclaimed well inside the budget
//! and a = 6 over-reaches).
//! The strength scale s_g that [`crate::synth::synthesize`] gives is the
//! realised coarse strength of the start the run begins from (the
//! polish's s₀ is its start's played strength alike), not the seed's
//! predicted one: a start that realises less than its nominal strength,
//! as squeeze_trans's transport start does, would otherwise give the row a
//! smaller slope than the cost's, and the played result is then both
//! weaker and further from the shape. With a = 1 the row would be zero at the seed's strength and
//! pull any stronger motion back to it. Under
//! several physics each adds its own first block.

use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::contact::{kinematic_least_normal, orbit_least_normal};
use super::limits::ShakerLimits;
use super::params::{Coefficients, Layout};
use super::progress::SynthesisProgress;
use super::robust::judged_under;
use super::stall::{StallRule, StallTracker};
use crate::field::{Field, FieldKind, FieldSettings, Grid, Validity};
use crate::motion::Motion;
use crate::request::FieldSpec;
use crate::scene::FrictionSpec;

/// Weight of the shape error over budget.
pub(crate) const SHAPE_WEIGHT: f64 = 20.0;
/// The strength row a − ŝ/s_g of the residuals asks for up to a = 4 times
/// the strength scale (module documentation: against the always-on shape
/// block, Gauss–Newton's balance of shape and strength then sits near the
/// cost's shape budget).
pub(crate) const STRENGTH_REACH: f64 = 4.0;
/// Weight of the relative peak excess.
pub(crate) const LIMIT_WEIGHT: f64 = 1.0;
/// Weight of the contact-margin violation (fraction of g).
pub(crate) const CONTACT_WEIGHT: f64 = 100.0;
/// Weight of the fraction of invalid samples.
pub(crate) const INVALID_WEIGHT: f64 = 10.0;
/// Cap on the shape error inside the cost.
const SHAPE_CAP: f64 = 10.0;
/// Extra contact margin (fraction of g) the coarse objective keeps: it sees
/// the steady orbits at its own points only, and the full grid's least N
/// can come out lower (the lab sink refined by least squares to the coarse
/// margin: 0.0982 g on the full 21 × 21 grid against 0.1 g on 7 × 7).
pub const MARGIN_SAFETY: f64 = 0.01;

/// Realised strength and shape error of a field against target vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Realised {
    /// ŝ = ⟨R, t⟩/⟨t, t⟩ over valid samples.
    pub strength: f64,
    /// ‖R − ŝ t‖/‖ŝ t‖ (infinite when ŝ ≤ 0).
    pub shape_error: f64,
    /// Samples that are not [`Validity::Ok`].
    pub invalid: usize,
    /// Angle (rad, counter-clockwise) of the rotation that best takes the
    /// target onto R: atan2(Σ t × r, Σ t · r) over valid samples (0 when
    /// undefined).
    pub turn: f64,
}

impl Realised {
    /// The worst case of one motion's measures under several physics
    /// ([`super::robust`]): the weakest strength, the largest shape error
    /// and invalid count, and the mean turn (what a phase calibration
    /// removes: centred, the turns at the range's ends are balanced).
    /// `None` for no measures.
    pub(crate) fn worst_of(all: &[Realised]) -> Option<Realised> {
        let first = all.first()?;
        Some(Realised {
            strength: all
                .iter()
                .map(|r| r.strength)
                .fold(first.strength, f64::min),
            shape_error: all
                .iter()
                .map(|r| r.shape_error)
                .fold(first.shape_error, f64::max),
            invalid: all.iter().map(|r| r.invalid).max().unwrap_or(first.invalid),
            turn: all.iter().map(|r| r.turn).sum::<f64>() / all.len() as f64,
        })
    }
}

/// Realised strength and shape error of `field` against `target` (one
/// vector per grid point, grid order).
pub fn realised(field: &Field, target: &[[f64; 2]]) -> Realised {
    let (mut rt, mut tt, mut rr, mut cross) = (0.0, 0.0, 0.0, 0.0);
    let mut invalid = 0;
    for ((r, t), v) in field.vectors.iter().zip(target).zip(&field.validity) {
        if *v != Validity::Ok {
            invalid += 1;
            continue;
        }
        rt += r[0] * t[0] + r[1] * t[1];
        tt += t[0] * t[0] + t[1] * t[1];
        rr += r[0] * r[0] + r[1] * r[1];
        cross += t[0] * r[1] - t[1] * r[0];
    }
    let s = if tt > 0.0 { rt / tt } else { 0.0 };
    // ‖R − s t‖² = rr − 2 s rt + s² tt = rr − s rt at the least-squares s.
    let shape_error = if s > 0.0 {
        ((rr - s * rt).max(0.0) / (s * s * tt)).sqrt()
    } else {
        f64::INFINITY
    };
    Realised {
        strength: s,
        shape_error,
        invalid,
        turn: if rt == 0.0 && cross == 0.0 {
            0.0
        } else {
            cross.atan2(rt)
        },
    }
}

/// A residual field `raw` (components in order) rescaled to the norm
/// 20 · max(0, e − budget) of the cost's shape term (its direction kept):
/// the played polish's block ([`crate::design::polish`]); with budget 0,
/// 20 e, the synthesis's (the module documentation). A non-finite `e` (no
/// positive strength) counts as the cost's cap.
pub(crate) fn shape_block(raw: &[f64], e: f64, budget: f64) -> Vec<f64> {
    let e = if e.is_finite() {
        e.min(SHAPE_CAP)
    } else {
        SHAPE_CAP
    };
    let over = SHAPE_WEIGHT * (e - budget).max(0.0);
    let norm = raw.iter().map(|v| v * v).sum::<f64>().sqrt();
    if over == 0.0 || norm == 0.0 {
        return vec![
            if norm == 0.0 {
                over / (raw.len().max(1) as f64).sqrt()
            } else {
                0.0
            };
            raw.len()
        ];
    }
    raw.iter().map(|v| v * over / norm).collect()
}

/// One evaluated candidate.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Evaluation {
    /// The parameter vector.
    pub params: Vec<f64>,
    /// Cost (see the module docs).
    pub cost: f64,
    /// Realised strength and shape error on the coarse grid.
    pub realised: Realised,
    /// Least N over the coarse grid (m/s²).
    pub least_normal: f64,
    /// The residual vector (module documentation).
    pub residuals: Vec<f64>,
}

/// Budget state shared by all evaluations of one synthesis.
#[derive(Debug)]
struct Tally {
    evaluations: usize,
    best: Option<Evaluation>,
    stall: StallTracker,
}

/// The coarse-grid objective (driven by argmin through [`super::multistart`]).
pub(crate) struct Objective<'a> {
    layout: Layout,
    limits: &'a ShakerLimits,
    settings: &'a FieldSettings,
    grid: Grid,
    target: Vec<[f64; 2]>,
    shape_budget: f64,
    strength_ref: f64,
    goal: f64,
    max_evaluations: usize,
    deadline: Option<Instant>,
    stall: Option<StallRule>,
    /// The physics each candidate is judged under (worst case over them):
    /// `settings` alone unless [`Objective::with_robust`] gave a range.
    physics: Vec<FieldSettings>,
    /// Per physics, its own target (sorting, [`Objective::with_classes`]);
    /// empty: `target` under every physics.
    class_targets: Vec<Vec<[f64; 2]>>,
    tally: Mutex<Tally>,
    progress: &'a SynthesisProgress,
}

impl<'a> Objective<'a> {
    /// The objective for `field` on `grid`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        field: &FieldSpec,
        grid: Grid,
        limits: &'a ShakerLimits,
        settings: &'a FieldSettings,
        shape_budget: f64,
        strength_ref: f64,
        max_evaluations: usize,
        deadline: Option<Instant>,
        progress: &'a SynthesisProgress,
    ) -> Objective<'a> {
        Objective {
            layout: Layout::new(limits),
            limits,
            settings,
            target: grid.points().iter().map(|p| field.eval(*p)).collect(),
            grid,
            shape_budget,
            strength_ref: strength_ref.max(1e-12),
            goal: strength_ref.max(1e-12),
            max_evaluations,
            deadline,
            stall: None,
            physics: vec![*settings],
            class_targets: Vec::new(),
            tally: Mutex::new(Tally {
                evaluations: 0,
                best: None,
                stall: StallTracker::default(),
            }),
            progress,
        }
    }

    /// The objective for `field` on `grid` without a budget or deadline and
    /// with strength scale 1: a yardstick that evaluates motions for a
    /// caller's own search (the played polish, the turned mirror).
    pub(crate) fn unbounded(
        field: &FieldSpec,
        grid: Grid,
        limits: &'a ShakerLimits,
        settings: &'a FieldSettings,
        shape_budget: f64,
        progress: &'a SynthesisProgress,
    ) -> Objective<'a> {
        Objective::new(
            field,
            grid,
            limits,
            settings,
            shape_budget,
            1.0,
            usize::MAX,
            None,
            progress,
        )
    }

    /// This objective with residuals against the strength scale `goal`
    /// (s_g of the module documentation; default the cost's strength
    /// scale).
    pub(crate) fn with_goal(mut self, goal: f64) -> Self {
        self.goal = goal.max(1e-12);
        self
    }

    /// This objective, also spent once `rule` says its best cost has
    /// stopped improving ([`super::stall`]).
    pub(crate) fn with_stall(mut self, rule: Option<StallRule>) -> Self {
        self.stall = rule;
        self
    }

    /// This objective judging every candidate by its worst case over the
    /// friction range `spec` ([`super::robust`]); `None` or an exact
    /// friction keeps the settings' own.
    pub(crate) fn with_robust(mut self, spec: Option<FrictionSpec>) -> Self {
        self.physics = judged_under(self.settings, spec);
        self
    }

    /// This objective judging every candidate by its worst case over part
    /// classes, each class's own field under its own physics (sorting by
    /// friction, [`crate::design::sort`]): `classes` replaces the physics
    /// and the target (empty: unchanged). The cost and the residuals are
    /// the robust objective's with the class's target in each physics'
    /// block: the weakest class's strength, the worst class's shape, the
    /// contact margin at every class's friction.
    pub(crate) fn with_classes(mut self, classes: &[(FieldSpec, FieldSettings)]) -> Self {
        if classes.is_empty() {
            return self;
        }
        let points = self.grid.points();
        self.physics = classes.iter().map(|c| c.1).collect();
        self.class_targets = classes
            .iter()
            .map(|(f, _)| points.iter().map(|p| f.eval(*p)).collect())
            .collect();
        self
    }

    /// The target under the `k`-th physics.
    fn target_of(&self, k: usize) -> &[[f64; 2]] {
        self.class_targets.get(k).unwrap_or(&self.target)
    }

    /// The physics each candidate is judged under.
    pub(crate) fn physics(&self) -> &[FieldSettings] {
        &self.physics
    }

    /// Counts the stall window from now (a search's start: what came
    /// before, such as the calibration, does not use it up).
    pub(crate) fn restart_stall(&self) {
        self.tally
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .stall
            .restart();
    }

    /// The parameter layout.
    pub(crate) fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The motion a parameter vector stands for (clamped onto the limits)
    /// and its relative peak excess before clamping.
    pub(crate) fn motion(&self, params: &[f64]) -> (Coefficients, f64) {
        let mut c = self.layout.from_vec(params);
        let excess = c.clamp(self.limits);
        (c, excess)
    }

    /// Evaluates `params` (counts against the budget).
    pub(crate) fn evaluate(&self, params: &[f64]) -> Evaluation {
        let e = self.measure(params);
        self.record(&e);
        e
    }

    /// Evaluates every point of `points` in parallel (rayon) and records
    /// them in their order, so the budget, the best and the stall rule see
    /// the same sequence on any number of threads.
    pub(crate) fn evaluate_batch(&self, points: &[Vec<f64>]) -> Vec<Evaluation> {
        let all: Vec<Evaluation> = points.par_iter().map(|p| self.measure(p)).collect();
        for e in &all {
            self.record(e);
        }
        all
    }

    /// The evaluation of `params` without counting it (pure: callable from
    /// several threads).
    pub(crate) fn measure(&self, params: &[f64]) -> Evaluation {
        let (c, excess) = self.motion(params);
        let motion = Motion::Signals(c.to_signals());
        let mut each = Vec::with_capacity(self.physics.len());
        let mut least_normal = f64::INFINITY;
        let mut residuals = Vec::new();
        for (k, settings) in self.physics.iter().enumerate() {
            let field = Field::compute(&motion, &self.grid, FieldKind::Velocity, settings, &|| {});
            let target = self.target_of(k);
            let r = realised(&field, target);
            residuals.extend(self.shape_residuals(&field, &r, target));
            each.push(r);
            least_normal = least_normal.min(
                kinematic_least_normal(&motion, &self.grid, settings)
                    .min(orbit_least_normal(&motion, &self.grid, settings)),
            );
        }
        let r = Realised::worst_of(&each).expect("judged_under never returns an empty set");
        let margin = self.margin_violation(least_normal);
        let cost = -r.strength / self.strength_ref
            + SHAPE_WEIGHT * (r.shape_error.min(SHAPE_CAP) - self.shape_budget).max(0.0)
            + LIMIT_WEIGHT * excess
            + CONTACT_WEIGHT * margin
            + INVALID_WEIGHT * r.invalid as f64 / self.grid.len() as f64;
        residuals.extend([
            STRENGTH_REACH - r.strength / self.goal,
            LIMIT_WEIGHT.sqrt() * excess,
            CONTACT_WEIGHT.sqrt() * margin,
            (INVALID_WEIGHT * r.invalid as f64 / self.grid.len() as f64).sqrt(),
        ]);
        Evaluation {
            params: params.to_vec(),
            cost,
            realised: r,
            least_normal,
            residuals,
        }
    }

    /// How far `least_normal` (m/s²) falls below the contact margin plus
    /// [`MARGIN_SAFETY`], as a fraction of g (0 when it does not).
    pub(crate) fn margin_violation(&self, least_normal: f64) -> f64 {
        (self.limits.contact_margin + MARGIN_SAFETY - least_normal / self.settings.gravity).max(0.0)
    }

    /// The shape block of the residuals (module documentation) of `field`
    /// measured as `r`.
    fn shape_residuals(&self, field: &Field, r: &Realised, target: &[[f64; 2]]) -> Vec<f64> {
        let s = r.strength;
        let raw: Vec<f64> = field
            .vectors
            .iter()
            .zip(&field.validity)
            .zip(target)
            .flat_map(|((v, ok), t)| {
                if *ok == Validity::Ok {
                    [v[0] - s * t[0], v[1] - s * t[1]]
                } else {
                    [0.0, 0.0]
                }
            })
            .collect();
        shape_block(&raw, r.shape_error, 0.0)
    }

    /// Counts `e` against the budget, the best and the stall rule.
    fn record(&self, e: &Evaluation) {
        let mut tally = self.tally.lock().unwrap_or_else(|p| p.into_inner());
        tally.evaluations += 1;
        tally.stall.record(e.cost, self.stall.as_ref());
        if tally.best.as_ref().is_none_or(|b| e.cost < b.cost) {
            tally.best = Some(e.clone());
        }
        let best = tally.best.as_ref();
        let best = best.map(|b| (b.realised.strength, b.realised.shape_error));
        self.progress.update(tally.evaluations, best);
    }

    /// Evaluations so far.
    pub(crate) fn evaluations(&self) -> usize {
        self.tally
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .evaluations
    }

    /// The best evaluation so far.
    pub(crate) fn best(&self) -> Option<Evaluation> {
        self.tally
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .best
            .clone()
    }

    /// True when the evaluation budget (or the deadline) is spent, or the
    /// stall rule (if any) says the best cost has stopped improving.
    pub(crate) fn spent(&self) -> bool {
        let tally = self.tally.lock().unwrap_or_else(|p| p.into_inner());
        let (evaluations, stalled) = (tally.evaluations, tally.stall.stalled(self.stall.as_ref()));
        drop(tally);
        evaluations >= self.max_evaluations
            || stalled
            || self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Friction;
    use crate::progress::ProgressMode;

    /// Judged over classes, a candidate's measure is the worst class's: the
    /// weakest strength, the largest shape error, and each class's shape
    /// block its own objective's, class after class; one class alone is
    /// that class's plain objective, residual for residual.
    #[test]
    fn classes_measure_is_the_worst_class_s() {
        let grid = Grid {
            x: [-0.02, 0.02],
            y: [-0.01, 0.01],
            n: [3, 3],
        };
        let limits = ShakerLimits::default();
        let at = |mu: f64| FieldSettings {
            friction: Friction::uniform(mu),
            ..FieldSettings::default()
        };
        let (s1, s2) = (at(0.2), at(0.45));
        let f1 = FieldSpec::Sink {
            center: [-0.01, 0.0],
            strength: 1.0,
        };
        let f2 = FieldSpec::Sink {
            center: [0.01, 0.0],
            strength: 1.0,
        };
        let progress = SynthesisProgress::new(ProgressMode::Quiet, 1);
        let o1 = Objective::unbounded(&f1, grid, &limits, &s1, 0.04, &progress);
        let o2 = Objective::unbounded(&f2, grid, &limits, &s2, 0.04, &progress);
        let both = Objective::unbounded(&f1, grid, &limits, &s1, 0.04, &progress)
            .with_classes(&[(f1.clone(), s1), (f2.clone(), s2)]);
        let alone = Objective::unbounded(&f1, grid, &limits, &s1, 0.04, &progress)
            .with_classes(&[(f1.clone(), s1)]);
        // A circular translation (20 m/s²) with tilts: both classes slip.
        let mut c = Coefficients::zero(limits.period, limits.harmonics);
        c.set(0, 1, 20.0, 0.0);
        c.set(1, 1, 20.0, -std::f64::consts::FRAC_PI_2);
        c.set(3, 1, 60.0, 0.0);
        c.set(4, 1, 60.0, -std::f64::consts::FRAC_PI_2);
        let x = o1.layout().to_vec(&c);
        let (e1, e2, e) = (o1.measure(&x), o2.measure(&x), both.measure(&x));
        assert!(e1.realised.strength != e2.realised.strength);
        assert_eq!(
            e.realised.strength,
            e1.realised.strength.min(e2.realised.strength)
        );
        assert_eq!(
            e.realised.shape_error,
            e1.realised.shape_error.max(e2.realised.shape_error)
        );
        let n = 2 * grid.len();
        assert_eq!(e.residuals[..n], e1.residuals[..n]);
        assert_eq!(e.residuals[n..2 * n], e2.residuals[..n]);
        assert_eq!(alone.measure(&x).residuals, e1.residuals);
    }
}
