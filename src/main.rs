//! `platefield` command-line tool: a thin shell over the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use platefield::basis::report::write_primitives;
use platefield::basis::Library;
use platefield::dynamics::{Friction, Model, Numerics};
use platefield::field::{FieldSettings, Grid};
use platefield::linesink::LineSink;
use platefield::{reproduce, Error, Result};

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
    /// Steady-state velocity of a point part on the paper's one-axis LineSink shaker (section II).
    Linesink(LinesinkArgs),
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

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Linesink(args) => linesink(args),
        Command::Reproduce { out } => reproduce::linesink_results(&out),
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
