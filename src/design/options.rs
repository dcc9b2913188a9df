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
    /// Checks every option against its allowed range, naming the
    /// command-line argument in the error.
    pub fn validate(&self) -> Result<()> {
        if let Some(n) = self.total_cycles {
            if !(1..=MAX_SEGMENT_CYCLES).contains(&n) {
                return Err(Error::invalid(
                    "--cycles",
                    format!("must be in 1..={MAX_SEGMENT_CYCLES}, got {n}"),
                ));
            }
        }
        if !(1..=MAX_SEGMENT_CYCLES).contains(&self.min_cycles) {
            return Err(Error::invalid(
                "--min-cycles",
                format!(
                    "must be in 1..={MAX_SEGMENT_CYCLES}, got {}",
                    self.min_cycles
                ),
            ));
        }
        for s in &self.shifts {
            if !s.iter().all(|v| v.is_finite() && v.abs() <= MAX_SHIFT_M) {
                return Err(Error::invalid(
                    "--shift",
                    format!(
                        "each coordinate must be in [-{MAX_SHIFT_M}, {MAX_SHIFT_M}] m, got {:.3e},{:.3e}",
                        s[0], s[1]
                    ),
                ));
            }
        }
        Ok(())
    }
}
