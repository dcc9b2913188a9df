//! `platefield design`: arguments, their checks, and the [`DesignOptions`] they build.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use platefield::basis::PrimitiveKind;
use platefield::design::closed_loop::LoopOptions;
use platefield::design::{
    BasisSection, DesignOptions, FitSection, Method, PlayModel, ScheduleSection,
};
use platefield::field::FieldKind;
use platefield::fit::FitMode;
use platefield::synth::SynthOptions;
use platefield::work::Runtime;
use platefield::{Error, Result};
use platefield_report as report;

use super::values::{choices, ModelChoice, FIELD_KINDS, MODELS, PRIMITIVE_KINDS};

/// Fit mode (see [`FitMode`]).
#[derive(Clone, Copy, ValueEnum)]
pub enum Mode {
    /// The strongest field of the target's shape.
    Shape,
    /// The target as given.
    Absolute,
    /// The strongest field within the relative error --budget.
    Budget,
    /// L1 norm of the residual.
    L1,
    /// L∞ norm of the residual.
    #[value(alias = "l_inf")]
    Linf,
}

/// `--method` (see [`Method`]).
#[derive(Clone, Copy, ValueEnum)]
pub enum DesignMethod {
    /// A time-shared schedule of primitives.
    Sequence,
    /// One simultaneous six-signal motion.
    Synthesize,
    /// Both, judged; the better one is kept.
    Auto,
    /// Primitives and a synthesized motion mixed in one fit.
    Mix,
    /// A synthesized motion time-shared with its mirror image (y → −y): holds its shape over the parts' friction, for targets symmetric in y.
    Mirror,
}

impl From<DesignMethod> for Method {
    fn from(m: DesignMethod) -> Method {
        match m {
            DesignMethod::Sequence => Method::Sequence,
            DesignMethod::Synthesize => Method::Synthesize,
            DesignMethod::Auto => Method::Auto,
            DesignMethod::Mix => Method::Mix,
            DesignMethod::Mirror => Method::Mirror,
        }
    }
}

/// `--shift x,y` (metres).
fn xy(text: &str) -> std::result::Result<[f64; 2], String> {
    let v: Vec<f64> = text
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    match v[..] {
        [x, y] if x.is_finite() && y.is_finite() && text.split(',').count() == 2 => Ok([x, y]),
        _ => Err(format!(
            "must be two numbers \"x,y\" in metres, got \"{text}\""
        )),
    }
}

