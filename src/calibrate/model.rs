//! The tracks' model: parts carried by the played motion's steady-state
//! velocity field, segment by segment, as a function of position and of
//! the parameters θ = (μ_k, μ_s − μ_k, amplitude scale).
//!
//! **Motion.** A part at r moves with dr/dt = V_i(r; θ), where i is the
//! schedule segment playing at time t (t modulo the schedule period, t = 0
//! where the first period starts) and V_i the steady-state velocity field
//! of segment i's motion ([`crate::field`], free or frozen by the
//! schedule's model; for a schedule of one motion without joins, played
//! on and on, corrected for the drift lag of a moving part,
//! [`crate::play::lag`]), its amplitudes multiplied by the scale
//! ([`Motion::amplitude_scaled`]); V = 0 during rest. V_i is sampled on a
//! grid over the plate region and interpolated bilinearly; the path is
//! integrated by RK4 in steps of at most [`MAX_STEP`] that end on every
//! segment boundary and every frame.
//!
//! **Within a cycle.** A camera frame catches the part somewhere in its
//! cycle, off its mean path by the periodic orbit's excursion e(φ; r)
//! (a few tenths of a millimetre on the shipped sink, as large as the
//! camera's noise, and aliased by a frame rate near the plate's frequency
//! into a slow wobble). The observed position is modelled as m(t) +
//! e(φ(t); m(t)): m the mean path above (where the part is at phase 0:
//! the steady velocity is its displacement from phase 0 to phase 0), φ the
//! phase within the playing segment's cycle, e the periodic orbit's
//! position less its phase-0 position and the mean drift ([`Excursions`]), sampled at [`PHASES`] phases per grid node and
//! interpolated bilinearly in r and linearly in φ. e is computed at the
//! stencil's centre and used over the stencil. What the model leaves out:
//! the few cycles a part takes to reach the periodic orbit after it is put
//! down and after a join, ramps of a mixed schedule's six-signal segments
//! (played steady here).
//!
//! **Fields over θ.** A [`FieldSet`] holds every segment's field at one θ
//! (computed, one steady state per grid point). A [`Stencil`] holds the
//! sets at θ_c and θ_c ± h_j e_j for the free parameters and evaluates each
//! grid sample as the quadratic in every parameter through those three
//! values (cross terms left out): exact for a field linear in θ, within
//! O(h³) of it along each axis.

use rayon::prelude::*;

use std::sync::Arc;

use crate::dynamics::{Friction, PartState, SteadyFailure, V2};
use crate::error::{Error, Result};
use crate::field::{Field, FieldKind, FieldSettings, Grid, Validity};
use crate::motion::Motion;
use crate::schedule::Schedule;

/// Index of μ_k in θ.
pub const MU_K: usize = 0;
/// Index of μ_s − μ_k (≥ 0) in θ.
pub const EXCESS: usize = 1;
/// Index of the amplitude scale in θ.
pub const SCALE: usize = 2;
/// Parameter names, by index.
pub const NAMES: [&str; 3] = ["mu_k", "mu_s - mu_k", "scale"];

/// Longest RK4 step of a path (s): the fields change over centimetres,
/// parts move at centimetres per second.
pub const MAX_STEP: f64 = 0.02;

/// Phases per cycle at which a periodic orbit's excursion is sampled.
pub const PHASES: usize = 32;

/// θ: [μ_k, μ_s − μ_k, amplitude scale].
pub type Theta = [f64; 3];

/// The friction of θ.
pub(crate) fn friction(theta: &Theta) -> Friction {
    Friction {
        stat: theta[MU_K] + theta[EXCESS],
        kinetic: theta[MU_K],
    }
}

/// The played motion: each segment's steady motion (or rest) and its
/// duration, the region its fields are sampled on, the physics besides
/// friction.
#[derive(Debug, Clone)]
pub(crate) struct PlayedMotion {
    segments: Vec<(Option<Motion>, f64)>,
    /// Segment ends within the period (s), cumulative.
    ends: Vec<f64>,
    period: f64,
    /// Sampling grid of the fields.
    pub grid: Grid,
    /// Gravity, model and numerics (friction replaced by θ's).
    pub settings: FieldSettings,
}

