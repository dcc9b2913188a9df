//! `platefield export`: arguments, and the file or stdout they write.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use platefield::motion::held_csv;
use platefield::output::write_atomic;
use platefield::schedule::export::{self, harmonics, pose, response};
use platefield::schedule::Schedule;
use platefield::Result;

/// What `export` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The six held acceleration signals as samples at `--rate` (every schedule).
    Csv,
    /// Per channel the amplitude and phase of each harmonic, A·sin(nωt + φ) (a schedule of one six-signal motion).
    Harmonics,
    /// Per point at `--rate` x, y, z and the fixed-axis x-y-z angles of the plate (a hexapod's wave table): one steady cycle, or one schedule period.
    Pose,
    /// One steady cycle of the six accelerations at `--points` points (a schedule of one six-signal motion).
    Cycle,
}

/// Arguments of `platefield export`.
#[derive(Args)]
pub struct ExportArgs {
    /// A schedule.json written by `design`.
    pub schedule: PathBuf,
    /// Samples per second (csv).
    #[arg(long, default_value_t = 10000.0, allow_negative_numbers = true)]
    pub rate: f64,
    /// Steady cycles of a six-signal (synthesized) motion between its ramp-in from rest and ramp-out to rest (10 cycles each); primitive schedules export one period to loop (csv).
    #[arg(long, default_value_t = export::DEFAULT_STEADY_CYCLES)]
    pub steady_cycles: u32,
    /// csv: the held samples; harmonics: amplitude and phase of each harmonic per channel; pose: positions and angles; cycle: one steady cycle's point values. All state the frame, the reference point and each axis's peak acceleration, velocity and stroke.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    pub format: Format,
    /// Points per cycle (cycle).
    #[arg(long, default_value_t = 256)]
    pub points: usize,
    /// A measured shaker response (per harmonic a complex 6 × 6 matrix or its diagonal, drive to plate accelerations): write the drive signals that make the plate play the design (as harmonics) instead.
    #[arg(long)]
    pub response: Option<PathBuf>,
    /// Output file (default: stdout).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

impl ExportArgs {
    /// Exports the schedule; returns what to print (the file itself
    /// without `--out`, else a line naming it).
    ///
    /// # Errors
    /// An unreadable or invalid schedule, a bad `--rate` or
    /// `--steady-cycles` or `--points`, a schedule `--format harmonics` or
    /// `cycle` cannot write, an
    /// unwritable `--out`. Nothing is written then.
    pub fn run(&self) -> Result<String> {
        let s = Schedule::load(&self.schedule)?;
        let (text, what) = match (&self.response, self.format) {
            (Some(file), Format::Harmonics | Format::Csv) => {
                let r = response::Response::read(file)?;
                let d = response::drive(&harmonics::harmonics(&s)?, &r)?;
                let what = format!(
                    "drive: {} terms over 6 channels through {}",
                    d.terms.len(),
                    file.display()
                );
                (d.to_csv(), what)
            }
            (Some(_), _) => return Err(platefield::Error::invalid(
                "--response",
                "writes the drive as harmonics: use it with --format harmonics (or no --format)",
            )),
            (None, format) => match format {
                Format::Csv => {
                    let e = export::export(&s, self.rate, self.steady_cycles)?
                        .held_to(platefield::synth::ShakerLimits::stated(&s));
                    for line in e.over_limits() {
                        eprintln!("warning: {line}");
                    }
                    for line in e.scaled().into_iter().chain(e.undriven_turns()) {
                        eprintln!("note: {line}");
                    }
                    let text = e.to_csv();
                    if let Some(why) =
                        held_csv::over_replay_size(Some(self.rate), text.len() as u64)
                    {
                        eprintln!("warning: the file is {why}");
                    }
                    let what = format!(
                        "{} samples at {} Hz: {}",
                        e.samples.samples.len(),
                        self.rate,
                        e.describe()
                    );
                    (text, what)
                }
                Format::Harmonics => {
                    let h = harmonics::harmonics(&s)?;
                    let what = format!(
                        "{} terms over 6 channels, T = {} s",
                        h.terms.len(),
                        h.period
                    );
                    (h.to_csv(), what)
                }
                Format::Pose => {
                    let p = pose::poses(&s, self.rate)?;
                    let what = format!(
                        "{} poses {:.9} s apart, {}",
                        p.points.len(),
                        p.dt,
                        if p.steady {
                            "one steady cycle"
                        } else {
                            "one schedule period"
                        }
                    );
                    (p.to_csv(), what)
                }
                Format::Cycle => {
                    let c = pose::cycle(&s, self.points)?;
                    let what = format!("{} points of one {} s cycle", c.points.len(), c.period);
                    (c.to_csv(), what)
                }
            },
        };
        match &self.out {
            Some(file) => {
                write_atomic(file, text.as_bytes())?;
                Ok(format!("wrote {} ({what})\n", file.display()))
            }
            None => Ok(text),
        }
    }
}