/// Arguments of `platefield design`.
#[derive(Args)]
pub struct DesignArgs {
    /// Target field JSON (docs/targets.md).
    pub target: PathBuf,
    /// Parts' friction, replacing the target's "friction": MU (μ_s = μ_k = MU) or LO:HI (known within a range).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "friction_from")]
    pub friction: Option<String>,
    /// Parts' friction from a calibration (`platefield calibrate`'s calibration.json): the design is over its 95 % interval (judged at the worst case over it).
    #[arg(long, value_name = "CALIBRATION.json")]
    pub friction_from: Option<PathBuf>,
    /// The class of --friction-from's calibration to design for (classes by increasing μ, from 0).
    #[arg(long, default_value_t = 0, requires = "friction_from")]
    pub class: usize,
    /// Fit mode: shape (strongest field of the target's shape), absolute, budget, l1 or linf (docs/design.md).
    #[arg(long, value_enum, default_value_t = Mode::Shape, hide_possible_values = true)]
    pub mode: Mode,
    /// Relative error budget for --mode budget, in (0, 1).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub budget: f64,
    /// Use at most this many segments.
    #[arg(long, allow_negative_numbers = true)]
    pub max_primitives: Option<usize>,
    /// Basis field kind: velocity (steady-state velocity fields) or force.
    #[arg(long, value_parser = choices(&FIELD_KINDS), default_value = "velocity", hide_possible_values = true)]
    pub basis: FieldKind,
    /// Rotation step of the basis copies (degrees; in [1, 360] and dividing 360).
    #[arg(long, default_value_t = 15.0, allow_negative_numbers = true)]
    pub rotation_step: f64,
    /// Primitive kinds allowed, comma separated (default: all eight: LineSink, LineSource, SkewSink, SkewSource, DivCircle, Trans, ScaledCircle, Circle).
    #[arg(long, value_parser = choices(&PRIMITIVE_KINDS), value_delimiter = ',', hide_possible_values = true)]
    pub primitives: Option<Vec<PrimitiveKind>>,
    /// Also use basis copies shifted by this horizontal offset "x,y" (m); repeatable.
    #[arg(long, allow_negative_numbers = true, value_parser = xy)]
    pub shift: Vec<[f64; 2]>,
    /// Keep basis fields that are invalid somewhere in the region (their invalid points are listed in the schedule).
    #[arg(long)]
    pub keep_invalid: bool,
    /// Minimum cycles per segment.
    #[arg(long, default_value_t = platefield::schedule::DEFAULT_MIN_CYCLES)]
    pub min_cycles: u32,
    /// Total schedule length in cycles (default: the shortest within the quantisation tolerance).
    #[arg(long)]
    pub cycles: Option<u32>,
    /// Output folder; files go to OUT/<target name>/ (out/ is ignored by git; the committed designs: --out results).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// How to design: sequence (time-shared primitives), synthesize (one six-signal motion), auto (both played, the better kept), mix or mirror (docs/design.md).
    #[arg(long, value_enum, default_value_t = DesignMethod::Auto, hide_possible_values = true)]
    pub method: DesignMethod,
    /// Synthesis: most coarse-grid re-simulations.
    #[arg(long, default_value_t = 300)]
    pub synth_evaluations: usize,
    /// Synthesis: RNG seed of the multi-start (same seed, same bytes).
    #[arg(long, default_value_t = 1)]
    pub synth_seed: u64,
    /// Synthesis: plays of the polish of the synthesized motion on the judge's points (0, the default: none).
    #[arg(long, default_value_t = 0)]
    pub polish_plays: usize,
    /// Synthesis and polish optimizer: least-squares (Levenberg–Marquardt) or nelder-mead (multi-start; results/design_speed.md compares them).
    #[arg(long, value_enum, default_value_t = Optimizer::LeastSquares, hide_possible_values = true)]
    pub optimizer: Optimizer,
    /// Model the candidates are played and judged at (the basis and synthesis: full): full (default), paper, frozen, paper+moving, paper+moving+centripetal+tilt, or auto (per candidate the cheapest rung within 2 % of full, recorded in schedule.json's "rungs").
    #[arg(long, value_parser = choices(&MODELS), hide_possible_values = true)]
    pub model: Option<ModelChoice>,
    /// Print the schedule JSON to stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Run even when the work estimate exceeds the limit (10 min at the stated rate; docs/commands.md).
    #[arg(long)]
    pub allow_long: bool,
    /// Do not read or write the basis cache (.platefield-cache/).
    #[arg(long)]
    pub no_cache: bool,
    /// Search the segment order and rest at the joins in closed-loop simulation; writes order.md.
    #[arg(long)]
    pub order_search: bool,
    /// Over the target's friction range, synthesize for the worst case at its ends and middle (three times the simulations).
    #[arg(long)]
    pub robust_synthesis: bool,
    /// Closed loop: judge the schedule, feed its realised field back (orders, contextual re-fit), keep the best; reports the realised error before and after.
    #[arg(long)]
    pub closed_loop: bool,
    /// Closed loop: most contextual re-fit iterations.
    #[arg(long, default_value_t = 8)]
    pub loop_iterations: u32,
}

/// The synthesis and polish optimizer (`--optimizer`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Optimizer {
    /// Levenberg–Marquardt on the residuals.
    LeastSquares,
    /// Multi-start Nelder–Mead.
    NelderMead,
}

