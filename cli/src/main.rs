//! `platefield` command-line tool: each subcommand parses its arguments
//! (clap), makes one library call and prints the summary it returns.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use platefield_cli as cli;

use cli::{AllowLong, Json, Play, Quiet, Steps};
use platefield::basis::StepsPlan;
use platefield::design::order::OrderRequest;
use platefield::work::Runtime;
use platefield::Result;
use platefield_report as report;
use platefield_studies as studies;
use platefield_studies::work::Expected;

#[derive(Parser)]
#[command(
    name = "platefield",
    version,
    about = "Vibration-induced friction fields on a 6-DOF plate: simulate and design",
    term_width = 0
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Design a schedule of primitive plate motions for a target field (the main job).
    Design(cli::design::DesignArgs),
    /// Export a schedule for a shaker controller: the six plate-centre acceleration signals as CSV samples, or each channel's harmonics.
    Export(cli::export::ExportArgs),
    /// Closed-loop verification: the judge, the model check (moving parts against the prediction), and where a swarm of parts ends up.
    Verify(cli::verify::VerifyArgs),
    /// Segment order and rest at the joins: which one best realises a schedule's prediction; writes OUT/<target>/verify/order.md.
    Order {
        /// A schedule.json written by `design`.
        schedule: PathBuf,
        /// Rest cycles tried at every join, comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = platefield::design::order::DEFAULT_REST_CYCLES)]
        rest: Vec<u32>,
        #[command(flatten)]
        play: Play,
        /// Output folder; writes OUT/<target>/verify/order.md (the default `out/` is ignored by git).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        long: AllowLong,
        #[command(flatten)]
        quiet: Quiet,
    },
    /// Compute a force or velocity field from a scene JSON file (motion, friction, grid, model).
    Field {
        /// The scene file (its schema: docs/scenes.md).
        scene: PathBuf,
        /// Write the field JSON to this file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write a quiver plot (SVG) to this file.
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Model, overriding the scene's: paper, full, frozen, a rung between them (paper+moving, paper+moving+centripetal+tilt), or auto (the cheapest rung within 2 % of full on 5×5 sample points of the grid, recorded under "rung").
        #[arg(long, value_parser = cli::values::choices(&cli::values::MODELS), hide_possible_values = true)]
        model: Option<cli::values::ModelChoice>,
        #[command(flatten)]
        json: Json,
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        long: AllowLong,
    },
    /// Equilibrium poses and continua of rest of a part with planar extent in a target's, scene's or schedule's field, their stability and basins.
    Poses(cli::poses::PosesArgs),
    /// Friction from camera tracks: μ_s, μ_k (and --scale, the delivered amplitude) with 95 % intervals from parts observed under a played schedule; JSON on stdout, report.md and plots in --out (--simulate: synthetic tracks).
    Calibrate(cli::calibrate::CalibrateArgs),
    /// Laboratory studies: the paper's results reproduced, model rungs, speed and accuracy; each regenerates its files in results/.
    #[command(subcommand)]
    Study(Study),
}

