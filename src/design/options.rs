//! Range checks of [`DesignOptions`], run before any library build, so a
//! count or a shift from the command line can neither overflow nor ask for
//! hours of simulation without a word.

use super::DesignOptions;
use crate::error::{Error, Result};
use crate::schedule::MAX_SEGMENT_CYCLES;

/// Largest basis shift (m) along either axis: the plate regions the
/// primitives are built for span a few centimetres, and the library grid
/// grows with the shift (a 1 m shift asked for 4.4 M samples per primitive).
pub const MAX_SHIFT_M: f64 = 0.1;

impl DesignOptions {
    /// Checks every option against its allowed range, naming the option's
    /// path (`total_cycles`, `closed_loop.stride`) in the error.
    pub fn validate(&self) -> Result<()> {
        if let Some(n) = self.total_cycles {
            if !(1..=MAX_SEGMENT_CYCLES).contains(&n) {
                return Err(Error::invalid(
                    "total_cycles",
                    format!("must be in 1..={MAX_SEGMENT_CYCLES}, got {n}"),
                ));
            }
        }
        if !(1..=MAX_SEGMENT_CYCLES).contains(&self.min_cycles) {
            return Err(Error::invalid(
                "min_cycles",
                format!(
                    "must be in 1..={MAX_SEGMENT_CYCLES}, got {}",
                    self.min_cycles
                ),
            ));
        }
        for s in &self.shifts {
            if !s.iter().all(|v| v.is_finite() && v.abs() <= MAX_SHIFT_M) {
                return Err(Error::invalid(
                    "shifts",
                    format!(
                        "each coordinate must be in [-{MAX_SHIFT_M}, {MAX_SHIFT_M}] m, got {:.3e},{:.3e}",
                        s[0], s[1]
                    ),
                ));
            }
        }
        rotation_step(self.rotation_step_deg)
    }
}

/// Smallest basis rotation step (degrees). The rotated copies are not
/// simulated but held and fitted: their memory and the fit's time grow as
/// 1/step² (the sink: 4 s at 1°, 19 s at 0.5°, 68 s at 0.25°), and a step
/// of 1e-9° asked for 2.9 TB and aborted.
pub const MIN_ROTATION_STEP_DEG: f64 = 1.0;

/// The rotation step (`--rotation-step`) must divide 360: the basis holds 360/step rotated
/// copies of each primitive, and a step that does not divide 360 was
/// rounded to the nearest whole number of copies without a word (7 became
/// 7.0588°, 51 copies; the sink's LineSinks fell out of the basis and the
/// fit reached 23 % error). A step is accepted when 360/step is within
/// 1e-9 of a whole number; otherwise the error names the nearest steps
/// below and above that divide 360 and are written with at most three
/// decimals (7: 6 and 7.2). The step must also lie in
/// [[`MIN_ROTATION_STEP_DEG`], 360].
fn rotation_step(step: f64) -> Result<()> {
    if !(MIN_ROTATION_STEP_DEG..=360.0).contains(&step) {
        return Err(Error::invalid(
            "rotation_step_deg",
            format!(
                "must be in [{MIN_ROTATION_STEP_DEG}, 360] degrees (at most 360 rotated copies of each primitive), got {}",
                crate::input::num(step)
            ),
        ));
    }
    let copies = 360.0 / step;
    if (copies - copies.round()).abs() <= 1e-9 {
        return Ok(());
    }
    // Steps 360/n in [1, 360] written with at most three decimals.
    let nice: Vec<f64> = (1..=360)
        .map(|n| 360.0 / f64::from(n))
        .filter(|s| ((s * 1000.0).round() - s * 1000.0).abs() < 1e-6)
        .collect();
    let below = nice
        .iter()
        .copied()
        .filter(|s| *s < step)
        .max_by(f64::total_cmp);
    let above = nice
        .iter()
        .copied()
        .filter(|s| *s > step)
        .min_by(f64::total_cmp);
    let nearest: Vec<String> = [below, above]
        .into_iter()
        .flatten()
        .map(|s| crate::input::num((s * 1000.0).round() / 1000.0))
        .collect();
    Err(Error::invalid(
        "rotation_step_deg",
        format!(
            "{} does not divide 360 (360/{} = {:.4} rotated copies; a whole number is needed); nearest steps that divide 360: {}",
            crate::input::num(step),
            crate::input::num(step),
            copies,
            nearest.join(", ")
        ),
    ))
}
