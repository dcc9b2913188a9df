//! `platefield` command-line tool: a thin shell over the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use platefield::basis::report::write_primitives;
use platefield::basis::Library;
use platefield::basis::PrimitiveKind;
use platefield::design::closed_loop::LoopOptions;
use platefield::design::quality::write_fit_quality;
use platefield::design::DesignOptions;
use platefield::dynamics::{Friction, Model, Numerics};
use platefield::field::FieldKind;
use platefield::field::{FieldSettings, Grid};
use platefield::fit::FitMode;
use platefield::linesink::LineSink;
use platefield::{report, reproduce, Error, Result};

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
        #[arg(long, default_value_t = 10000.0)]
        rate: f64,
        /// Output CSV (default: stdout).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Design every target in targets/ in every fit mode; write results/fit_quality.md.
    FitQuality {
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Steady-state velocity of a point part on the paper's one-axis LineSink shaker (section II).
    Linesink(LinesinkArgs),
    /// Compute a force or velocity field from a scene JSON file (motion, friction, grid, model).
    Field {
        /// The scene file (see README, "Scenes").
        scene: PathBuf,
        /// Print the field JSON on stdout instead of a summary.
        #[arg(long)]
        json: bool,
        /// Write the field JSON to this file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write a quiver plot (SVG) to this file.
        #[arg(long)]
        svg: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Simulate the primitive library and write results/primitives/ (fields, plots, table1.md).
    Primitives {
        /// Output directory.
        #[arg(long, default_value = "results/primitives")]
        out: PathBuf,
        /// Grid points per side over ±4 cm.
        #[arg(long, default_value_t = 21)]
        grid: usize,
        /// RK4 steps per cycle.
        #[arg(long, default_value_t = FieldSettings::default().numerics.steps_per_cycle)]
        steps: usize,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Regenerate the section II results in results/: Fig. 3, time-to-travel, convergence.
    Reproduce {
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Cheapest model rung within tolerance of the full model, per primitive: writes rungs.md.
    Rungs {
        /// Largest accepted relative L2 error against the full model.
        #[arg(
            long,
            default_value_t = platefield::basis::rung::DEFAULT_RUNG_TOLERANCE,
            allow_negative_numbers = true
        )]
        tolerance: f64,
        /// Output directory.
        #[arg(long, default_value = "results/primitives")]
        out: PathBuf,
    },
    /// Library build time against error over steps per cycle: writes library_speed.md.
    Speed {
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Closed-loop verification: realised field against prediction, and where a swarm of parts ends up.
    Verify(VerifyArgs),
    /// Interaction error of two sequenced LineSinks (DESIGN.md section 6): writes results/verify/sink_interaction.md.
    Interaction {
        /// Output directory.
        #[arg(long, default_value = "results/verify")]
        out: PathBuf,
    },
    /// Segment order and rest at the joins: which one best realises a schedule's prediction; writes OUT/<target>/verify/order.md.
    Order {
        /// A schedule.json written by `design`.
        schedule: PathBuf,
        /// Start points per side of the N×N grid over ±3 cm.
        #[arg(long, default_value_t = 5)]
        points: usize,
        /// Rest cycles tried at every join, comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = platefield::design::order::DEFAULT_REST_CYCLES)]
        rest: Vec<u32>,
        /// Minimum schedule periods measured per candidate.
        #[arg(long, default_value_t = 1)]
        periods: u32,
        /// Minimum warm-up periods per candidate (at least 40 primitive cycles are always played).
        #[arg(long, default_value_t = 1)]
        warmup: u32,
        /// Model: the schedule's own (default, normally full), full, paper, or frozen.
        #[arg(long)]
        model: Option<String>,
        /// Output folder; writes OUT/<target>/verify/order.md.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// SqueezeTrans's squeeze line against segment order, phasing, cycles and rest (the paper's section V): writes squeeze_trans_order.{md,csv}.
    SqueezeOrder {
        /// Output directory.
        #[arg(long, default_value = "results/verify")]
        out: PathBuf,
    },
}

#[derive(clap::Args)]
struct VerifyArgs {
    /// A schedule.json written by `design`.
    schedule: PathBuf,
    /// Realised-field grid: start points per side of the N×N grid over the target region.
    #[arg(long, default_value_t = 5)]
    points: usize,
    /// Schedule periods measured (after the warm-up).
    #[arg(long, default_value_t = 1)]
    periods: u32,
    /// Schedule periods played before measuring.
    #[arg(long, default_value_t = 1)]
    warmup: u32,
    /// Model: the schedule's own (default, normally full), full, paper, or frozen (full with positions frozen: an exact comparison when parts drift far).
    #[arg(long)]
    model: Option<String>,
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

#[derive(clap::Args)]
struct LinesinkArgs {
    /// Angular-acceleration waveform: square (eq. 1, ±α) or sine (ψ'' = A sin ωt).
    #[arg(long, default_value = "square")]
    wave: String,
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
    #[arg(long, allow_negative_numbers = true)]
    r: String,
    /// Model preset: paper (small angle, frozen position, no centripetal/tilt/Coriolis) or full.
    #[arg(long, default_value = "paper")]
    model: String,
    /// The part moves during the cycle (free steady state); implied by --model full.
    #[arg(long)]
    free: bool,
    /// RK4 steps per cycle.
    #[arg(long, default_value_t = Numerics::default().steps_per_cycle)]
    steps: usize,
    /// Gravity (m/s²).
    #[arg(long, default_value_t = 9.81)]
    gravity: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

fn parse_list(field: &str, text: &str) -> Result<Vec<f64>> {
    let items: Vec<&str> = text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    if items.is_empty() {
        return Err(Error::invalid(field, "must list at least one number"));
    }
    items
        .iter()
        .map(|s| {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| Error::invalid(field, format!("\"{s}\" is not a finite number")))
        })
        .collect()
}

fn linesink(args: LinesinkArgs) -> Result<()> {
    let ls = LineSink {
        wave: args.wave.parse()?,
        accel: args.accel,
        depth: args.depth,
        period: args.period,
        friction: Friction {
            stat: args.mu_static.unwrap_or(args.mu),
            kinetic: args.mu,
        },
        gravity: args.gravity,
    };
    ls.validate()?;
    let rs = parse_list("--r", &args.r)?;
    let mut model = Model::preset(&args.model, "--model")?;
    model.moving |= args.free;
    let numerics = Numerics {
        steps_per_cycle: args.steps,
        ..Numerics::default()
    };
    numerics.validate("--steps").map_err(|_| {
        Error::invalid(
            "--steps",
            format!("must be in 1..=1000000, got {}", args.steps),
        )
    })?;
    let rows = ls.rows(&rs, model, numerics);
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).map_err(|e| Error::Physical(e.to_string()))?
        );
        return Ok(());
    }
    println!(
        "LineSink: {:?} wave, accel {} rad/s², depth {} m, T {} s, μ_k {}, μ_s {}, model {}",
        ls.wave,
        ls.accel,
        ls.depth,
        ls.period,
        ls.friction.kinetic,
        ls.friction.stat,
        model.name()
    );
    if let Some(edge) = ls.deadband_edge() {
        println!("stick deadband: |r| ≤ {edge:.6} m");
    }
    println!(
        "{:>10} {:>14} {:>14} {:>8}  note",
        "r (m)", "v_ss (m/s)", "eq17 (m/s)", "stuck"
    );
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.6e}"));
    for row in rows {
        println!(
            "{:>10.5} {:>14} {:>14} {:>8}  {}",
            row.r,
            opt(row.v_ss),
            opt(row.eq17),
            row.stick_fraction.map_or("-".into(), |s| format!("{s:.3}")),
            row.error.unwrap_or_default()
        );
    }
    Ok(())
}

