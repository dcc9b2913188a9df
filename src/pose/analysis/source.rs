//! A designed schedule's point field: the time-weighted mean of its
//! segments' steady-state velocity fields.
//!
//! **Model.** A part that moves little during one segment drifts, over a
//! schedule period T = Σ d_i, by Σ d_i V_i(p): its mean velocity is
//! V(p) = Σ_i d_i V_i(p) / T, a rest segment contributing V = 0 for its
//! duration (a part at rest on a plate at rest stays). V_i is the field of
//! the periodic motion segment i plays between its ramps
//! ([`crate::schedule::Segment::steady_motion`]). This is the field
//! the design fitted (its predicted field); the played drops
//! ([`crate::pose::play_drops`]) measure what it leaves out (start-up transients
//! at the joins, motion within a segment).

use super::lifted::GridField;
use crate::field::{Field, FieldKind, Grid};
use crate::schedule::Schedule;
use crate::{Error, Result};

/// The time-weighted velocity field of `schedule`'s segments on `grid`,
/// computed with the schedule's settings (module docs). A sample where
/// some segment's point part loses contact is refused as physically
/// invalid.
///
/// ```no_run
/// use platefield::pose::schedule_field;
/// use platefield::schedule::Schedule;
/// let s = Schedule::load(std::path::Path::new("results/ellipse/schedule.json"))?;
/// let grid = s.target_spec.as_ref().and_then(|t| t.grid).expect("a grid");
/// let field = schedule_field(&s, &grid)?;
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn schedule_field(schedule: &Schedule, grid: &Grid) -> Result<GridField> {
    let mut sum = vec![[0.0f64; 2]; grid.len()];
    let mut total = 0.0;
    for (i, seg) in schedule.segments.iter().enumerate() {
        seg.validate_motion(&format!("schedule.segments[{i}]"))?;
        total += seg.duration_s;
        let Some(motion) = seg.steady_motion() else {
            continue;
        };
        let field = Field::compute(
            &motion,
            grid,
            FieldKind::Velocity,
            &schedule.settings,
            &|| {},
        );
        if field.valid_count() != grid.len() {
            return Err(Error::ContactLost(format!(
                "schedule.segments[{i}] ({}): the point part loses contact at {} of {} grid points; its field is not defined there",
                seg.label,
                grid.len() - field.valid_count(),
                grid.len()
            )));
        }
        for (acc, v) in sum.iter_mut().zip(&field.vectors) {
            acc[0] += seg.duration_s * v[0];
            acc[1] += seg.duration_s * v[1];
        }
    }
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::invalid(
            "schedule.segments",
            "must last a positive time",
        ));
    }
    let mean = sum.iter().map(|v| [v[0] / total, v[1] / total]).collect();
    Ok(GridField::from_samples(*grid, mean))
}

/// Every [`REALISED_STRIDE`]-th grid point per axis is played for the
/// realised field.
pub const REALISED_STRIDE: usize = 2;

/// The realised point field of `schedule` on `grid`: a point part played
/// through the schedule from every [`REALISED_STRIDE`]-th grid point with
/// its position frozen there ([`crate::dynamics::Model::FROZEN`]: the
/// local field, start-up transients at the segment joins included), one
/// warm-up period (lengthened while its transient lasts) and one measured
/// period averaged over windows starting at every join
/// ([`crate::play::measure`]). What the played part sees, where
/// [`schedule_field`] is what the design predicts; the lifted field of a
/// pose design is placed on this one. A point that loses contact is
/// refused as physically invalid.
pub fn realised_field(schedule: &Schedule, grid: &Grid) -> Result<GridField> {
    use crate::play::measure::{play_points, Windows};
    let sm = crate::play::ScheduleMotion::from_schedule(schedule)?;
    let mut opts = crate::play::PlayOptions::from_settings(&schedule.settings);
    opts.model = crate::dynamics::Model {
        moving: false,
        ..schedule.settings.model
    };
    let coarse = Grid {
        n: [
            (grid.n[0] - 1) / REALISED_STRIDE + 1,
            (grid.n[1] - 1) / REALISED_STRIDE + 1,
        ],
        ..*grid
    };
    let plays = play_points(&sm, &coarse.points(), &opts, Windows::EveryJoin);
    if let Some(p) = plays.iter().find(|p| p.note.is_some()) {
        return Err(Error::ContactLost(format!(
            "the point part played from ({}, {}) m: {}",
            p.start[0],
            p.start[1],
            p.note.clone().unwrap_or_default()
        )));
    }
    Ok(GridField::from_samples(
        coarse,
        plays.iter().map(|p| p.realised).collect(),
    ))
}
