//! The primitive library simulated into fields: [`FieldLibrary`] holds one
//! field kind (what a design needs: the default velocity basis never uses
//! force fields, which were a third of a cold design's time), [`Library`]
//! both kinds (what `platefield primitives` reports).

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

/// One primitive with its field of a [`FieldLibrary`]'s kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldEntry {
    /// The primitive and its parameters.
    pub primitive: Primitive,
    /// Its field (zero-velocity force or steady-state velocity).
    pub field: Field,
}

/// The primitives simulated into fields of one kind only.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldLibrary {
    /// Sampling grid.
    pub grid: Grid,
    /// Field settings (model, friction, numerics, phases).
    pub settings: FieldSettings,
    /// The kind of every field held.
    pub kind: FieldKind,
    /// The entries, in the order requested.
    pub entries: Vec<FieldEntry>,
}

impl FieldLibrary {
    /// Simulates the `kind` field of each primitive (and nothing else).
    pub fn build(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        kind: FieldKind,
        quiet: bool,
    ) -> FieldLibrary {
        let bar = progress_bar((primitives.len() * grid.len()) as u64, quiet);
        let entries = primitives
            .iter()
            .map(|p| {
                bar.set_message(p.kind.name());
                let tick = || bar.inc(1);
                FieldEntry {
                    primitive: p.clone(),
                    field: Field::compute(&p.motion(), grid, kind, settings, &tick),
                }
            })
            .collect();
        bar.finish_and_clear();
        FieldLibrary {
            grid: *grid,
            settings: *settings,
            kind,
            entries,
        }
    }
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
    /// Simulates the force and velocity fields of each primitive (two
    /// [`FieldLibrary`] builds, force first).
    pub fn build(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        quiet: bool,
    ) -> Library {
        let force = FieldLibrary::build(primitives, grid, settings, FieldKind::Force, quiet);
        let velocity = FieldLibrary::build(primitives, grid, settings, FieldKind::Velocity, quiet);
        let entries = force
            .entries
            .into_iter()
            .zip(velocity.entries)
            .map(|(f, v)| LibraryEntry {
                primitive: f.primitive,
                force: f.field,
                velocity: v.field,
            })
            .collect();
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
