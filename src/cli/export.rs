//! `platefield export`: arguments, and the file or stdout they write.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use platefield::motion::held_csv;
use platefield::output::write_atomic;
use platefield::schedule::export::{self, harmonics};
use platefield::schedule::Schedule;
use platefield::Result;

/// What `export` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The six held acceleration signals as samples at `--rate` (every schedule).
    Csv,
    /// Per channel the amplitude and phase of each harmonic, A·sin(nωt + φ) (a schedule of one six-signal motion).
    Harmonics,
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
    /// csv: the held samples; harmonics: amplitude and phase of each harmonic per channel. Both state the frame, the reference point and each axis's peak acceleration, velocity and stroke.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    pub format: Format,
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
    /// `--steady-cycles`, a schedule `--format harmonics` cannot write, an
    /// unwritable `--out`. Nothing is written then.
    pub fn run(&self) -> Result<String> {
        let s = Schedule::load(&self.schedule)?;
        let (text, what) = match self.format {
            Format::Csv => {
                let e = export::export(&s, self.rate, self.steady_cycles)?;
                for line in e.over_limits() {
                    eprintln!("warning: {line}");
                }
                let text = e.to_csv();
                if let Some(why) = held_csv::over_replay_size(Some(self.rate), text.len() as u64) {
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