impl PlayedMotion {
    /// The motion of `schedule` (segments of positive duration, each
    /// segment's steady motion), its fields sampled on `grid`.
    ///
    /// # Errors
    /// The schedule is invalid or every segment is rest.
    pub(crate) fn from_schedule(schedule: &Schedule, grid: Grid) -> Result<PlayedMotion> {
        schedule.validate()?;
        let segments: Vec<(Option<Motion>, f64)> = schedule
            .segments
            .iter()
            .filter(|s| s.duration_s > 0.0)
            .map(|s| (s.steady_motion(), s.duration_s))
            .collect();
        if segments.iter().all(|s| s.0.is_none()) {
            return Err(Error::invalid(
                "schedule.segments",
                "every segment is rest: the parts do not move",
            ));
        }
        let ends = segments
            .iter()
            .scan(0.0, |acc, s| {
                *acc += s.1;
                Some(*acc)
            })
            .collect::<Vec<f64>>();
        let period = ends.last().copied().unwrap_or(0.0);
        Ok(PlayedMotion {
            segments,
            ends,
            period,
            grid,
            settings: schedule.settings,
        })
    }

    /// Segments in which the plate moves (a field each).
    pub(crate) fn moving_segments(&self) -> usize {
        self.segments.iter().filter(|s| s.0.is_some()).count()
    }

    /// Schedule period (s).
    pub(crate) fn period(&self) -> f64 {
        self.period
    }

    /// Every segment's field at θ.
    ///
    /// # Errors
    /// A motion cannot be scaled (see [`Motion::amplitude_scaled`]).
    pub(crate) fn fields(&self, theta: &Theta) -> Result<FieldSet> {
        let lagged =
            self.moving_segments() == 1 && self.segments.len() == 1 && self.settings.model.moving;
        let fields = self.per_moving_segment(theta, |m, settings| {
            if lagged {
                lagged_field(m, &self.grid, settings)
            } else {
                Field::compute(m, &self.grid, FieldKind::Velocity, settings, &|| {})
            }
        })?;
        Ok(FieldSet {
            fields,
            excursion: None,
        })
    }

    /// Every segment's field at θ with the periodic orbits' excursions: a
    /// stencil's centre.
    ///
    /// # Errors
    /// As [`PlayedMotion::fields`].
    pub(crate) fn centre(&self, theta: &Theta) -> Result<FieldSet> {
        let mut set = self.fields(theta)?;
        set.excursion = Some(Arc::new(self.excursions(theta)?));
        Ok(set)
    }

    /// `f` of every moving segment's motion scaled by θ, under θ's
    /// friction (`None` for rest).
    fn per_moving_segment<T>(
        &self,
        theta: &Theta,
        f: impl Fn(&Motion, &FieldSettings) -> T,
    ) -> Result<Vec<Option<T>>> {
        let settings = FieldSettings {
            friction: friction(theta),
            ..self.settings
        };
        self.segments
            .iter()
            .map(|(m, _)| {
                m.as_ref()
                    .map(|m| Ok(f(&m.amplitude_scaled(theta[SCALE])?, &settings)))
                    .transpose()
            })
            .collect()
    }

    /// Every moving segment's periodic-orbit excursion at θ on the grid
    /// (a grid node without a steady state has none: zero).
    ///
    /// # Errors
    /// A motion cannot be scaled.
    pub(crate) fn excursions(&self, theta: &Theta) -> Result<Excursions> {
        let points = self.grid.points();
        let per_segment = self.per_moving_segment(theta, |m, settings| {
            let sim = settings.simulator(m);
            points
                .par_iter()
                .map(|&p| orbit_excursion(&sim, p))
                .collect::<Vec<_>>()
        })?;
        Ok(Excursions {
            grid: self.grid,
            per_segment,
            periods: self
                .segments
                .iter()
                .map(|(m, _)| m.as_ref().map_or(0.0, Motion::period))
                .collect(),
        })
    }

