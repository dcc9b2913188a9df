//! The native module of the `platefield` Python package
//! (`platefield._platefield`). Each function is the library call the
//! command-line tool makes for the same job, so Python and the CLI give the
//! same numbers: `design` and `verify` parse the CLI's own argument structs
//! (`cli::design::DesignArgs`, `cli::verify::VerifyArgs`: the CLI crate's
//! library, as the platefield library has no clap types) from the argument list the
//! Python layer builds from keyword arguments and run them with `--json`;
//! `poses` calls the same `cli::poses::run` with `--json`;
//! `field` (the library door `platefield::scene::field`) and `export`
//! return numpy arrays of what `field` and `export`
//! print. The GIL is released while Rust works.

use std::path::Path;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::Parser;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use cli::design::DesignArgs;
use cli::verify::VerifyArgs;
use platefield::field::Validity;
use platefield::scene::Scene;
use platefield::schedule::{export as schedule_export, Schedule};
use platefield::Error;

/// The `platefield` command's argument groups and handlers (the CLI crate's
/// library): the library exports no clap types.
use platefield_cli as cli;

create_exception!(
    _platefield,
    NativeError,
    PyException,
    "An error of the Rust library: args (kind, path, message, suggestion); the Python layer raises it as platefield.Error's subclasses."
);

/// `platefield design ARGS --json`.
#[derive(Parser)]
#[command(name = "design")]
struct DesignCommand {
    #[command(flatten)]
    args: DesignArgs,
}

/// `platefield verify ARGS --json`.
#[derive(Parser)]
#[command(name = "verify")]
struct VerifyCommand {
    #[command(flatten)]
    args: VerifyArgs,
}

/// A library error as a [`NativeError`] (kind, JSON path or argument, message, "").
fn library_error(e: Error) -> PyErr {
    let (kind, path, message) = match e {
        Error::Invalid { field, message } => ("invalid", field, message),
        Error::ContactLost(m) => ("contact_lost", String::new(), m),
        Error::Unreachable(m) => ("unreachable", String::new(), m),
        Error::Internal(m) => ("internal", String::new(), m),
        Error::NotConverged(m) => ("not_converged", String::new(), m),
        // The fit's own kind stays in the Rust error; Python sees it as
        // not converged, with the fit's message, as before.
        Error::Fit(f) => ("not_converged", String::new(), format!("fit: {f}")),
        Error::Io { path, source } => ("io", path, source.to_string()),
    };
    NativeError::new_err((kind, path, message, String::new()))
}

/// A clap error as a [`NativeError`]: ("unknown", the argument, message,
/// the similar argument clap suggests) for an argument no option has, else
/// ("invalid", the argument, message, "").
fn argument_error(e: &clap::Error) -> PyErr {
    let text = |k| match e.get(k) {
        Some(ContextValue::String(s)) => s.clone(),
        Some(ContextValue::Strings(v)) => v.first().cloned().unwrap_or_default(),
        _ => String::new(),
    };
    let kind = if e.kind() == ErrorKind::UnknownArgument {
        "unknown"
    } else {
        "invalid"
    };
    let rendered = e.render().to_string();
    let message = rendered
        .lines()
        .next()
        .unwrap_or_default()
        .trim_start_matches("error: ")
        .to_string();
    NativeError::new_err((
        kind,
        text(ContextKind::InvalidArg),
        message,
        text(ContextKind::SuggestedArg),
    ))
}

/// `platefield design ARGV --json`: the schedule JSON it prints.
#[pyfunction]
fn design(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let mut cmd = DesignCommand::try_parse_from(argv).map_err(|e| argument_error(&e))?;
    cmd.args.json = true;
    py.detach(|| cmd.args.run()).map_err(library_error)
}

