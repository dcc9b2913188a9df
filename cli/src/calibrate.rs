//! `platefield calibrate`: friction from camera tracks, and with
//! `--simulate` synthetic tracks by the exact simulator.

use std::path::PathBuf;

use clap::Args;

use platefield::calibrate::{simulate_tracks, CalibrateOptions, TrackSimulation};
use platefield::dynamics::Friction;
use platefield::schedule::Schedule;
use platefield::{Error, Result};
use platefield_report as report;

/// Arguments of `platefield calibrate`.
#[derive(Args)]
pub struct CalibrateArgs {
    /// The schedule.json that was played.
    pub schedule: PathBuf,
    /// Camera tracks: CSV with the header t_s,part,x_m,y_m (theta_rad optional), t = 0 where the schedule's first period starts, positions in the plate frame.
    #[arg(required_unless_present = "simulate")]
    pub tracks: Option<PathBuf>,
    /// Instead of calibrating, write synthetic tracks to this file: parts played through the schedule by the exact simulator, observed with noise and missing frames (the options under "Simulation").
    #[arg(long, value_name = "TRACKS.csv", conflicts_with = "tracks")]
    pub simulate: Option<PathBuf>,
    /// Also estimate the amplitude scale of the delivered motion.
    #[arg(long)]
    pub scale: bool,
    /// Grid points per side of the velocity fields over the plate region.
    #[arg(long, default_value_t = CalibrateOptions::default().grid)]
    pub grid: usize,
    /// How long the motion was played (s): frames after it are refused.
    #[arg(long, allow_negative_numbers = true)]
    pub played: Option<f64>,
    /// Output folder: calibration.json, report.md, trajectories.svg, likelihood.svg.
    #[arg(long, default_value = "out/calibration")]
    pub out: PathBuf,
    #[command(flatten, next_help_heading = "Simulation (with --simulate)")]
    #[allow(missing_docs)]
    pub simulation: TracksArgs,
}

impl CalibrateArgs {
    /// Calibrates, writes the report files and returns the JSON to print;
    /// with `--simulate`, writes the synthetic tracks instead.
    pub fn run(&self) -> Result<String> {
        if let Some(path) = &self.simulate {
            let csv = self.simulation.run(&self.schedule)?;
            platefield::output::write_atomic(path, csv.as_bytes())?;
            return Ok(format!("wrote {}\n", path.display()));
        }
        let Some(tracks) = &self.tracks else {
            return Err(Error::invalid(
                "TRACKS",
                "give the tracks file (or --simulate FILE)",
            ));
        };
        if let Some(p) = self.played {
            platefield::error::positive("--played", p)?;
        }
        let options = CalibrateOptions {
            scale: self.scale,
            grid: self.grid,
            played: self.played,
        };
        report::calibrate::run(&self.schedule, tracks, &options, &self.out)
    }
}

/// The synthetic tracks of `platefield calibrate --simulate`.
#[derive(Args)]
pub struct TracksArgs {
    /// A class's friction: MU (μ_s = μ_k) or STATIC:KINETIC; repeat for several classes (the parts are split evenly among them, in order).
    #[arg(long, default_value = "0.3")]
    pub friction: Vec<String>,
    /// Parts.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub parts: u64,
    /// Track duration (s) from the schedule's start.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub seconds: f64,
    /// Frames per second.
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    pub fps: f64,
    /// Position noise per axis, one standard deviation (m).
    #[arg(long, default_value_t = 2e-4, allow_negative_numbers = true)]
    pub noise: f64,
    /// Fraction of frames missing.
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub missing: f64,
    /// Amplitude scale the motion is played at (the shaker's delivered amplitude over the sent one).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub amplitude: f64,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `--friction MU` or `STATIC:KINETIC`.
pub fn friction(text: &str) -> Result<Friction> {
    let bad = || {
        Error::invalid(
            "--friction",
            format!("expected MU or STATIC:KINETIC (numbers in [0, 2], static ≥ kinetic), got \"{text}\""),
        )
    };
    let f = match text.split_once(':') {
        Some((s, k)) => Friction {
            stat: s.trim().parse().map_err(|_| bad())?,
            kinetic: k.trim().parse().map_err(|_| bad())?,
        },
        None => Friction::uniform(text.trim().parse().map_err(|_| bad())?),
    };
    if !(f.kinetic > 0.0 && f.stat <= 2.0) {
        return Err(bad());
    }
    f.validate("--friction")?;
    Ok(f)
}

impl TracksArgs {
    /// Simulates the tracks on the schedule at `schedule` and returns them as CSV.
    pub fn run(&self, schedule: &std::path::Path) -> Result<String> {
        let classes = self
            .friction
            .iter()
            .map(|f| friction(f))
            .collect::<Result<Vec<_>>>()?;
        let schedule = Schedule::load(schedule)?;
        let region = schedule.region();
        let n = self.parts as usize;
        let sim = TrackSimulation {
            frictions: (0..n).map(|i| classes[i * classes.len() / n]).collect(),
            seconds: self.seconds,
            fps: self.fps,
            noise: self.noise,
            missing: self.missing,
            scale: self.amplitude,
            seed: self.seed,
        };
        Ok(simulate_tracks(&schedule, &region, &sim)?.to_csv())
    }
}
