//! The primitive library simulated into fields: [`FieldLibrary`] holds one
//! field kind (what a design needs: the default velocity basis never uses
//! force fields, which would be a third of a cold design's time), [`Library`]
//! both kinds (what `platefield study primitives` reports).

use serde::{Deserialize, Serialize};

use super::primitives::{Primitive, PrimitiveKind};
use super::steps::StepsPlan;
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::progress::{Progress, ProgressMode};

/// One primitive with its fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LibraryEntry {
    /// The primitive and its parameters.
    pub primitive: Primitive,
    /// Zero-velocity force field.
    pub force: Field,
    /// Steps per cycle the force field was simulated with.
    pub force_steps: usize,
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
    /// Steps per cycle it was simulated with ([`StepsPlan`]).
    pub steps_per_cycle: usize,
}

/// The primitives simulated into fields of one kind only.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldLibrary {
    /// Sampling grid.
    pub grid: Grid,
    /// Field settings (model, friction, numerics, phases) as requested; an
    /// entry's own steps per cycle are its `steps_per_cycle`.
    pub settings: FieldSettings,
    /// The kind of every field held.
    pub kind: FieldKind,
    /// The entries, in the order requested.
    pub entries: Vec<FieldEntry>,
}

impl FieldLibrary {
    /// Simulates the `kind` field of each primitive (and nothing else), all
    /// at the settings' steps per cycle.
    pub fn build(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        kind: FieldKind,
        progress: ProgressMode,
    ) -> FieldLibrary {
        Self::build_with(
            primitives,
            grid,
            settings,
            kind,
            StepsPlan::Uniform,
            progress,
        )
    }

    /// As [`FieldLibrary::build`], each field at the steps per cycle of
    /// `plan`.
    pub fn build_with(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        kind: FieldKind,
        plan: StepsPlan,
        progress: ProgressMode,
    ) -> FieldLibrary {
        let label = match kind {
            FieldKind::Force => "force library",
            FieldKind::Velocity => "velocity library",
        };
        let progress = Progress::new(
            label,
            "samples",
            (primitives.len() * grid.len()) as u64,
            progress,
        );
        let entries = primitives
            .iter()
            .map(|p| {
                progress.set_message(p.kind.name());
                let tick = || progress.inc(1);
                let at = plan.settings(p, kind, grid, settings);
                FieldEntry {
                    primitive: p.clone(),
                    field: Field::compute(&p.motion(), grid, kind, &at, &tick),
                    steps_per_cycle: at.numerics.steps_per_cycle,
                }
            })
            .collect();
        progress.finish();
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
    /// Field settings (model, friction, numerics, phases) as requested; an
    /// entry's force field was simulated at its `force_steps`.
    pub settings: FieldSettings,
    /// The entries, in the order requested.
    pub entries: Vec<LibraryEntry>,
}

impl Library {
    /// Simulates the force and velocity fields of each primitive (two
    /// [`FieldLibrary`] builds, force first), the force fields at the steps
    /// per cycle of `plan`.
    pub fn build(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        plan: StepsPlan,
        progress: ProgressMode,
    ) -> Library {
        let force =
            FieldLibrary::build_with(primitives, grid, settings, FieldKind::Force, plan, progress);
        let velocity =
            FieldLibrary::build(primitives, grid, settings, FieldKind::Velocity, progress);
        let entries = force
            .entries
            .into_iter()
            .zip(velocity.entries)
            .map(|(f, v)| LibraryEntry {
                primitive: f.primitive,
                force: f.field,
                force_steps: f.steps_per_cycle,
                velocity: v.field,
            })
            .collect();
        Library {
            grid: *grid,
            settings: *settings,
            entries,
        }
    }

    /// "Kind steps" per entry, comma-separated: the steps per cycle of each
    /// force field.
    pub fn force_steps_list(&self) -> String {
        self.entries
            .iter()
            .map(|e| format!("{} {}", e.primitive.kind.name(), e.force_steps))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The paper's eight primitives with default parameters.
    pub fn default_primitives() -> Vec<Primitive> {
        PrimitiveKind::ALL
            .iter()
            .map(|k| Primitive::new(*k))
            .collect()
    }
}
