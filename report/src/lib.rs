//! Every file the product writes and every terminal summary it prints:
//! designs ([`design`]: `schedule.json`, `fit.svg`, `report.md`), closed
//! loops (`closed_loop`), order searches ([`mod@order`]), verifications
//! ([`verify`]: `summary.json`, `trajectories.svg`) and exported signals.
//! The top layer: it may use every module below it, and nothing uses it
//! but the command-line shell and the studies (which write their tables
//! with [`table::Table`]). Each `run` function is one subcommand:
//! compute everything, then write (so bad input writes nothing), then
//! return the text to print.

pub mod calibrate;
pub mod closed_loop;
pub mod design;
pub mod method;
pub mod order;
pub mod plot;
pub mod pose_design;
pub mod pose_friction;
pub mod poses;
pub mod run_design;
pub mod sort;
pub mod table;
pub mod verify;

use std::path::Path;

/// The command that was run, for a report's "Regenerate:" line: the
/// process's arguments after the program, as `platefield ARGS` (an
/// argument with a space or quote in single quotes; `--quiet` and `--json`
/// left out), when they are a
/// `platefield` subcommand (the CLI, or Python's argument list passed to
/// it); else `platefield {fallback}`.
pub(crate) fn invocation(fallback: &str) -> String {
    // Flags that change only what is printed, not the files, are left out.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--quiet" && a != "--json")
        .collect();
    let subcommand = fallback.split(' ').next().unwrap_or("");
    if args.first().map(String::as_str) != Some(subcommand) {
        return format!("platefield {fallback}");
    }
    let quoted: Vec<String> = args
        .iter()
        .map(|a| {
            if a.is_empty() || a.contains([' ', '\'', '"', '`']) {
                format!("'{}'", a.replace('\'', "'\\''"))
            } else {
                a.clone()
            }
        })
        .collect();
    format!("platefield {}", quoted.join(" "))
}

use platefield::design::order::OrderRequest;
use platefield::error::Result;

/// `platefield order`: searches the orders and rest insertions of the
/// schedule at `path` ([`platefield::design::order::order_schedule_file`]),
/// writes `OUT/<target>/verify/order.md` and returns the table and a line
/// naming the file.
pub fn order(path: &Path, req: &OrderRequest, out: &Path) -> Result<String> {
    let start = std::time::Instant::now();
    // The folder order.md goes to, checked before the search (reading the
    // schedule is cheap; its errors are the ones the search would give).
    let schedule = platefield::schedule::Schedule::load(path)?;
    platefield::output::check_writable(
        &out.join(schedule.target_folder()?).join("verify"),
        "--out",
    )?;
    let platefield::design::order::OrderOutcome { schedule, search } =
        platefield::design::order::order_schedule_file(path, req)?;
    let md = order::order_md(path, req.n, &schedule, &search);
    let file = order::write(&md, &schedule, out)?;
    Ok(format!(
        "{md}wrote {} ({:.1} s)\n",
        file.display(),
        start.elapsed().as_secs_f64()
    ))
}
