//! DESIGN.md section 6's interaction table: how far a sequenced schedule's
//! realised field is from the time-weighted combination of its segments'
//! steady-state fields, for a Sink made of two orthogonal LineSinks.
//!
//! Setup: LineSink at rotation 0° then at 90°, n cycles each (equal time),
//! paper defaults (ω = 209 rad/s, ψ0 = 0.005 rad, depth 5 cm, μ = 0.3),
//! frozen positions (the full model with `moving` off), 5 × 5 points over
//! ±4 cm. Two waveforms: (a) the primitives' rest-to-rest ψ0(1 − cos ωt);
//! (b) a sine ψ'' = ψ0 ω² sin ωt (the same peak angular acceleration), whose
//! plate velocity jumps at every join.
//!
//! Error definition: relative L2 error over the 25 points of the realised
//! mean velocity (displacement over whole schedule periods after a warm-up)
//! against the time-weighted prediction ([`super::realised`]). The warm-up is
//! at least 40 primitive cycles and the measurement covers at least 20
//! (whole schedule periods in both).

use std::path::Path;

use serde::Serialize;

use super::realised::{grid_points, verify_points, VerifyOptions};
use super::{Join, PlayedSegment, ScheduleMotion};
use crate::basis::primitives::PSI0;
use crate::basis::{Primitive, PrimitiveKind};
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::motion::{Motion, Waveform};

/// Cycles per segment in the table.
pub const CYCLES: [u32; 3] = [1, 3, 10];

/// One row of the table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InteractionRow {
    /// Cycles per segment.
    pub cycles: u32,
    /// Relative L2 error, rest-to-rest waveform.
    pub rest_to_rest: f64,
    /// Relative L2 error, sine waveform (inertial velocity continuous at joins).
    pub sine: f64,
    /// Relative L2 error, sine waveform with the slip velocity carried
    /// over unchanged at joins (unphysical).
    pub sine_slip_kept: f64,
}

/// The two orthogonal LineSinks, `cycles` each, with the rest-to-rest
/// waveform (`sine` false) or a sine of the same peak angular acceleration.
pub fn sink_schedule(cycles: u32, sine: bool) -> Result<ScheduleMotion> {
    let segments = [0.0, 90.0]
        .iter()
        .map(|deg| {
            let p = Primitive {
                rotation_deg: *deg,
                ..Primitive::new(PrimitiveKind::LineSink)
            };
            let mut m = p.motion();
            if sine {
                if let Motion::Screw(s) = &mut m {
                    s.rotation = Waveform::Sine {
                        accel: PSI0 * p.omega * p.omega,
                    };
                }
            }
            PlayedSegment::moving(format!("LineSink@{deg}°"), m, cycles)
        })
        .collect();
    ScheduleMotion::new(segments)
}

/// Interaction error of the two-LineSink Sink with `cycles` per segment on
/// `n × n` points over ±`half` m, for `model`.
pub fn interaction_error(
    cycles: u32,
    sine: bool,
    n: usize,
    half: f64,
    model: Model,
    join: Join,
) -> Result<f64> {
    let sm = sink_schedule(cycles, sine)?;
    let per_period = 2 * cycles;
    let opts = VerifyOptions {
        model,
        join,
        warmup_periods: 40u32.div_ceil(per_period),
        periods: 20u32.div_ceil(per_period),
        ..VerifyOptions::default()
    };
    let v = verify_points(&sm, &grid_points(n, half), &opts);
    if v.valid != n * n {
        let why = v
            .points
            .iter()
            .find_map(|p| p.note.clone())
            .unwrap_or_default();
        return Err(Error::Physical(format!(
            "interaction ({cycles} cycles, {}): {} of {} points invalid: {why}",
            if sine { "sine" } else { "rest-to-rest" },
            n * n - v.valid,
            n * n
        )));
    }
    Ok(v.relative_error)
}

/// The frozen model of the table: everything on but `moving`.
pub const FROZEN: Model = Model {
    moving: false,
    ..Model::FULL
};

/// Computes the rows of the table for `model` on `n × n` points over ±`half` m.
pub fn interaction_rows(n: usize, half: f64, model: Model) -> Result<Vec<InteractionRow>> {
    CYCLES
        .iter()
        .map(|&c| {
            Ok(InteractionRow {
                cycles: c,
                rest_to_rest: interaction_error(c, false, n, half, model, Join::Inertial)?,
                sine: interaction_error(c, true, n, half, model, Join::Inertial)?,
                sine_slip_kept: interaction_error(c, true, n, half, model, Join::Slip)?,
            })
        })
        .collect()
}

