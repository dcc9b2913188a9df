//! `platefield design` end to end: load the target, design it, write the
//! folder whole, and return what to print. Above the formatters
//! (`design`, `method`, `closed_loop`), which it composes, so the files of
//! the report layer import one way.

use std::fmt::Write as _;
use std::path::Path;

/// Every file `design` may write in `OUT/<target name>/`. The folder is
/// written whole ([`platefield::output::Staged`]): a run's files replace the
/// previous run's in one atomic swap, and those of them it did not write
/// are not carried over, so that the folder holds one design (a sequenced
/// run after a synthesized one leaves no `signals.svg`); `verify/` and
/// files of the user's are kept.
pub(crate) const DESIGN_FILES: [&str; 10] = [
    "schedule.json",
    "schedule_open_loop.json",
    "closed_loop.md",
    "closed_loop.json",
    "fit.svg",
    "report.md",
    "signals.svg",
    "order.md",
    "sort.json",
    "sorted.svg",
];

/// `platefield design`: loads the target at `path`, designs it by
/// [`platefield::inverse::run`] with `opts`, writes `OUT/<target name>/…` whole
/// and returns the schedule JSON (`json`) or the terminal summary with the
/// files written.
pub fn run(
    path: &Path,
    opts: &platefield::design::DesignOptions,
    out: &Path,
    json: bool,
) -> platefield::error::Result<String> {
    use platefield::design::Method;
    use platefield::inverse::{DesignOutcome, TargetFile};
    let mut file = TargetFile::load(path)?;
    if let Some(f) = opts.friction {
        file.set_friction(f, "--friction")?;
    }
    let name = file.target().folder_name(path)?;
    if let TargetFile::Field(target) = &mut file {
        target.name = name.clone();
    }
    let dir = out.join(&name);
    platefield::output::check_writable(&dir, "--out")?;
    let outcome = platefield::inverse::run(&file, opts)?;
    let target = file.target();
    let md = match outcome {
        DesignOutcome::Sorted(d) => {
            return super::sort::run(target, &d, &dir, json, &DESIGN_FILES, &opts.runtime)
        }
        DesignOutcome::ClosedLoop {
            design: d,
            closed_loop: result,
        } => {
            let stage = platefield::output::Staged::new(&dir)?;
            super::closed_loop::write(&d, target, &result, stage.path())?;
            stage.commit(&DESIGN_FILES)?;
            if json {
                return super::closed_loop::schedule_json(&d, target, &result);
            }
            return Ok(format!(
                "{}{}{}wrote {}/{{schedule.json, schedule_open_loop.json, closed_loop.md, closed_loop.json, fit.svg, report.md}}\n",
                super::closed_loop::headline(&d, target, &result),
                super::design::summary(&d),
                super::closed_loop::summary(&result),
                dir.display()
            ));
        }
        DesignOutcome::Method(md) => md,
        DesignOutcome::Pose(d) => return pose(&d, &dir, json),
    };
    let stage = platefield::output::Staged::new(&dir)?;
    let files = super::method::write(&md, stage.path())?;
    stage.commit(&DESIGN_FILES)?;
    if json {
        return md.kept().schedule.to_json();
    }
    // The kept design first, with its details; the others only by their
    // one line each in the candidates' list (report.md has their details).
    let mut text = super::method::headline(&md);
    let kept = md.kept().method;
    if let Some(d) = md.sequence.as_ref().filter(|_| kept == Method::Sequence) {
        text.push_str(&super::design::summary(d));
    }
    if let Some(syn) = md.synthesis.as_ref().filter(|_| kept != Method::Sequence) {
        let _ = writeln!(text, "synthesize: {}", syn.timed_summary());
    }
    text.push_str(&super::method::summary(&md));
    let _ = writeln!(text, "wrote {}/{{{}}}", dir.display(), files.join(", "));
    Ok(text)
}

/// Writes a pose target's design `d` (`platefield::pose::design`) to `dir`
/// whole and returns the schedule JSON or the summary.
fn pose(
    d: &platefield::pose::design::PoseDesign,
    dir: &Path,
    json: bool,
) -> platefield::error::Result<String> {
    let stage = platefield::output::Staged::new(dir)?;
    let files = super::pose_design::write(d, stage.path())?;
    stage.commit(&DESIGN_FILES)?;
    if json {
        return d.method.kept().schedule.to_json();
    }
    let mut text = super::pose_design::headline(d);
    if let Some(syn) = &d.method.synthesis {
        let _ = writeln!(text, "synthesize: {}", syn.timed_summary());
    }
    let _ = writeln!(text, "wrote {}/{{{}}}", dir.display(), files.join(", "));
    Ok(text)
}
