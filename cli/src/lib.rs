//! Command-line argument groups and handlers of the `platefield` binary: each
//! handler turns parsed arguments into one library call and returns the text
//! to print, so `main.rs` stays a thin clap shell.

pub mod calibrate;
pub mod design;
pub mod export;
pub mod field;
pub mod linesink;
pub mod poses;
pub mod values;
pub mod verify;

use clap::Args;

use platefield::dynamics::{Model, Numerics};
use platefield::{Error, Result};

/// How moving parts play a schedule for the model check (`verify`, `order`).
#[derive(Args)]
pub struct Play {
    /// Start points per side of the N×N grid over the target region (order: over ±3 cm).
    #[arg(long, default_value_t = 5)]
    pub points: usize,
    /// Schedule periods measured after the warm-up (order: at least, per candidate).
    #[arg(long, default_value_t = 1)]
    pub periods: u32,
    /// Schedule periods played before measuring (order: at least, and at least 40 primitive cycles).
    #[arg(long, default_value_t = 1)]
    pub warmup: u32,
    /// Model: the schedule's own (default, normally full), full, paper, frozen (full with positions frozen: an exact comparison when parts drift far), a rung between paper and full (paper+moving, paper+moving+centripetal+tilt), or auto (verify only: per segment the cheapest rung within 2 % of full at the realised grid's points, recorded in the summary; played at the cheapest that moves the part and holds for every segment).
    #[arg(long, value_parser = values::choices(&values::MODELS), hide_possible_values = true)]
    pub model: Option<values::ModelChoice>,
}

impl Play {
    /// The model asked for, when it is one (not `auto`): `None` plays the
    /// schedule's own; `auto` is refused naming `--model` (`command`
    /// chooses no rung).
    pub fn fixed_model(&self, command: &str) -> Result<Option<Model>> {
        match self.model {
            None => Ok(None),
            Some(values::ModelChoice::Model(m)) => Ok(Some(m)),
            Some(values::ModelChoice::Auto) => Err(Error::invalid(
                "--model",
                format!("auto is for verify and design; {command} takes paper, full, frozen, paper+moving or paper+moving+centripetal+tilt"),
            )),
        }
    }
}

/// `--json`.
#[derive(Args)]
pub struct Json {
    /// Print JSON on stdout instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// `--quiet`.
#[derive(Args)]
pub struct Quiet {
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `--allow-long`.
#[derive(Args)]
pub struct AllowLong {
    /// Run even when the work estimate exceeds the limit (10 min at the stated rate; docs/commands.md).
    #[arg(long)]
    pub allow_long: bool,
}

/// Integrator resolution.
#[derive(Args)]
pub struct Steps {
    /// RK4 steps per cycle.
    #[arg(long, default_value_t = Numerics::default().steps_per_cycle as u64,
          value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    pub steps: u64,
}

impl Steps {
    /// The default numerics with `--steps` RK4 steps per cycle.
    pub fn numerics(&self) -> Numerics {
        Numerics {
            steps_per_cycle: self.steps as usize,
            ..Numerics::default()
        }
    }
}