    /// The segment playing at time `t` and the time its play ends.
    fn segment_at(&self, t: f64) -> (usize, f64) {
        let k = (t / self.period).floor();
        let base = k * self.period;
        let local = t - base;
        // A boundary reached to round-off belongs to the next segment.
        let eps = 1e-12 * self.period.max(1.0);
        match self.ends.iter().position(|&e| local < e - eps) {
            Some(i) => (i, base + self.ends[i]),
            None => (0, base + self.period + self.ends[0]),
        }
    }

    /// The position at `t1` of a part at `r` at `t0` (t1 ≥ t0).
    ///
    /// # Errors
    /// The path crosses a field sample that is not valid.
    pub(crate) fn advance(
        &self,
        set: &FieldSet,
        mut r: [f64; 2],
        mut t: f64,
        t1: f64,
    ) -> Result<[f64; 2]> {
        while t < t1 {
            let (i, end) = self.segment_at(t);
            let stop = end.min(t1);
            match &set.fields[i] {
                None => t = stop,
                Some(f) => {
                    let n = ((stop - t) / MAX_STEP).ceil().max(1.0);
                    let h = (stop - t) / n;
                    for _ in 0..n as usize {
                        r = rk4(f, r, h)?;
                    }
                    t = stop;
                }
            }
        }
        Ok(r)
    }

    /// Positions at `times` (increasing, the first ≥ `t0`) of a part at
    /// `r` at `t0`.
    ///
    /// # Errors
    /// As [`PlayedMotion::advance`].
    pub(crate) fn path(
        &self,
        set: &FieldSet,
        r: [f64; 2],
        t0: f64,
        times: &[f64],
    ) -> Result<Vec<[f64; 2]>> {
        let (mut r, mut t) = (r, t0);
        times
            .iter()
            .map(|&ti| {
                r = self.advance(set, r, t, ti)?;
                t = ti;
                Ok(match &set.excursion {
                    Some(e) => {
                        let (i, end) = self.segment_at(ti);
                        let start = end - self.segments[i].1;
                        let d = e.at(i, ti - start, r);
                        [r[0] + d[0], r[1] + d[1]]
                    }
                    None => r,
                })
            })
            .collect()
    }
}

/// The drift-lag-corrected steady velocity field of `motion` on `grid`
/// ([`crate::play::lag`]: a part that keeps moving under one motion is not
/// on the fixed point's orbit, and realises up to a few per cent more or
/// less than the steady state there). Samples where the correction fails
/// keep the steady state; those without one are flagged as
/// [`Field::compute`] flags them.
fn lagged_field(motion: &Motion, grid: &Grid, settings: &FieldSettings) -> Field {
    let direct = settings.simulator(motion);
    let table = crate::dynamics::KinematicsTable::cycle(&direct);
    let sim = direct.with_table(&table);
    let samples: Vec<([f64; 2], Validity)> = grid
        .points()
        .par_iter()
        .map(|&p| match sim.steady_state(p) {
            Ok(ss) => {
                let v = crate::play::lag::lagged_velocity_continued(&sim, p, &ss)
                    .unwrap_or(ss.velocity);
                if v[0].is_finite() && v[1].is_finite() {
                    (v, Validity::Ok)
                } else {
                    ([0.0; 2], Validity::NonFinite)
                }
            }
            Err(SteadyFailure::ContactLoss(_)) => ([0.0; 2], Validity::ContactLost),
            Err(SteadyFailure::NotConverged { .. }) => ([0.0; 2], Validity::NotConverged),
        })
        .collect();
    Field {
        grid: *grid,
        kind: FieldKind::Velocity,
        vectors: samples.iter().map(|s| s.0).collect(),
        validity: samples.iter().map(|s| s.1).collect(),
    }
}