/// The laboratory's studies (`platefield study <name>`).
#[derive(Subcommand)]
enum Study {
    /// Steady-state velocity of a point part on the paper's one-axis LineSink shaker (section II).
    Linesink(cli::linesink::LinesinkArgs),
    /// Regenerate the section II results: Fig. 3, time-to-travel, convergence.
    #[command(mut_arg("out", default_dir(studies::reproduce::DIR)))]
    Reproduce(StudyOut),
    /// Simulate the primitive library; its fields, plots and table1.md (Table I fits).
    #[command(mut_arg("out", default_dir(studies::primitives::DIR)))]
    Primitives {
        /// Grid points per side over ±4 cm.
        #[arg(long, default_value_t = 21)]
        grid: usize,
        #[command(flatten)]
        steps: Steps,
        /// Force fields at each primitive's calibrated steps per cycle (the
        /// fewest within 1e-4 of 512 steps; on the default grid, where they
        /// were measured, whatever --steps says); velocity fields at --steps.
        #[arg(long)]
        calibrated: bool,
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// The shipped parts' equilibrium poses and basins on the designed elliptic sinks: poses.md.
    #[command(mut_arg("out", default_dir(studies::poses::DIR)))]
    Poses {
        /// Also play this many drops per part and ellipse with the planar simulator (slow: minutes per part).
        #[arg(long, default_value_t = 0)]
        play_drops: usize,
        #[command(flatten)]
        out: StudyOut,
    },
    /// The shipped pose designs played at their part's friction ±20 % (μ 0.24, 0.30, 0.36; minutes of CPU): poses_friction.md.
    #[command(mut_arg("out", default_dir(studies::poses_friction::DIR)))]
    PosesFriction(StudyOut),
    /// Pose design over a seeded family of random parts (polygons, brackets, rectangles; each with its own friction and asked pose), played at μ ± 20 %: pose_family.md and the members' files in pose_family/ (minutes of CPU per part; CPU seconds printed only).
    #[command(mut_arg("out", default_dir(studies::pose_family::DIR)))]
    PoseFamily {
        /// Parts in the family (the kinds in their shares).
        #[arg(long, default_value_t = studies::pose_family::COUNT as u64, value_parser = clap::value_parser!(u64).range(1..=100))]
        count: u64,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Cheapest model rung within tolerance of the full model, per primitive: rungs.md.
    #[command(mut_arg("out", default_dir(studies::rung::DIR)))]
    Rungs {
        /// Largest accepted relative L2 error against the full model.
        #[arg(long, default_value_t = platefield::field::rung::DEFAULT_RUNG_TOLERANCE, allow_negative_numbers = true)]
        tolerance: f64,
        #[command(flatten)]
        out: StudyOut,
    },
    /// The automatic model rung (verify --model auto) of every shipped design's segments, from results/*/schedule.json: rungs_auto.md (times printed only).
    #[command(mut_arg("out", default_dir(studies::rungs_auto::DIR)))]
    RungsAuto {
        /// Largest accepted relative L2 error against the full model.
        #[arg(long, default_value_t = platefield::field::rung::DEFAULT_RUNG_TOLERANCE, allow_negative_numbers = true)]
        tolerance: f64,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Library build time against error over steps per cycle: library_speed.md.
    #[command(mut_arg("out", default_dir(studies::speed::DIR)))]
    Speed(StudyOut),
    /// Every primitive's force and velocity field error against steps per cycle and time: engine_speed.{md,csv,svg}.
    #[command(mut_arg("out", default_dir(studies::engine_speed::DIR)))]
    EngineSpeed(StudyOut),
    /// Design every target in targets/ in every fit mode: fit_quality.md.
    #[command(mut_arg("out", default_dir(studies::fit_quality::DIR)))]
    FitQuality(StudyOut),
    /// Interaction error of two sequenced LineSinks (a Sink): sink_interaction.md.
    #[command(mut_arg("out", default_dir(studies::interaction::DIR)))]
    Interaction(StudyOut),
    /// Designs for μ 0.3 against designs robust over μ ∈ [0.2, 0.4], each played at μ 0.2–0.4; single-μ designs at 0.15 and 0.6: robust.md.
    #[command(mut_arg("out", default_dir(studies::robust::DIR)))]
    Robust {
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// The shipped targets that state their own friction range, designed by auto over it, played at 5 frictions over it and their exports replayed: robust_shipped.md (under a minute of CPU per target).
    #[command(mut_arg("out", default_dir(studies::robust_shipped::DIR)))]
    RobustShipped {
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Robust design (auto over each target's friction range) against the nominal design (auto at the range's middle), on a seeded family of random targets, both judged over the range: robust_family.md (CPU seconds printed only; about a minute of CPU per target).
    #[command(mut_arg("out", default_dir(studies::robust_family::DIR)))]
    RobustFamily {
        /// Targets in the family (the kinds in their shares).
        #[arg(long, default_value_t = studies::robust_family::COUNT as u64, value_parser = clap::value_parser!(u64).range(1..=400))]
        count: u64,
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// The robust share's knobs on the family's mirror-symmetric members: the segment length and the frictions judged, against the worst shape over the range and the judge's work: robust_knobs.md (CPU seconds printed only).
    #[command(mut_arg("out", default_dir(studies::robust_knobs::DIR)))]
    RobustKnobs {
        /// Members (the first of the family that a reflection maps to themselves; at most 28).
        #[arg(long, default_value_t = studies::robust_knobs::MEMBERS as u64, value_parser = clap::value_parser!(u64).range(1..=studies::robust_knobs::MEMBERS as u64))]
        count: u64,
        #[command(flatten)]
        quiet: Quiet,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Every shipped target designed (auto) under several synthesis and polish budgets: design_speed.md (times printed only).
    #[command(mut_arg("out", default_dir(studies::design_speed::DIR)))]
    DesignSpeed {
        /// Only these targets (comma-separated names under targets/).
        #[arg(long, value_delimiter = ',')]
        targets: Vec<String>,
        #[command(flatten)]
        out: StudyOut,
    },
    /// One synthesized six-signal motion per target against its sequenced schedule, both judged: synthesis.{md,csv}.
    #[command(mut_arg("out", default_dir(studies::synthesis::DIR)))]
    Synthesis {
        /// Only these rows (comma-separated: sink, saddle, whirlpool, squeeze_trans, line_sink_30, lab, refine:whirlpool, refine:squeeze_trans).
        #[arg(long, value_delimiter = ',')]
        rows: Vec<String>,
        /// Harmonics of 2π/T the sequenced rows' syntheses may use.
        #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=16))]
        harmonics: u32,
        /// Coarse evaluations per synthesis.
        #[arg(long, default_value_t = 300, value_parser = clap::value_parser!(u64).range(1..=100_000))]
        evaluations: u64,
        /// Multi-start starts per synthesis.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
        starts: u64,
        /// Plays of the played polish of each row's kept motion (0: none).
        #[arg(long, default_value_t = 300, value_parser = clap::value_parser!(u64).range(0..=100_000))]
        polish_plays: u64,
        #[command(flatten)]
        out: StudyOut,
    },
    /// Sorting by friction against the friction contrast (μ ratio 1.25-3, sinks 3 cm apart) and the sinks' distance (1, 2, 4 cm at ratio 2), each designed and played as `design` does a classes target: sort.md (most of an hour of CPU; CPU seconds printed only).
    #[command(mut_arg("out", default_dir(studies::sort::DIR)))]
    Sort(StudyOut),
    /// The measurements behind numbers the docs state (the saddle's margin cap, the ratchet, the lag, the saddle's parts, single fields): probes.md (timings printed only).
    #[command(mut_arg("out", default_dir(studies::probes::DIR)))]
    Probes(StudyOut),
    /// SqueezeTrans's squeeze line against segment order, phasing, cycles and rest (the paper's section V): squeeze_trans_order.{md,csv}.
    #[command(mut_arg("out", default_dir(studies::squeeze_order::DIR)))]
    SqueezeOrder(StudyOut),
    /// A linear feeder: a point part's conveying speed against the throw number (0.5-3) and the phase between the track's two vibrations, at μ 0.2, 0.3 and 0.5, set against the classic throw-conveyor theory: feeder.md.
    #[command(mut_arg("out", default_dir(studies::feeder::DIR)))]
    Feeder(StudyOut),
    /// Designs that may fly: the sink's and the saddle's realised strength at a judged shape error of at most 5 %, in contact against brief flight (at most 10 % of the cycle airborne, judged with the flight rung): flight_strength.md.
    #[command(mut_arg("out", default_dir(studies::flight_strength::DIR)))]
    FlightStrength(StudyOut),
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

/// `order`'s request from its arguments.
fn order_request(
    rest: Vec<u32>,
    play: &Play,
    long: &AllowLong,
    quiet: &Quiet,
) -> platefield::Result<OrderRequest> {
    Ok(OrderRequest {
        n: play.points,
        rest_cycles: rest,
        warmup: play.warmup,
        periods: play.periods,
        model: play.fixed_model("order")?,
        runtime: Runtime {
            quiet: quiet.quiet,
            allow_long: long.allow_long,
        },
    })
}

/// The synthesis study's settings from its arguments (evaluations, starts,
/// polish plays).
fn synthesis_settings(
    harmonics: u32,
    [evaluations, starts, plays]: [u64; 3],
) -> studies::synthesis::StudySettings {
    studies::synthesis::StudySettings {
        harmonics,
        evaluations: evaluations as usize,
        starts: starts as usize,
        polish_plays: plays as usize,
    }
}

fn run(cli: Cli) -> Result<String> {
    match cli.command {
        Command::Design(args) => args.run(),
        Command::Export(args) => args.run(),
        Command::Verify(args) => args.run(),
        Command::Calibrate(args) => args.run(),
        Command::Order {
            schedule,
            rest,
            play,
            out,
            long,
            quiet,
        } => order_request(rest, &play, &long, &quiet)
            .and_then(|req| report::order(&schedule, &req, &out)),
        Command::Field {
            scene,
            out,
            svg,
            model,
            json,
            quiet,
            long,
        } => cli::field::run(
            &scene,
            json.json,
            out.as_deref(),
            svg.as_deref(),
            quiet.quiet,
            long.allow_long,
            model,
        ),
        Command::Poses(args) => args.run(),
        Command::Study(study) => run_study(study),
    }
}

/// Runs one of the laboratory's studies.
fn run_study(study: Study) -> Result<String> {
    match study {
        Study::Linesink(args) => args.run(),
        Study::Reproduce(o) => studies::watched_defaults("reproduce", false, || {
            studies::reproduce::linesink_results(&o.out)
        }),
        Study::Primitives {
            grid,
            steps,
            calibrated,
            quiet,
            out,
        } => {
            let plan = if calibrated {
                StepsPlan::Calibrated
            } else {
                StepsPlan::Uniform
            };
            let steps = steps.numerics().steps_per_cycle;
            let factor = studies::primitives::work_factor(grid, steps, plan);
            let expected = Expected::scaled("primitives", factor, "grid and steps");
            studies::watched("primitives", expected, quiet.quiet, || {
                studies::primitives::run(&out.out, grid, steps, plan, quiet.quiet)
            })
        }
        Study::Poses { play_drops, out } => {
            let drops = studies::poses::played_drops_estimate(play_drops)?;
            let expected = Expected::defaults("poses-study")
                .map(|e| e.plus(drops, platefield::work::PLANAR_POINT_STEP_COST));
            studies::watched("poses-study", expected, false, || {
                studies::poses::run(&out.out, play_drops)
            })
        }
        Study::PoseFamily { count, out } => {
            // A member's work taken as the family's mean: the recorded
            // count scaled by the members asked for.
            let share = count as f64 / studies::pose_family::COUNT as f64;
            let expected =
                studies::work::Expected::scaled("pose-family", share, "of the family's members");
            studies::watched("pose-family", expected, false, || {
                studies::pose_family::run(&out.out, count as usize)
            })
        }
        Study::PosesFriction(o) => studies::watched_defaults("poses-friction-study", false, || {
            studies::poses_friction::run(&o.out)
        }),
        Study::RungsAuto { tolerance, out } => {
            // Every rung is computed whatever the tolerance: the same work.
            studies::watched_defaults("rungs-auto", false, || {
                studies::rungs_auto::run(Path::new(studies::rungs_auto::DIR), &out.out, tolerance)
            })
        }
        Study::Rungs { tolerance, out } => {
            // Every rung is computed whatever the tolerance: the same work.
            studies::watched_defaults("rungs", false, || studies::rung::run(&out.out, tolerance))
        }
        Study::Speed(o) => {
            studies::watched_defaults("speed", false, || studies::speed::run(&o.out))
        }
        Study::EngineSpeed(o) => {
            studies::watched_defaults("engine-speed", false, || studies::engine_speed::run(&o.out))
        }
        Study::FitQuality(o) => studies::watched_defaults("fit-quality", false, || {
            studies::fit_quality::run(Path::new("targets"), &o.out)
        }),
        Study::Interaction(o) => {
            studies::watched_defaults("interaction", false, || studies::interaction::run(&o.out))
        }
        Study::Robust { quiet, out } => studies::watched_defaults("robust", quiet.quiet, || {
            studies::robust::run(&out.out, quiet.quiet)
        }),
        Study::RobustShipped { quiet, out } => {
            studies::watched_defaults("robust-shipped", quiet.quiet, || {
                studies::robust_shipped::run(&out.out, quiet.quiet)
            })
        }
        Study::RobustFamily { count, quiet, out } => {
            // A member's work taken as the family's mean: the recorded
            // count scaled by the members asked for.
            let share = count as f64 / studies::robust_family::COUNT as f64;
            let expected =
                studies::work::Expected::scaled("robust-family", share, "of the family's members");
            studies::watched("robust-family", expected, quiet.quiet, || {
                studies::robust_family::run(&out.out, count as usize, quiet.quiet)
            })
        }
        Study::RobustKnobs { count, quiet, out } => {
            let expected = studies::work::Expected::scaled(
                "robust-knobs",
                count as f64 / studies::robust_knobs::MEMBERS as f64,
                "of the family's mirror-symmetric members",
            );
            studies::watched("robust-knobs", expected, quiet.quiet, || {
                studies::robust_knobs::run(&out.out, count as usize, quiet.quiet)
            })
        }
        Study::Sort(o) => studies::watched_defaults("sort", false, || studies::sort::run(&o.out)),
        Study::Probes(o) => {
            studies::watched_defaults("probes", false, || studies::probes::run(&o.out))
        }
        Study::Feeder(o) => {
            studies::watched_defaults("feeder", false, || studies::feeder::run(&o.out))
        }
        Study::FlightStrength(o) => studies::watched_defaults("flight-strength", false, || {
            studies::flight_strength::run(&o.out)
        }),
        Study::SqueezeOrder(o) => studies::watched_defaults("squeeze-order", false, || {
            studies::squeeze_order::run(&o.out)
        }),
        Study::DesignSpeed { targets, out } => {
            let expected = if targets.is_empty() {
                Expected::defaults("design-speed")
            } else {
                Some(Expected::estimated(
                    studies::design_speed::estimate(&targets)?,
                    1.0,
                ))
            };
            studies::watched("design-speed", expected, false, || {
                studies::design_speed::run(&out.out, &targets)
            })
        }
        Study::Synthesis {
            rows,
            harmonics,
            evaluations,
            starts,
            polish_plays,
            out,
        } => {
            let study = synthesis_settings(harmonics, [evaluations, starts, polish_plays]);
            let expected = studies::synthesis::expected(&rows, &study)?;
            studies::watched("synthesis", expected, false, || {
                studies::synthesis::run(&out.out, &rows, &study)
            })
        }
    }
}

fn main() -> ExitCode {
    platefield::output::remove_stages_on_interrupt();
    match run(Cli::parse()) {
        Ok(summary) => print_summary(&summary),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Prints `summary` on stdout. A reader that closed the pipe early
/// (`platefield export S | head -2`) has all it wanted: the program ends
/// quietly with success. Any other write error is reported (exit 2).
fn print_summary(summary: &str) -> ExitCode {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(summary.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: stdout: {e}");
            ExitCode::from(2)
        }
    }
}