/// Computes the table (5 × 5 points over ±4 cm, frozen full model; the
/// paper model alongside) and writes it to `out/sink_interaction.md`;
/// returns the markdown.
pub fn interaction_table(out: &Path) -> Result<String> {
    let rows = interaction_rows(5, 0.04, FROZEN)?;
    let paper_rows = interaction_rows(5, 0.04, Model::PAPER)?;
    let doc = |c: u32| match c {
        1 => ("50 %", "190 %"),
        3 => ("21 %", "69 %"),
        10 => ("6.5 %", "21 %"),
        _ => ("-", "-"),
    };
    let mut md = String::new();
    md.push_str("# Interaction of sequenced primitives: a Sink from two orthogonal LineSinks\n\n");
    md.push_str(
        "Generated by `platefield interaction` (`platefield::verify::interaction_table`).\n\n\
         LineSink at 0° then LineSink at 90°, equal time (n cycles each), paper defaults \
         (ω = 209 rad/s, ψ0 = 0.005 rad, axis 5 cm below the plate, μ = 0.3, g = 9.81 m/s²), \
         frozen positions, 5 × 5 points over ±4 cm. Realised mean velocity (displacement over \
         whole schedule periods after a warm-up of ≥ 40 primitive cycles, measured over \
         ≥ 20 cycles) against the time-weighted prediction ½(V_0° + V_90°) of the two \
         steady-state velocity fields (same model, same waveform). Error: relative L2 over the \
         25 points, ‖realised − predicted‖ / ‖predicted‖. Sine: ψ'' = ψ0 ω² sin ωt (same peak \
         angular acceleration), so the plate velocity jumps by ψ0 ω × 5 cm ≈ 5 cm/s at every \
         join. *Inertial*: the part's tangential inertial velocity is continuous at a join \
         (physical, DESIGN.md section 7). *Slip kept*: the slip velocity relative to the plate \
         is carried over unchanged, i.e. the part jumps with the plate (unphysical; shown \
         because it is the naive way to chain simulations).\n\n",
    );
    let table = |md: &mut String, rows: &[InteractionRow], with_doc: bool| {
        md.push_str("| cycles per segment | rest-to-rest ψ0(1 − cos ωt) | sine, inertial velocity continuous | sine, slip velocity kept |");
        md.push_str(if with_doc {
            " DESIGN.md (rest-to-rest / sine) |\n|---|---|---|---|---|\n"
        } else {
            "\n|---|---|---|---|\n"
        });
        for r in rows {
            md.push_str(&format!(
                "| {} | {:.1} % | {:.1} % | {:.1} % |",
                r.cycles,
                100.0 * r.rest_to_rest,
                100.0 * r.sine,
                100.0 * r.sine_slip_kept
            ));
            if with_doc {
                let (a, b) = doc(r.cycles);
                md.push_str(&format!(" {a} / {b} |"));
            }
            md.push('\n');
        }
    };
    md.push_str(
        "## Full model with frozen positions (centripetal, tilt, Coriolis on; `moving` off)\n\n",
    );
    table(&mut md, &rows, true);
    if let (Some(first), Some(last)) = (rows.first(), rows.last()) {
        md.push_str(&format!(
            "\nThe rest-to-rest column reproduces DESIGN.md. The sine column does not: with the \
             part's inertial velocity continuous at the joins (the physical rule) the sine schedule \
             is as accurate as the rest-to-rest one ({:.1} % → {:.1} %), because the two joins of a \
             schedule period kick the slip velocity by equal and opposite amounts (v_0° − v_90° and \
             v_90° − v_0°), whose displacements nearly cancel. Other join rules tried do not give \
             DESIGN.md's 190 / 69 / 21 % either: keeping the slip velocity (column 4) gives {:.1} % → \
             {:.1} %; resetting the slip velocity to zero at each join, or applying the kick with the \
             wrong sign, gave about 100–110 % → 14–16 % in a one-off experiment. We could not \
             identify the setup behind DESIGN.md's sine column; the qualitative conclusion stands \
             (a velocity jump at the joins is at best harmless and, with any rule other than the \
             physical one, harmful; short segments need closed-loop correction).\n",
            100.0 * first.sine,
            100.0 * last.sine,
            100.0 * first.sine_slip_kept,
            100.0 * last.sine_slip_kept
        ));
    }
    md.push_str("\n## Paper model (no centripetal, tilt or Coriolis terms; frozen positions)\n\n");
    table(&mut md, &paper_rows, false);
    crate::output::write_atomic(&out.join("sink_interaction.md"), md.as_bytes())?;
    Ok(md)
}
