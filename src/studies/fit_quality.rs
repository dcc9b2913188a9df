//! `results/fit_quality.md`: how well, and how fast, each example target is
//! fitted in each mode from a cached basis.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::design::{design, DesignOptions};
use crate::error::{Error, Result};
use crate::fit::FitMode;
use crate::output::write_atomic;
use crate::request::Target;

/// The fit modes compared.
pub fn modes() -> Vec<FitMode> {
    vec![
        FitMode::Shape,
        FitMode::Absolute,
        FitMode::Budget { rel_error: 0.05 },
        FitMode::L1,
        FitMode::LInf,
    ]
}

/// Designs every target in every mode and writes `fit_quality.md` to `out`.
pub fn write_fit_quality(targets: &[PathBuf], base: &DesignOptions, out: &Path) -> Result<String> {
    let mut md = String::from(
        "# Fit quality of the example targets\n\n\
         Every target in `targets/` designed in every fit mode from the cached basis \
         (velocity fields of the 8 primitives, rotated every 15°). Relative L2 error of the \
         continuous fit and of the whole-cycle schedule; time is the fit, verification and \
         scheduling time from a cached basis on this machine (2 cores). `budget` maximises the \
         strength within a 5 % error budget (infeasible targets say so). \
         Regenerate: `platefield fit-quality`.\n\n\
         | target | mode | rel. L2 error | schedule error | mean angle (°) | strength | segments | time (s) | note |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for path in targets {
        let target = Target::load(path)?;
        for mode in modes() {
            let opts = DesignOptions {
                fit: crate::design::FitSection { mode, ..base.fit },
                runtime: crate::work::Runtime::QUIET,
                ..base.clone()
            };
            match design(&target, &opts) {
                Ok(d) => {
                    let s = &d.schedule;
                    let _ = writeln!(
                        md,
                        "| {} | {} | {:.4} | {:.4} | {:.2} | {:.4} | {} | {:.3} | {} |",
                        s.target,
                        mode.name(),
                        s.fit.relative_l2_error,
                        s.fit_quantized.relative_l2_error,
                        s.fit.mean_angle_error_deg,
                        s.fit.strength,
                        s.segments.iter().filter(|g| g.is_moving()).count(),
                        d.fit_time_s,
                        if s.poor_fit { "poor fit" } else { "" }
                    );
                }
                Err(e) => {
                    let _ = writeln!(
                        md,
                        "| {} | {} | – | – | – | – | – | – | {} |",
                        target.name,
                        mode.name(),
                        e.to_string().replace('|', "/")
                    );
                }
            }
        }
    }
    write_atomic(&out.join("fit_quality.md"), md.as_bytes())?;
    Ok(md)
}

/// Default output folder of `platefield fit-quality`.
pub const DIR: &str = "results";

/// `platefield fit-quality`: every `*.json` target in the folder `targets`
/// (in name order), designed with the default options; returns
/// `fit_quality.md`.
pub fn run(targets: &Path, out: &Path) -> Result<String> {
    let io = |e| Error::Io {
        path: targets.display().to_string(),
        source: e,
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(targets)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    write_fit_quality(&files, &DesignOptions::default(), out)
}
