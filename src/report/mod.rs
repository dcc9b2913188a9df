//! Every file the product writes and every terminal summary it prints:
//! designs ([`design`]: `schedule.json`, `fit.svg`, `report.md`), closed
//! loops ([`closed_loop`]), order searches ([`mod@order`]), verifications
//! ([`verify`]: `summary.json`, `trajectories.svg`) and exported signals.
//! The top layer: it may use every module below it, and nothing uses it
//! but the command-line shell. Each `run` function is one subcommand:
//! compute everything, then write (so bad input writes nothing), then
//! return the text to print.

pub mod closed_loop;
pub mod design;
pub mod method;
pub mod order;
pub mod poses;
pub mod run_design;
pub mod sort;
pub mod sort_play;
pub mod verify;

use std::path::Path;

use crate::design::order::OrderRequest;
use crate::error::Result;
use crate::output::write_atomic;
use crate::schedule::export;
use crate::schedule::Schedule;

/// `platefield export`: the six signals of the schedule at `path` at
/// `rate` samples/s as CSV, written to `out` (returns a line saying so) or
/// returned for stdout.
pub fn export(path: &Path, rate: f64, steady_cycles: u32, out: Option<&Path>) -> Result<String> {
    let s = Schedule::load(path)?;
    let e = export::export(&s, rate, steady_cycles)?;
    let csv = e.samples.to_csv();
    match out {
        Some(file) => {
            write_atomic(file, csv.as_bytes())?;
            Ok(format!(
                "wrote {} ({} samples at {rate} Hz: {})\n",
                file.display(),
                e.samples.samples.len(),
                e.describe()
            ))
        }
        None => Ok(csv),
    }
}

/// `platefield order`: searches the orders and rest insertions of the
/// schedule at `path` ([`crate::design::order::order_schedule_file`]),
/// writes `OUT/<target>/verify/order.md` and returns the table and a line
/// naming the file.
pub fn order(path: &Path, req: &OrderRequest, out: &Path) -> Result<String> {
    let start = std::time::Instant::now();
    // The folder order.md goes to, checked before the search (reading the
    // schedule is cheap; its errors are the ones the search would give).
    let schedule = crate::schedule::Schedule::load(path)?;
    crate::output::check_writable(&out.join(schedule.target_folder()?).join("verify"), "--out")?;
    let (schedule, search) = crate::design::order::order_schedule_file(path, req)?;
    let md = order::order_md(path, req.n, &schedule, &search);
    let file = order::write(&md, &schedule, out)?;
    Ok(format!(
        "{md}wrote {} ({:.1} s)\n",
        file.display(),
        start.elapsed().as_secs_f64()
    ))
}