/// `platefield verify ARGV --json`: the summary JSON it prints.
#[pyfunction]
fn verify(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let mut cmd = VerifyCommand::try_parse_from(argv).map_err(|e| argument_error(&e))?;
    cmd.args.json = true;
    py.detach(|| cmd.args.run()).map_err(library_error)
}

/// `platefield poses PART SOURCE --json`: the analysis JSON it prints
/// (`drops` random drops; `play` seconds of planar simulation per drop
/// through a schedule source; files into `out` when given; `allow_long`
/// lifts the work limit as `--allow-long` does).
#[pyfunction]
#[pyo3(signature = (part, source, drops, play, out, allow_long))]
fn poses(
    py: Python<'_>,
    part: String,
    source: String,
    drops: usize,
    play: Option<f64>,
    out: Option<String>,
    allow_long: bool,
) -> PyResult<String> {
    py.detach(|| {
        cli::poses::PosesArgs {
            part: part.into(),
            source: source.into(),
            drops,
            play,
            friction: None,
            out: out.map(Into::into),
            json: cli::Json { json: true },
            quiet: true,
            long: cli::AllowLong { allow_long },
        }
        .run()
    })
    .map_err(library_error)
}

/// A document (`what`: scene or schedule) from the file `path` by `load`,
/// or from JSON `text` by `parse`: the library's own readers and checks.
fn document<T>(
    path: Option<&str>,
    text: Option<&str>,
    what: &str,
    load: impl Fn(&Path) -> Result<T, Error>,
    parse: impl Fn(&str) -> Result<T, Error>,
) -> Result<T, Error> {
    match (path, text) {
        (Some(p), _) => load(Path::new(p)),
        (None, Some(t)) => parse(t),
        (None, None) => Err(Error::invalid(what, "give a path or a dict")),
    }
}

/// The field `platefield field` computes for a scene: a dict of numpy
/// arrays `fx`, `fy` (ny × nx; m/s, or m/s² for force fields), `valid` (ny × nx booleans),
/// `x` (nx), `y` (ny) in metres, and `kind`.
#[pyfunction]
#[pyo3(signature = (path, text, quiet, allow_long))]
fn field<'py>(
    py: Python<'py>,
    path: Option<String>,
    text: Option<String>,
    quiet: bool,
    allow_long: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let computed = py.detach(|| {
        let s = document(
            path.as_deref(),
            text.as_deref(),
            "scene",
            Scene::load,
            Scene::from_json_str,
        )?;
        let origin = path.as_deref().unwrap_or("scene");
        platefield::scene::field(&platefield::scene::FieldRequest {
            scene: s,
            source: origin.into(),
            runtime: platefield::work::Runtime { quiet, allow_long },
        })
    });
    let f = computed.map_err(library_error)?;
    let [nx, ny] = f.grid.n;
    let grid = |values: Vec<f64>| Array2::from_shape_vec((ny, nx), values);
    let fx = grid(f.vectors.iter().map(|v| v[0]).collect());
    let fy = grid(f.vectors.iter().map(|v| v[1]).collect());
    let valid = Array2::from_shape_vec(
        (ny, nx),
        f.validity.iter().map(|v| *v == Validity::Ok).collect(),
    );
    let shape = |e: numpy::ndarray::ShapeError| PyException::new_err(e.to_string());
    let d = PyDict::new(py);
    d.set_item("fx", fx.map_err(shape)?.into_pyarray(py))?;
    d.set_item("fy", fy.map_err(shape)?.into_pyarray(py))?;
    d.set_item("valid", valid.map_err(shape)?.into_pyarray(py))?;
    d.set_item("x", PyArray1::from_vec(py, f.grid.xs()))?;
    d.set_item("y", PyArray1::from_vec(py, f.grid.ys()))?;
    d.set_item("kind", format!("{:?}", f.kind).to_lowercase())?;
    Ok(d)
}

/// The schedule at `path` or in JSON `text`.
fn schedule(path: Option<&str>, text: Option<&str>) -> Result<Schedule, Error> {
    document(path, text, "schedule", Schedule::load, |t| {
        Schedule::from_json_str(t, "schedule")
    })
}