fn primitives(out: &std::path::Path, n: usize, steps: usize, quiet: bool) -> Result<()> {
    let grid = Grid {
        n: [n, n],
        ..Grid::DEFAULT
    };
    grid.validate("--grid")?;
    let mut settings = FieldSettings::default();
    settings.numerics.steps_per_cycle = steps;
    settings.numerics.validate("--steps")?;
    let start = std::time::Instant::now();
    let lib = Library::build(&Library::default_primitives(), &grid, &settings, quiet);
    let elapsed = start.elapsed().as_secs_f64();
    let table = write_primitives(&lib, out)?;
    print!("{table}");
    println!(
        "
built {} primitives × 2 fields on {}×{} in {elapsed:.2} s; wrote {}",
        lib.entries.len(),
        n,
        n,
        out.display()
    );
    Ok(())
}

fn rungs(out: &std::path::Path, tolerance: f64) -> Result<()> {
    use platefield::basis::rung;
    platefield::error::non_negative("--tolerance", tolerance)?;
    let reports = rung::default_reports(tolerance);
    print!("{}", rung::write_reports(out, &reports, tolerance)?);
    print!("\n{}", rung::times_table(&reports));
    println!("wrote {}", out.join("rungs.md").display());
    Ok(())
}

/// A model override for playing schedules: full, paper, or frozen (full with positions frozen).
fn played_model(name: Option<&str>, flag: &str) -> Result<Option<Model>> {
    Ok(match name {
        None => None,
        Some("frozen") => Some(platefield::verify::interaction::FROZEN),
        Some(name) => Some(Model::preset(name, flag).map_err(|_| {
            Error::invalid(
                flag,
                format!("unknown model \"{name}\" (expected full, paper or frozen)"),
            )
        })?),
    })
}

fn order_cmd(
    schedule: &std::path::Path,
    points: usize,
    rest: &[u32],
    periods: u32,
    warmup: u32,
    model: Option<&str>,
    out: &std::path::Path,
) -> Result<()> {
    let model = played_model(model, "--model")?;
    print!(
        "{}",
        report::order(schedule, points, rest, warmup, periods, model, out)?
    );
    Ok(())
}

