//! Helpers shared by the integration tests.

use std::process::Command;

/// Runs the `platefield` binary; returns (exit code, stdout, stderr).
pub fn platefield(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_platefield"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The arguments of a fast design (0.1 s) of `target` into `out`.
#[allow(dead_code)] // not every test file that shares this module designs
pub fn design_args<'a>(target: &'a str, out: &'a str) -> Vec<&'a str> {
    let fast = "--method sequence --primitives LineSink --rotation-step 90 --no-cache --quiet";
    ["design", target]
        .into_iter()
        .chain(fast.split(' '))
        .chain(["--out", out])
        .collect()
}
