//! Command-line values of the library's enums: the library derives no clap
//! trait, so each enum's names and help lines (those `--help` lists) are
//! stated here, and [`choices`] parses them.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};

use platefield::basis::PrimitiveKind;
use platefield::dynamics::{Model, Preset};
use platefield::field::rung::RUNGS;
use platefield::field::FieldKind;
use platefield_studies::linesink::Wave;

/// One value: what it parses to, its name on the command line, its help.
type Choice<T> = (T, &'static str, &'static str);

/// A parser of the names in `table` into their values; `--help` lists each
/// name with its help line.
pub fn choices<T: Copy + Send + Sync + 'static>(
    table: &'static [Choice<T>],
) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        table
            .iter()
            .map(|(_, name, help)| PossibleValue::new(*name).help(*help)),
    )
    .try_map(move |name: String| {
        table
            .iter()
            .find(|c| c.1 == name)
            .map(|c| c.0)
            .ok_or_else(|| format!("not one of the possible values: {name}"))
    })
}

/// `--basis` ([`FieldKind`]).
pub const FIELD_KINDS: [Choice<FieldKind>; 2] = [
    (
        FieldKind::Force,
        "force",
        "Zero-velocity force field (m/s²)",
    ),
    (
        FieldKind::Velocity,
        "velocity",
        "Steady-state velocity field (m/s)",
    ),
];

/// `--primitives` ([`PrimitiveKind`], by their names in files).
pub const PRIMITIVE_KINDS: [Choice<PrimitiveKind>; 8] = [
    (
        PrimitiveKind::LineSink,
        "LineSink",
        "Rotation about a horizontal axis below the plate: f ≈ a(−x, 0)",
    ),
    (
        PrimitiveKind::LineSource,
        "LineSource",
        "The same with the axis above: f ≈ a(x, 0)",
    ),
    (
        PrimitiveKind::SkewSink,
        "SkewSink",
        "Screw (rotation and translation in phase) about an axis below: f ≈ a(−x, x)",
    ),
    (
        PrimitiveKind::SkewSource,
        "SkewSource",
        "Screw about an axis above: f ≈ a(x, −x)",
    ),
    (
        PrimitiveKind::DivCircle,
        "DivCircle",
        "Rotation about an axis through the centre tilted 45°: f ≈ (a x y, b x²)",
    ),
    (
        PrimitiveKind::Trans,
        "Trans",
        "Asymmetric in-plane translation: f ≈ a(1, 0)",
    ),
    (
        PrimitiveKind::ScaledCircle,
        "ScaledCircle",
        "Asymmetric in-plane rotation, small amplitude: f ≈ a(−y, x)",
    ),
    (
        PrimitiveKind::Circle,
        "Circle",
        "Asymmetric in-plane rotation, large amplitude: f ≈ a(−y, x)/|(x, y)|",
    ),
];

/// `--model` ([`Preset`]).
pub const PRESETS: [Choice<Preset>; 3] = [
    (
        Preset::Paper,
        "paper",
        "The paper's analysis (small angles, no centripetal or tilt terms)",
    ),
    (Preset::Full, "full", "Every term on"),
    (Preset::Frozen, "frozen", "Every term on, positions frozen"),
];

/// A `--model` of `verify` and `order`: a model, or the automatic rung.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelChoice {
    /// This model.
    Model(Model),
    /// The cheapest rung within the default tolerance of full, per segment
    /// (`platefield::field::rung`).
    Auto,
}

/// `--model` of `verify` and `order` ([`ModelChoice`]): the presets, the
/// two intermediate rungs, and `auto`.
pub const MODELS: [Choice<ModelChoice>; 6] = [
    (
        ModelChoice::Model(Model::PAPER),
        "paper",
        "The paper's analysis (small angles, no centripetal or tilt terms)",
    ),
    (ModelChoice::Model(Model::FULL), "full", "Every term on"),
    (
        ModelChoice::Model(Model::FROZEN),
        "frozen",
        "Every term on, positions frozen",
    ),
    (
        ModelChoice::Model(RUNGS[1].1),
        RUNGS[1].0,
        "The paper's analysis with the part moving during the cycle",
    ),
    (
        ModelChoice::Model(RUNGS[2].1),
        RUNGS[2].0,
        "Every term but Coriolis",
    ),
    (
        ModelChoice::Auto,
        "auto",
        "Per segment the cheapest rung within 2 % of full at the realised grid's points; played at the cheapest rung that moves the part and is within it for every segment",
    ),
];

/// `linesink --wave` ([`Wave`]).
pub const WAVES: [Choice<Wave>; 2] = [
    (Wave::Square, "square", "The paper's eq. 1: ±α square wave"),
    (Wave::Sine, "sine", "ψ'' = A sin ωt"),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Every table names each variant once, by the name the library uses
    /// where it has one.
    #[test]
    fn tables_are_whole_and_named_as_the_library_names_them() {
        for (k, name, _) in PRIMITIVE_KINDS {
            assert_eq!(k.name(), name);
        }
        let kinds: std::collections::BTreeSet<_> = PRIMITIVE_KINDS.iter().map(|c| c.0).collect();
        assert_eq!(kinds.len(), PrimitiveKind::ALL.len());
        let p = choices(&PRESETS);
        let cmd = clap::Command::new("t");
        let arg = clap::Arg::new("m");
        assert_eq!(
            p.parse_ref(&cmd, Some(&arg), std::ffi::OsStr::new("frozen"))
                .unwrap(),
            Preset::Frozen
        );
        assert!(p
            .parse_ref(&cmd, Some(&arg), std::ffi::OsStr::new("Frozen"))
            .is_err());
    }
}
