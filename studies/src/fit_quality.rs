//! `results/fit_quality.md`: how well, and how fast, each example target is
//! fitted in each mode from a cached basis.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use platefield::design::{design, DesignOptions};
use platefield::error::{Error, Result};
use platefield::fit::FitMode;
use platefield::output::write_atomic;
use platefield::request::Target;
use platefield_report::table::Table;

/// The fit modes compared.
pub(crate) fn modes() -> Vec<FitMode> {
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
         continuous fit and of the whole-cycle schedule. `budget` maximises the \
         strength within a 5 % error budget (infeasible targets say so). A target with a \
         friction range is fitted by the worst-case fit over its range (`platefield::fit::worst`: \
         the least worst shape error, then the strongest within it) in every mode, so its rows \
         agree. Pose targets \
         (`\"kind\": \"pose\"`) are designed by `pose::design`, not fitted, and are left out. \
         Regenerate: `platefield study fit-quality` (it prints each fit's time, which is not written \
         here).\n\n",
    );
    let mut table = Table::new([
        "target",
        "mode",
        "rel. L2 error",
        "schedule error",
        "mean angle (°)",
        "strength",
        "segments",
        "note",
    ]);
    let mut times =
        String::from("fit, verification and scheduling time from the cached basis (s):\n");
    for path in targets {
        let target = Target::load(path)?;
        for mode in modes() {
            let opts = DesignOptions {
                fit: platefield::design::FitSection { mode, ..base.fit },
                runtime: platefield::work::Runtime::QUIET,
                ..base.clone()
            };
            match design(&target, &opts) {
                Ok(d) => {
                    let s = &d.schedule;
                    table.row([
                        s.target.clone(),
                        mode.name().to_string(),
                        format!("{:.4}", s.fit.relative_l2_error),
                        format!("{:.4}", s.fit_quantized.relative_l2_error),
                        format!("{:.2}", s.fit.mean_angle_error_deg),
                        format!("{:.4}", s.fit.strength),
                        s.segments
                            .iter()
                            .filter(|g| g.is_moving())
                            .count()
                            .to_string(),
                        if s.poor_fit { "poor fit" } else { "" }.to_string(),
                    ]);
                    let _ = writeln!(times, "  {} {}: {:.3}", s.target, mode.name(), d.fit_time_s);
                }
                Err(e) => {
                    let mut cells = vec![target.name.clone(), mode.name().to_string()];
                    cells.extend(["–"; 5].map(String::from));
                    cells.push(e.to_string().replace('|', "/"));
                    table.row(cells);
                }
            }
        }
    }
    md.push_str(&table.markdown());
    write_atomic(&out.join("fit_quality.md"), md.as_bytes())?;
    Ok(format!("{md}\n{times}"))
}

/// Default output folder of `platefield study fit-quality`.
pub const DIR: &str = "results";

/// `platefield study fit-quality`: every target of [`fitted_targets`] in the
/// folder `targets`, designed with the default options; returns
/// `fit_quality.md` and each fit's time.
pub fn run(targets: &Path, out: &Path) -> Result<String> {
    write_fit_quality(&fitted_targets(targets)?, &DesignOptions::default(), out)
}

/// The `*.json` targets in the folder `targets` but pose targets (designed
/// by `pose::design`, not fitted), in name order.
///
/// # Errors
/// The folder or a target file cannot be read.
pub fn fitted_targets(targets: &Path) -> Result<Vec<PathBuf>> {
    let io = |e| Error::Io {
        path: targets.display().to_string(),
        source: e,
    };
    let json: Vec<PathBuf> = std::fs::read_dir(targets)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    let mut files = Vec::new();
    for p in json {
        if platefield::pose::design::PoseTarget::load(&p)?.is_none() {
            files.push(p);
        }
    }
    files.sort();
    Ok(files)
}