impl DesignArgs {
    /// The design options these arguments ask for; errors name the argument and its range.
    pub fn options(&self) -> Result<DesignOptions> {
        let mode = match self.mode {
            Mode::Shape => FitMode::Shape,
            Mode::Absolute => FitMode::Absolute,
            Mode::Budget => {
                if !(self.budget > 0.0 && self.budget < 1.0) {
                    return Err(Error::invalid(
                        "--budget",
                        format!(
                            "must be in (0, 1), got {}",
                            platefield::input::num(self.budget)
                        ),
                    ));
                }
                FitMode::Budget {
                    rel_error: self.budget,
                }
            }
            Mode::L1 => FitMode::L1,
            Mode::Linf => FitMode::LInf,
        };
        if self.min_cycles == 0 {
            return Err(Error::invalid("--min-cycles", "must be ≥ 1"));
        }
        if self.max_primitives == Some(0) {
            return Err(Error::invalid("--max-primitives", "must be ≥ 1"));
        }
        let mut shifts = vec![[0.0, 0.0]];
        shifts.extend(self.shift.iter().copied());
        Ok(DesignOptions {
            basis: BasisSection {
                kind: self.basis,
                shifts,
                rotation_step_deg: self.rotation_step,
                keep_invalid: self.keep_invalid,
                kinds: (self.primitives.clone()).unwrap_or_else(|| PrimitiveKind::ALL.to_vec()),
                cache_dir: (!self.no_cache).then(|| PathBuf::from(".platefield-cache")),
                ..BasisSection::default()
            },
            fit: FitSection {
                mode,
                max_primitives: self.max_primitives,
            },
            schedule: ScheduleSection {
                min_cycles: self.min_cycles,
                total_cycles: self.cycles,
                order_search: self.order_search,
                ..ScheduleSection::default()
            },
            runtime: Runtime {
                quiet: self.quiet,
                allow_long: self.allow_long,
            },
            friction: match (&self.friction, &self.friction_from) {
                (_, Some(path)) => Some(
                    platefield::calibrate::Calibration::load(path)?.friction_spec(self.class)?,
                ),
                (f, None) => f
                    .as_deref()
                    .map(|f| platefield::scene::FrictionSpec::parse_arg(f, "--friction"))
                    .transpose()?,
            },
            model: match self.model {
                None => PlayModel::Own,
                Some(ModelChoice::Model(m)) => PlayModel::Fixed(m),
                Some(ModelChoice::Auto) => PlayModel::Auto {
                    tolerance: platefield::field::rung::DEFAULT_RUNG_TOLERANCE,
                },
            },
            ..DesignOptions::default()
        })
    }

    /// Checks the arguments, designs the schedule and returns the summary to print.
    pub fn run(&self) -> Result<String> {
        let mut opts = self.options()?;
        let loop_opts = LoopOptions {
            max_iterations: self.loop_iterations,
            ..LoopOptions::default()
        };
        loop_opts.validate().map_err(flag_named)?;
        opts.closed_loop = self.closed_loop.then_some(loop_opts);
        if self.synth_evaluations == 0 {
            return Err(Error::invalid("--synth-evaluations", "must be ≥ 1"));
        }
        let mut synth = SynthOptions {
            max_evaluations: self.synth_evaluations,
            polish_plays: self.polish_plays,
            robust_synthesis: self.robust_synthesis,
            // Progress is on stderr, so it is shown whatever stdout
            // carries (--json too); only --quiet silences it.
            progress: opts.runtime.progress(),
            ..SynthOptions::default()
        };
        synth.multistart.seed = self.synth_seed;
        if self.optimizer == Optimizer::NelderMead {
            synth.lm = None;
            synth.polish_lm = None;
        }
        opts.synthesis = synth;
        opts.method = self.method.into();
        report::run_design::run(&self.target, &opts, &self.out, self.json).map_err(flag_named)
    }
}

/// The command-line flag of each option path [`DesignOptions`]' checks
/// name (the library speaks in option paths, the command line in flags).
const FLAGS: [(&str, &str); 8] = [
    ("schedule.total_cycles", "--cycles"),
    ("schedule.min_cycles", "--min-cycles"),
    ("basis.shifts", "--shift"),
    ("basis.rotation_step_deg", "--rotation-step"),
    ("method", "--method"),
    ("closed_loop", "--closed-loop"),
    ("closed_loop.max_iterations", "--loop-iterations"),
    ("model", "--model"),
];

/// `e` with an option path of [`FLAGS`] replaced by its flag.
fn flag_named(e: Error) -> Error {
    match e {
        Error::Invalid { field, message } => {
            let field = FLAGS
                .iter()
                .find(|(path, _)| *path == field)
                .map_or(field, |(_, flag)| flag.to_string());
            Error::Invalid { field, message }
        }
        e => e,
    }
}