/// One RK4 step of dr/dt = V(r) in the field `f`.
fn rk4(f: &Field, r: [f64; 2], h: f64) -> Result<[f64; 2]> {
    let at = |p: [f64; 2], k: [f64; 2], s: f64| [p[0] + s * k[0], p[1] + s * k[1]];
    let k1 = velocity(f, r)?;
    let k2 = velocity(f, at(r, k1, 0.5 * h))?;
    let k3 = velocity(f, at(r, k2, 0.5 * h))?;
    let k4 = velocity(f, at(r, k3, h))?;
    Ok([
        r[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
        r[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
    ])
}

/// The field at `p`, bilinear, `p` held to the grid's region (a path
/// that leaves it carries the edge's velocity).
fn velocity(f: &Field, p: [f64; 2]) -> Result<[f64; 2]> {
    let g = &f.grid;
    let q = [p[0].clamp(g.x[0], g.x[1]), p[1].clamp(g.y[0], g.y[1])];
    f.bilinear(q).map_err(|v| {
        Error::Unreachable(format!(
            "the velocity field near ({:.4}, {:.4}) m is not valid ({v}): the model cannot follow a part there",
            q[0], q[1]
        ))
    })
}

/// The periodic orbit's excursion at grid point `p`: its position at
/// [`PHASES`] phases less its position at phase 0 and less the mean drift
/// V·τ (zero where there is no steady state).
fn orbit_excursion(sim: &crate::dynamics::Simulator<'_>, p: [f64; 2]) -> Vec<[f64; 2]> {
    let zero = vec![[0.0; 2]; PHASES];
    let Ok(s) = sim.steady_state(p) else {
        return zero;
    };
    let r0 = V2::from(p);
    let period = sim.period();
    let mut state = PartState::new(r0, V2::from(s.start_slip));
    let mut rec = Vec::new();
    if sim
        .advance(0.0, period, &mut state, &r0, Some(&mut rec))
        .is_err()
    {
        return zero;
    }
    let mut pts: Vec<(f64, [f64; 2])> = vec![(0.0, [0.0; 2])];
    pts.extend(rec.iter().map(|q| {
        (
            q.t,
            [
                q.state.r.x - p[0] - s.velocity[0] * q.t,
                q.state.r.y - p[1] - s.velocity[1] * q.t,
            ],
        )
    }));
    (0..PHASES)
        .map(|k| {
            let tau = period * k as f64 / PHASES as f64;
            let j = pts
                .partition_point(|q| q.0 <= tau)
                .clamp(1, pts.len().max(2) - 1);
            let (a, b) = (pts[j - 1], pts.get(j).copied().unwrap_or(pts[j - 1]));
            let w = if b.0 > a.0 {
                (tau - a.0) / (b.0 - a.0)
            } else {
                0.0
            };
            [
                a.1[0] + w * (b.1[0] - a.1[0]),
                a.1[1] + w * (b.1[1] - a.1[1]),
            ]
        })
        .collect()
}

/// Each moving segment's periodic-orbit excursion on the grid:
/// `per_segment[i][node][phase]` (m).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Excursions {
    grid: Grid,
    per_segment: Vec<Option<Vec<Vec<[f64; 2]>>>>,
    periods: Vec<f64>,
}

impl Excursions {
    /// The excursion of segment `i` at time `tau` into the segment, at `r`.
    fn at(&self, i: usize, tau: f64, r: [f64; 2]) -> [f64; 2] {
        let Some(nodes) = &self.per_segment[i] else {
            return [0.0; 2];
        };
        let g = &self.grid;
        let f = (tau / self.periods[i]).rem_euclid(1.0) * PHASES as f64;
        // f ≥ 0 (or NaN, to 0 either way): truncation is the floor.
        let k0 = (f as usize).min(PHASES - 1);
        let (k1, wk) = ((k0 + 1) % PHASES, f - k0 as f64);
        let Some(cell) = g.bilinear_weights(g.clamp(r)) else {
            return [0.0; 2];
        };
        let mut out = [0.0; 2];
        for (k, w) in cell {
            let node = &nodes[k];
            for x in 0..2 {
                out[x] += w * ((1.0 - wk) * node[k0][x] + wk * node[k1][x]);
            }
        }
        out
    }
}

/// Every segment's velocity field at one θ (`None`: rest), and the
/// periodic orbits' excursions when the model includes them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FieldSet {
    /// Per segment.
    pub fields: Vec<Option<Field>>,
    /// The excursions within a cycle (`None`: the mean path alone).
    pub excursion: Option<Arc<Excursions>>,
}

