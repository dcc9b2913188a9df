//! `platefield` command-line tool: each subcommand parses its arguments
//! (clap), makes one library call and prints the summary it returns.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use platefield::basis::PrimitiveKind;
use platefield::design::closed_loop::LoopOptions;
use platefield::design::DesignOptions;
use platefield::dynamics::{Friction, Numerics, Preset};
use platefield::field::FieldKind;
use platefield::fit::FitMode;
use platefield::output::write_atomic;
use platefield::studies::{self, linesink::LineSink, linesink::Wave};
use platefield::{report, Error, Result};

#[derive(Parser)]
#[command(
    name = "platefield",
    version,
    about = "Vibration-induced friction fields on a 6-DOF plate: simulate and design"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Design a schedule of primitive plate motions for a target field (the main job).
    Design(DesignArgs),
    /// Export a schedule as the six plate-centre acceleration signals (CSV) at a controller rate.
    Export {
        /// A schedule.json written by `design`.
        schedule: PathBuf,
        /// Samples per second.
        #[arg(long, default_value_t = 10000.0, allow_negative_numbers = true)]
        rate: f64,
        /// Output CSV (default: stdout).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Closed-loop verification: realised field against prediction, and where a swarm of parts ends up.
    Verify(VerifyArgs),
    /// Segment order and rest at the joins: which one best realises a schedule's prediction; writes OUT/<target>/verify/order.md.
    Order {
        /// A schedule.json written by `design`.
        schedule: PathBuf,
        /// Rest cycles tried at every join, comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = platefield::design::order::DEFAULT_REST_CYCLES)]
        rest: Vec<u32>,
        #[command(flatten)]
        play: Play,
        /// Output folder; writes OUT/<target>/verify/order.md.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Compute a force or velocity field from a scene JSON file (motion, friction, grid, model).
    Field {
        /// The scene file (see README, "Scenes").
        scene: PathBuf,
        /// Write the field JSON to this file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write a quiver plot (SVG) to this file.
        #[arg(long)]
        svg: Option<PathBuf>,
        #[command(flatten)]
        json: Json,
        #[command(flatten)]
        quiet: Quiet,
    },
    /// Study: steady-state velocity of a point part on the paper's one-axis LineSink shaker (section II).
    Linesink(LinesinkArgs),
    /// Study: regenerate the section II results: Fig. 3, time-to-travel, convergence.
    #[command(mut_arg("out", default_dir(studies::reproduce::DIR)))]
    Reproduce(StudyOut),
    /// Study: simulate the primitive library; its fields, plots and table1.md (Table I fits).
    #[command(mut_arg("out", default_dir(studies::primitives::DIR)))]
    Primitives {
        /// Grid points per side over ±4 cm.
        #[arg(long, default_value_t = 21)]
        grid: usize,
        #[command(flatten)]
        steps: Steps,
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Study: cheapest model rung within tolerance of the full model, per primitive: rungs.md.
    #[command(mut_arg("out", default_dir(studies::rung::DIR)))]
    Rungs {
        /// Largest accepted relative L2 error against the full model.
        #[arg(long, default_value_t = studies::rung::DEFAULT_RUNG_TOLERANCE, allow_negative_numbers = true)]
        tolerance: f64,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Study: library build time against error over steps per cycle: library_speed.md.
    #[command(mut_arg("out", default_dir(studies::speed::DIR)))]
    Speed(StudyOut),
    /// Study: design every target in targets/ in every fit mode: fit_quality.md.
    #[command(mut_arg("out", default_dir(studies::fit_quality::DIR)))]
    FitQuality(StudyOut),
    /// Study: interaction error of two sequenced LineSinks (a Sink): sink_interaction.md.
    #[command(mut_arg("out", default_dir(studies::interaction::DIR)))]
    Interaction(StudyOut),
    /// Study: SqueezeTrans's squeeze line against segment order, phasing, cycles and rest (the paper's section V): squeeze_trans_order.{md,csv}.
    #[command(mut_arg("out", default_dir(studies::squeeze_order::DIR)))]
    SqueezeOrder(StudyOut),
}

/// How a schedule is played to measure its realised field (`verify`, `order`).
#[derive(Args)]
struct Play {
    /// Start points per side of the N×N grid over the target region (order: over ±3 cm).
    #[arg(long, default_value_t = 5)]
    points: usize,
    /// Schedule periods measured after the warm-up (order: at least, per candidate).
    #[arg(long, default_value_t = 1)]
    periods: u32,
    /// Schedule periods played before measuring (order: at least, and at least 40 primitive cycles).
    #[arg(long, default_value_t = 1)]
    warmup: u32,
    /// Model: the schedule's own (default, normally full), full, paper, or frozen (full with positions frozen: an exact comparison when parts drift far).
    #[arg(long, value_enum)]
    model: Option<Preset>,
}

/// Output folder of a study; its default is the study's `DIR`.
#[derive(Args)]
struct StudyOut {
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
}

/// Sets a study's default output folder.
fn default_dir(dir: &'static str) -> impl FnOnce(clap::Arg) -> clap::Arg {
    move |a| a.default_value(dir).required(false)
}

/// `--json`.
#[derive(Args)]
struct Json {
    /// Print JSON on stdout instead of a summary.
    #[arg(long)]
    json: bool,
}

/// `--quiet`.
#[derive(Args)]
struct Quiet {
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Integrator resolution.
#[derive(Args)]
struct Steps {
    /// RK4 steps per cycle.
    #[arg(long, default_value_t = Numerics::default().steps_per_cycle as u64,
          value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    steps: u64,
}

impl Steps {
    fn numerics(&self) -> Numerics {
        Numerics {
            steps_per_cycle: self.steps as usize,
            ..Numerics::default()
        }
    }
}

/// Fit mode (see [`FitMode`]).
#[derive(Clone, Copy, ValueEnum)]
enum Mode {
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

#[derive(clap::Args)]
struct VerifyArgs {
    /// A schedule.json written by `design`.
    schedule: PathBuf,
    #[command(flatten)]
    play: Play,
    /// Swarm: point parts per side of the N×N grid over the target region.
    #[arg(long, default_value_t = 9)]
    swarm: usize,
    /// Swarm duration in seconds (rounded up to whole schedule periods); default: long enough to converge by the design's strength.
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// Swarm duration in schedule periods.
    #[arg(long)]
    repetitions: Option<u32>,
    /// Convergence tolerance on the distance to the target's attractor (m).
    #[arg(long, default_value_t = 0.003, allow_negative_numbers = true)]
    tol: f64,
    /// Rectangle size LENGTHxWIDTH in metres.
    #[arg(long, default_value = "0.02x0.005")]
    rect: String,
    /// Rectangle start poses (0: no rectangles).
    #[arg(long, default_value_t = 4)]
    rect_poses: usize,
    /// Output folder; writes OUT/<target>/verify/{summary.json, trajectories.svg}.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Print the summary JSON on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct LinesinkArgs {
    /// Angular-acceleration waveform: square (eq. 1, ±α) or sine (ψ'' = A sin ωt).
    #[arg(long, value_enum, default_value_t = Wave::Square)]
    wave: Wave,
    /// α of the square wave, or the sine's amplitude A (rad/s²).
    #[arg(long, allow_negative_numbers = true)]
    accel: f64,
    /// Axis depth below the plate surface (m); negative = above (LineSource).
    #[arg(long, allow_negative_numbers = true)]
    depth: f64,
    /// Period T (s).
    #[arg(long, default_value_t = 0.03, allow_negative_numbers = true)]
    period: f64,
    /// Kinetic friction coefficient μ.
    #[arg(long, default_value_t = 0.3, allow_negative_numbers = true)]
    mu: f64,
    /// Static friction coefficient (default: equal to --mu).
    #[arg(long, allow_negative_numbers = true)]
    mu_static: Option<f64>,
    /// Plate positions from the axis (m), comma separated.
    #[arg(
        long,
        required = true,
        allow_negative_numbers = true,
        value_delimiter = ','
    )]
    r: Vec<f64>,
    /// Model preset: paper (small angle, frozen position, no centripetal/tilt/Coriolis), full, or frozen (full, position frozen).
    #[arg(long, value_enum, default_value_t = Preset::Paper)]
    model: Preset,
    /// The part moves during the cycle (free steady state); implied by --model full.
    #[arg(long)]
    free: bool,
    #[command(flatten)]
    steps: Steps,
    /// Gravity (m/s²).
    #[arg(long, default_value_t = 9.81, allow_negative_numbers = true)]
    gravity: f64,
    #[command(flatten)]
    json: Json,
}

fn linesink(a: &LinesinkArgs) -> Result<String> {
    let ls = LineSink {
        wave: a.wave,
        accel: a.accel,
        depth: a.depth,
        period: a.period,
        friction: Friction {
            stat: a.mu_static.unwrap_or(a.mu),
            kinetic: a.mu,
        },
        gravity: a.gravity,
    };
    let mut model = a.model.model();
    model.moving |= a.free;
    ls.report(&a.r, model, a.steps.numerics(), a.json.json)
}

fn order_cmd(
    schedule: &std::path::Path,
    rest: &[u32],
    play: &Play,
    out: &std::path::Path,
) -> Result<()> {
    print!(
        "{}",
        report::order(
            schedule,
            play.points,
            rest,
            play.warmup,
            play.periods,
            play.model.map(Preset::model),
            out
        )?
    );
    Ok(())
}

/// `--rect LENGTHxWIDTH` (metres).
fn rect_size(text: &str) -> Result<[f64; 2]> {
    let bad = || {
        Error::invalid(
            "--rect",
            format!("expected LENGTHxWIDTH in metres, e.g. 0.02x0.005, got \"{text}\""),
        )
    };
    let (l, w) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let l: f64 = l.trim().parse().map_err(|_| bad())?;
    let w: f64 = w.trim().parse().map_err(|_| bad())?;
    Ok([l, w])
}

fn verify_cmd(args: &VerifyArgs) -> Result<()> {
    use platefield::verify::{Duration, VerifyRequest};
    let model = args.play.model.map(Preset::model);
    let duration = match (args.duration, args.repetitions) {
        (Some(_), Some(_)) => {
            return Err(Error::invalid(
                "--duration",
                "give either --duration or --repetitions, not both",
            ))
        }
        (Some(s), None) => Duration::Seconds(s),
        (None, Some(n)) => Duration::Repetitions(n),
        (None, None) => Duration::Auto,
    };
    let req = VerifyRequest {
        points: args.play.points,
        warmup: args.play.warmup,
        periods: args.play.periods,
        model,
        swarm: args.swarm,
        duration,
        tol: args.tol,
        rectangle: rect_size(&args.rect)?,
        rectangle_poses: args.rect_poses,
    };
    print!(
        "{}",
        report::verify::run(&args.schedule, &req, &args.out, args.json)?
    );
    Ok(())
}

/// `platefield field`: load, compute, then write (nothing is written on bad input).
fn field(
    scene_path: &std::path::Path,
    json: bool,
    out: Option<&std::path::Path>,
    svg: Option<&std::path::Path>,
    quiet: bool,
) -> Result<()> {
    let scene = platefield::scene::Scene::load(scene_path)?;
    let start = std::time::Instant::now();
    let field = scene.compute(quiet).map_err(|e| match e {
        Error::Physical(m) => Error::Physical(format!("{}: {m}", scene_path.display())),
        e => e,
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let mut text = serde_json::to_string_pretty(&field.to_json(&scene.settings()))
        .map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    let stem = scene_path
        .file_stem()
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    if let Some(path) = out {
        write_atomic(path, text.as_bytes())?;
    }
    if let Some(path) = svg {
        write_atomic(path, field.quiver(&scene.title(&stem)).to_svg().as_bytes())?;
    }
    if json {
        print!("{text}");
        return Ok(());
    }
    print!("{}", scene.summary(&field, seconds));
    for path in out.iter().chain(svg.iter()) {
        println!("wrote {}", path.display());
    }
    Ok(())
}

#[derive(clap::Args)]
struct DesignArgs {
    /// Target field JSON (see the README's target schema).
    target: PathBuf,
    /// Fit mode: shape (strongest field of the target's shape), absolute, budget, l1 or linf.
    #[arg(long, value_enum, default_value_t = Mode::Shape)]
    mode: Mode,
    /// Relative error budget for --mode budget, in (0, 1).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    budget: f64,
    /// Use at most this many segments.
    #[arg(long, allow_negative_numbers = true)]
    max_primitives: Option<usize>,
    /// Basis field kind: velocity (steady-state velocity fields, default) or force.
    #[arg(long, value_enum, default_value_t = FieldKind::Velocity)]
    basis: FieldKind,
    /// Rotation step of the basis copies (degrees).
    #[arg(long, default_value_t = 15.0, allow_negative_numbers = true)]
    rotation_step: f64,
    /// Primitive kinds allowed, comma separated (default: all eight).
    #[arg(long, value_enum, value_delimiter = ',')]
    primitives: Option<Vec<PrimitiveKind>>,
    /// Also use basis copies shifted by this horizontal offset "x,y" (m); repeatable.
    #[arg(long, allow_negative_numbers = true, value_parser = xy)]
    shift: Vec<[f64; 2]>,
    /// Keep basis fields that are invalid somewhere in the region (their invalid points are listed in the schedule).
    #[arg(long)]
    keep_invalid: bool,
    /// Minimum cycles per segment.
    #[arg(long, default_value_t = platefield::schedule::DEFAULT_MIN_CYCLES)]
    min_cycles: u32,
    /// Total schedule length in cycles (default: the shortest within the quantisation tolerance).
    #[arg(long)]
    cycles: Option<u32>,
    /// Output folder; files go to OUT/<target name>/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Print the schedule JSON to stdout.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Do not read or write the basis cache (.platefield-cache/).
    #[arg(long)]
    no_cache: bool,
    /// Search the segment order and rest at the joins in closed-loop simulation; writes order.md.
    #[arg(long)]
    order_search: bool,
    /// Closed loop: play the schedule, feed the realised field back (orders, contextual re-fit), keep the best; reports the realised error before and after.
    #[arg(long)]
    closed_loop: bool,
    /// Closed loop: play every N-th target grid point per axis.
    #[arg(long, default_value_t = 2)]
    loop_stride: usize,
    /// Closed loop: most contextual re-fit iterations.
    #[arg(long, default_value_t = 8)]
    loop_iterations: u32,
    /// Closed loop: model the schedules are played with: the design's own (default, normally full), full, paper, or frozen (positions frozen: the local field, for long schedule periods in which parts travel far; not valid with Circle segments).
    #[arg(long, value_enum)]
    loop_model: Option<Preset>,
}

fn design_options(args: &DesignArgs) -> Result<DesignOptions> {
    let mode = match args.mode {
        Mode::Shape => FitMode::Shape,
        Mode::Absolute => FitMode::Absolute,
        Mode::Budget => {
            if !(args.budget > 0.0 && args.budget < 1.0) {
                return Err(Error::invalid(
                    "--budget",
                    format!("must be in (0, 1), got {}", args.budget),
                ));
            }
            FitMode::Budget {
                rel_error: args.budget,
            }
        }
        Mode::L1 => FitMode::L1,
        Mode::Linf => FitMode::LInf,
    };
    let kind = args.basis;
    let kinds = args
        .primitives
        .clone()
        .unwrap_or_else(|| PrimitiveKind::ALL.to_vec());
    if args.min_cycles == 0 {
        return Err(Error::invalid("--min-cycles", "must be ≥ 1"));
    }
    if args.max_primitives == Some(0) {
        return Err(Error::invalid("--max-primitives", "must be ≥ 1"));
    }
    let mut shifts = vec![[0.0, 0.0]];
    shifts.extend(args.shift.iter().copied());
    Ok(DesignOptions {
        mode,
        kind,
        shifts,
        rotation_step_deg: args.rotation_step,
        keep_invalid: args.keep_invalid,
        max_primitives: args.max_primitives,
        min_cycles: args.min_cycles,
        total_cycles: args.cycles,
        kinds,
        cache_dir: (!args.no_cache).then(|| PathBuf::from(".platefield-cache")),
        quiet: args.quiet,
        order_search: args.order_search,
        ..DesignOptions::default()
    })
}

fn design_cmd(args: DesignArgs) -> Result<()> {
    let opts = design_options(&args)?;
    let loop_opts = LoopOptions {
        stride: args.loop_stride,
        max_iterations: args.loop_iterations,
        model: args.loop_model.map(Preset::model),
        ..LoopOptions::default()
    };
    loop_opts.validate()?;
    let closed = args.closed_loop.then_some(&loop_opts);
    print!(
        "{}",
        report::design::run(&args.target, &opts, closed, &args.out, args.json)?
    );
    Ok(())
}

fn export_cmd(schedule: &std::path::Path, rate: f64, out: Option<PathBuf>) -> Result<()> {
    print!("{}", report::export(schedule, rate, out.as_deref())?);
    Ok(())
}

fn run(cli: Cli) -> Result<()> {
    let summary = match cli.command {
        Command::Design(args) => return design_cmd(args),
        Command::Export {
            schedule,
            rate,
            out,
        } => return export_cmd(&schedule, rate, out),
        Command::Verify(args) => return verify_cmd(&args),
        Command::Order {
            schedule,
            rest,
            play,
            out,
        } => return order_cmd(&schedule, &rest, &play, &out),
        Command::Field {
            scene,
            out,
            svg,
            json,
            quiet,
        } => {
            return field(
                &scene,
                json.json,
                out.as_deref(),
                svg.as_deref(),
                quiet.quiet,
            )
        }
        Command::Linesink(args) => linesink(&args)?,
        Command::Reproduce(o) => studies::reproduce::linesink_results(&o.out)?,
        Command::Primitives {
            grid,
            steps,
            quiet,
            out,
        } => studies::primitives::run(
            &out.out,
            grid,
            steps.numerics().steps_per_cycle,
            quiet.quiet,
        )?,
        Command::Rungs { tolerance, out } => studies::rung::run(&out.out, tolerance)?,
        Command::Speed(o) => studies::speed::run(&o.out)?,
        Command::FitQuality(o) => studies::fit_quality::run(Path::new("targets"), &o.out)?,
        Command::Interaction(o) => studies::interaction::run(&o.out)?,
        Command::SqueezeOrder(o) => studies::squeeze_order::run(&o.out)?,
    };
    print!("{summary}");
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
