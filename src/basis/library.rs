//! The primitive library simulated into force and velocity fields.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};

use super::primitives::{Primitive, PrimitiveKind};
use crate::field::{Field, FieldKind, FieldSettings, Grid};

/// One primitive with its fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LibraryEntry {
    /// The primitive and its parameters.
    pub primitive: Primitive,
    /// Zero-velocity force field.
    pub force: Field,
    /// Steady-state velocity field.
    pub velocity: Field,
}

/// A built library.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Library {
    /// Sampling grid.
    pub grid: Grid,
    /// Field settings (model, friction, numerics, phases).
    pub settings: FieldSettings,
    /// The entries, in the order requested.
    pub entries: Vec<LibraryEntry>,
}

/// A progress bar over `total` field samples, drawn only on a terminal.
pub fn progress_bar(total: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total);
    if let Ok(style) =
        ProgressStyle::with_template("{msg:>14} [{bar:40}] {pos}/{len} samples ({eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

impl Library {
    /// Simulates the force and velocity fields of each primitive.
    pub fn build(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        quiet: bool,
    ) -> Library {
        let bar = progress_bar(2 * (primitives.len() * grid.len()) as u64, quiet);
        let entries = primitives
            .iter()
            .map(|p| {
                bar.set_message(p.kind.name());
                let motion = p.motion();
                let tick = || bar.inc(1);
                LibraryEntry {
                    primitive: p.clone(),
                    force: Field::compute(&motion, grid, FieldKind::Force, settings, &tick),
                    velocity: Field::compute(&motion, grid, FieldKind::Velocity, settings, &tick),
                }
            })
            .collect();
        bar.finish_and_clear();
        Library {
            grid: *grid,
            settings: *settings,
            entries,
        }
    }

    /// The paper's eight primitives with default parameters.
    pub fn default_primitives() -> Vec<Primitive> {
        PrimitiveKind::ALL
            .iter()
            .map(|k| Primitive::new(*k))
            .collect()
    }
}