/// Peak acceleration, velocity and stroke per channel (the header's
/// figures): a dict of three 6-lists, x, y, z linear then angular.
fn peaks_dict<'py>(
    py: Python<'py>,
    p: &schedule_export::peaks::KinematicPeaks,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("acceleration", p.acceleration.to_vec())?;
    d.set_item("velocity", p.velocity.to_vec())?;
    d.set_item("stroke", p.stroke.to_vec())?;
    Ok(d)
}

/// `platefield export` as an (n, 7) array: t (s), then a_x, a_y, a_z
/// (m/s²) and α_x, α_y, α_z (rad/s²) of the plate centre, one row per
/// sample, the rows of the CSV before formatting; with the file's peaks
/// as played (`peaks_dict`).
#[pyfunction]
#[pyo3(signature = (path, text, rate, steady_cycles))]
#[allow(clippy::type_complexity)]
fn export<'py>(
    py: Python<'py>,
    path: Option<String>,
    text: Option<String>,
    rate: f64,
    steady_cycles: u32,
) -> PyResult<(Bound<'py, numpy::PyArray2<f64>>, Bound<'py, PyDict>)> {
    let exported = py.detach(|| {
        let s = schedule(path.as_deref(), text.as_deref())?;
        schedule_export::export(&s, rate, steady_cycles)
    });
    let e = exported.map_err(library_error)?;
    let dt = e.samples.dt;
    let flat: Vec<f64> = (e.samples.samples.iter().enumerate())
        .flat_map(|(k, a)| std::iter::once(k as f64 * dt).chain(a.iter().copied()))
        .collect();
    let rows = Array2::from_shape_vec((e.samples.samples.len(), 7), flat)
        .map_err(|e| PyException::new_err(e.to_string()))?;
    Ok((rows.into_pyarray(py), peaks_dict(py, &e.peaks())?))
}

/// `platefield export --format harmonics`: a dict of `period` (s), `terms`
/// (an (m, 4) array of channel index 0-5, harmonic n, amplitude A in m/s²
/// or rad/s², phase φ in rad: A·sin(n·2πt/T + φ)) and the steady motion's
/// `peaks` (`peaks_dict`).
#[pyfunction]
#[pyo3(signature = (path, text))]
fn harmonics<'py>(
    py: Python<'py>,
    path: Option<String>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let h = py
        .detach(|| {
            schedule_export::harmonics::harmonics(&schedule(path.as_deref(), text.as_deref())?)
        })
        .map_err(library_error)?;
    let flat: Vec<f64> = (h.terms.iter())
        .flat_map(|t| {
            [
                t.channel as f64,
                f64::from(t.harmonic),
                t.amplitude,
                t.phase,
            ]
        })
        .collect();
    let terms = Array2::from_shape_vec((h.terms.len(), 4), flat)
        .map_err(|e| PyException::new_err(e.to_string()))?;
    let d = PyDict::new(py);
    d.set_item("period", h.period)?;
    d.set_item("terms", terms.into_pyarray(py))?;
    d.set_item("peaks", peaks_dict(py, &h.peaks)?)?;
    Ok(d)
}

/// The default steady cycles of `export` for a six-signal motion.
#[pyfunction]
fn default_steady_cycles() -> u32 {
    schedule_export::DEFAULT_STEADY_CYCLES
}

#[pymodule]
fn _platefield(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(design, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    m.add_function(wrap_pyfunction!(field, m)?)?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    m.add_function(wrap_pyfunction!(harmonics, m)?)?;
    m.add_function(wrap_pyfunction!(poses, m)?)?;
    m.add_function(wrap_pyfunction!(default_steady_cycles, m)?)?;
    m.add("NativeError", m.py().get_type::<NativeError>())?;
    Ok(())
}