fn squeeze_order_cmd(out: &std::path::Path) -> Result<()> {
    let start = std::time::Instant::now();
    print!("{}", platefield::verify::squeeze_order_report(out)?);
    println!(
        "wrote {} and {} ({:.1} s)",
        out.join("squeeze_trans_order.md").display(),
        out.join("squeeze_trans_order.csv").display(),
        start.elapsed().as_secs_f64()
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
    let model = played_model(args.model.as_deref(), "--model")?;
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
        points: args.points,
        warmup: args.warmup,
        periods: args.periods,
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

fn interaction_cmd(out: &std::path::Path) -> Result<()> {
    print!("{}", platefield::verify::interaction_table(out)?);
    println!("wrote {}", out.join("sink_interaction.md").display());
    Ok(())
}

fn speed(out: &std::path::Path) -> Result<()> {
    print!("{}", platefield::basis::speed::library_speed(out)?);
    println!("wrote {}", out.join("library_speed.md").display());
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
    use platefield::output::write_atomic;
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
    #[arg(long, default_value = "shape")]
    mode: String,
    /// Relative error budget for --mode budget, in (0, 1).
    #[arg(long, default_value_t = 0.05)]
    budget: f64,
    /// Use at most this many segments.
    #[arg(long)]
    max_primitives: Option<usize>,
    /// Basis field kind: velocity (steady-state velocity fields, default) or force.
    #[arg(long, default_value = "velocity")]
    basis: String,
    /// Rotation step of the basis copies (degrees).
    #[arg(long, default_value_t = 15.0)]
    rotation_step: f64,
    /// Primitive kinds allowed, comma separated (default: all eight).
    #[arg(long)]
    primitives: Option<String>,
    /// Also use basis copies shifted by this horizontal offset "x,y" (m); repeatable.
    #[arg(long, allow_negative_numbers = true)]
    shift: Vec<String>,
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
    #[arg(long)]
    loop_model: Option<String>,
}

fn design_options(args: &DesignArgs) -> Result<DesignOptions> {
    let mode = match args.mode.as_str() {
        "shape" => FitMode::Shape,
        "absolute" => FitMode::Absolute,
        "budget" => {
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
        "l1" => FitMode::L1,
        "linf" | "l_inf" => FitMode::LInf,
        other => {
            return Err(Error::invalid(
                "--mode",
                format!("unknown mode \"{other}\" (expected shape, absolute, budget, l1 or linf)"),
            ))
        }
    };
    let kind = match args.basis.as_str() {
        "velocity" => FieldKind::Velocity,
        "force" => FieldKind::Force,
        other => {
            return Err(Error::invalid(
                "--basis",
                format!("unknown basis \"{other}\" (expected velocity or force)"),
            ))
        }
    };
    let kinds = match &args.primitives {
        None => PrimitiveKind::ALL.to_vec(),
        Some(list) => list
            .split(',')
            .map(|s| PrimitiveKind::from_name(s.trim(), "--primitives"))
            .collect::<Result<Vec<_>>>()?,
    };
    if args.min_cycles == 0 {
        return Err(Error::invalid("--min-cycles", "must be ≥ 1"));
    }
    if args.max_primitives == Some(0) {
        return Err(Error::invalid("--max-primitives", "must be ≥ 1"));
    }
    let mut shifts = vec![[0.0, 0.0]];
    for text in &args.shift {
        let v = parse_list("--shift", text)?;
        if v.len() != 2 {
            return Err(Error::invalid(
                "--shift",
                format!("must be two numbers \"x,y\" in metres, got \"{text}\""),
            ));
        }
        shifts.push([v[0], v[1]]);
    }
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
        model: played_model(args.loop_model.as_deref(), "--loop-model")?,
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

fn fit_quality_cmd(out: &std::path::Path) -> Result<()> {
    let mut targets: Vec<PathBuf> = std::fs::read_dir("targets")
        .map_err(|e| Error::Io {
            path: "targets".into(),
            source: e,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    targets.sort();
    let md = write_fit_quality(&targets, &DesignOptions::default(), out)?;
    print!("{md}");
    Ok(())
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Design(args) => design_cmd(args),
        Command::Export {
            schedule,
            rate,
            out,
        } => export_cmd(&schedule, rate, out),
        Command::FitQuality { out } => fit_quality_cmd(&out),
        Command::Linesink(args) => linesink(args),
        Command::Field {
            scene,
            json,
            out,
            svg,
            quiet,
        } => field(&scene, json, out.as_deref(), svg.as_deref(), quiet),
        Command::Reproduce { out } => reproduce::linesink_results(&out),
        Command::Rungs { tolerance, out } => rungs(&out, tolerance),
        Command::Speed { out } => speed(&out),
        Command::Verify(args) => verify_cmd(&args),
        Command::Interaction { out } => interaction_cmd(&out),
        Command::Order {
            schedule,
            points,
            rest,
            periods,
            warmup,
            model,
            out,
        } => order_cmd(
            &schedule,
            points,
            &rest,
            periods,
            warmup,
            model.as_deref(),
            &out,
        ),
        Command::SqueezeOrder { out } => squeeze_order_cmd(&out),
        Command::Primitives {
            out,
            grid,
            steps,
            quiet,
        } => primitives(&out, grid, steps, quiet),
    }
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
