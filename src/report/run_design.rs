//! `platefield design` end to end: load the target, design it, write the
//! folder whole, and return what to print. Above the formatters
//! (`design`, `method`, `closed_loop`), which it composes, so the files of
//! the report layer import one way.

use std::fmt::Write as _;
use std::path::Path;

/// Every file `design` may write in `OUT/<target name>/`. The folder is
/// written whole ([`crate::output::Staged`]): a run's files replace the
/// previous run's in one atomic swap, and those of them it did not write
/// are not carried over, so that the folder holds one design (a sequenced
/// run after a synthesized one leaves no `signals.svg`); `verify/` and
/// files of the user's are kept.
pub const DESIGN_FILES: [&str; 9] = [
    "schedule.json",
    "schedule_open_loop.json",
    "closed_loop.md",
    "closed_loop.json",
    "fit.svg",
    "report.md",
    "signals.svg",
    "order.md",
    "sort.json",
];

/// `platefield design`: loads the target at `path`, designs it by
/// `method` (the closed loop, when `closed_loop` is given, re-fits the
/// sequenced design only), plays every candidate, writes
/// `OUT/<target name>/…` and returns the schedule JSON (`json`) or the
/// terminal summary with the files written.
pub fn run(
    path: &Path,
    opts: &crate::design::DesignOptions,
    closed_loop: Option<&crate::design::closed_loop::LoopOptions>,
    out: &Path,
    json: bool,
    method: crate::design::Method,
    synth: &crate::synth::SynthOptions,
) -> crate::error::Result<String> {
    use crate::design::closed_loop as cl;
    use crate::design::Method;
    let mut target = crate::request::Target::load(path)?;
    target.name = target.folder_name(path)?;
    let dir = out.join(&target.name);
    crate::output::check_writable(&dir, "--out")?;
    if !target.classes.is_empty() {
        if closed_loop.is_some()
            || matches!(method, Method::Synthesize | Method::Mix | Method::Mirror)
        {
            return Err(crate::error::Error::invalid(
                "--method",
                "a target with classes is designed by one stacked fit of primitives (sort by friction): use --method auto or sequence, without --closed-loop",
            ));
        }
        return super::sort::run(&target, opts, &dir, json, &DESIGN_FILES);
    }
    if let Some(l) = closed_loop {
        l.validate()?;
        if matches!(method, Method::Synthesize | Method::Mix | Method::Mirror) {
            return Err(crate::error::Error::invalid(
                "--closed-loop",
                "re-fits a sequenced schedule; use it with --method sequence (or auto, which then designs by sequence)",
            ));
        }
        let d = crate::design::design(&target, opts)?;
        let result = cl::closed_loop(&target, &d, l)?;
        let stage = crate::output::Staged::new(&dir)?;
        super::closed_loop::write(&d, &target, &result, stage.path())?;
        stage.commit(&DESIGN_FILES)?;
        if json {
            return super::closed_loop::schedule_json(&d, &target, &result);
        }
        return Ok(format!(
            "{}{}wrote {}/{{schedule.json, schedule_open_loop.json, closed_loop.md, closed_loop.json, fit.svg, report.md}}\n",
            super::design::summary(&d),
            super::closed_loop::summary(&result),
            dir.display()
        ));
    }
    let md = crate::design::design_by_method(&target, opts, synth, method)?;
    let stage = crate::output::Staged::new(&dir)?;
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
        let _ = writeln!(text, "synthesize: {}", syn.summary());
    }
    text.push_str(&super::method::summary(&md));
    let _ = writeln!(text, "wrote {}/{{{}}}", dir.display(), files.join(", "));
    Ok(text)
}