impl FieldSet {
    /// Largest difference between two sets' valid samples (m/s).
    pub(crate) fn max_difference(&self, other: &FieldSet) -> f64 {
        self.fields
            .iter()
            .zip(&other.fields)
            .filter_map(|(a, b)| a.as_ref().zip(b.as_ref()))
            .flat_map(|(a, b)| a.vectors.iter().zip(&b.vectors))
            .map(|(u, v)| (u[0] - v[0]).hypot(u[1] - v[1]))
            .fold(0.0, f64::max)
    }
}

/// Field sets at θ_c and θ_c ± h_j e_j for the free parameters; the
/// samples at any θ as the per-axis quadratic through them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Stencil {
    /// θ_c.
    pub center: Theta,
    /// Step per parameter.
    pub h: Theta,
    /// The free parameters (indices into θ).
    pub free: Vec<usize>,
    base: FieldSet,
    /// Per free parameter: (minus, plus).
    sides: Vec<(FieldSet, FieldSet)>,
}

impl Stencil {
    /// Computes the 1 + 2·|free| field sets.
    ///
    /// # Errors
    /// As [`PlayedMotion::fields`].
    pub(crate) fn compute(
        motion: &PlayedMotion,
        center: Theta,
        h: Theta,
        free: &[usize],
    ) -> Result<Stencil> {
        Stencil::around(motion, motion.centre(&center)?, center, h, free)
    }

    /// The stencil about `center` whose centre's set `base` (with its
    /// excursions) is already computed.
    ///
    /// # Errors
    /// As [`PlayedMotion::fields`].
    pub(crate) fn around(
        motion: &PlayedMotion,
        base: FieldSet,
        center: Theta,
        h: Theta,
        free: &[usize],
    ) -> Result<Stencil> {
        let sides = free
            .iter()
            .map(|&j| {
                let (mut lo, mut hi) = (center, center);
                lo[j] -= h[j];
                hi[j] += h[j];
                Ok((motion.fields(&lo)?, motion.fields(&hi)?))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Stencil {
            center,
            h,
            free: free.to_vec(),
            base,
            sides,
        })
    }

    /// The field set at θ (free parameters from θ, the others at θ_c).
    pub(crate) fn at(&self, theta: &Theta) -> FieldSet {
        let weights: Vec<(f64, f64)> = self
            .free
            .iter()
            .map(|&j| {
                let d = (theta[j] - self.center[j]) / self.h[j];
                // Lagrange weights of the nodes −1, +1 (the centre's is
                // 1 − d² and enters through the base).
                (0.5 * d * (d - 1.0), 0.5 * d * (d + 1.0))
            })
            .collect();
        let fields = self
            .base
            .fields
            .iter()
            .enumerate()
            .map(|(s, f)| {
                f.as_ref().map(|f0| {
                    let mut out = f0.clone();
                    for (k, v) in out.vectors.iter_mut().enumerate() {
                        for ((lo, hi), &(wl, wh)) in self.sides.iter().zip(&weights) {
                            let (a, b) = (&lo.fields[s], &hi.fields[s]);
                            if let (Some(a), Some(b)) = (a, b) {
                                for (x, vx) in v.iter_mut().enumerate() {
                                    *vx += wl * (a.vectors[k][x] - f0.vectors[k][x])
                                        + wh * (b.vectors[k][x] - f0.vectors[k][x]);
                                }
                            }
                        }
                    }
                    for (k, val) in out.validity.iter_mut().enumerate() {
                        for (lo, hi) in &self.sides {
                            for side in [lo, hi] {
                                if let Some(f) = &side.fields[s] {
                                    if f.validity[k] != Validity::Ok {
                                        *val = f.validity[k];
                                    }
                                }
                            }
                        }
                    }
                    out
                })
            })
            .collect();
        FieldSet {
            fields,
            excursion: self.base.excursion.clone(),
        }
    }
}
