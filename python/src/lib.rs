//! `bridgetwin._native`: the Rust side of the Python package. Reading decodes every
//! message in Rust into typed columns (`bridgetwin::input`) and hands them to numpy
//! without copying; simulating runs the same code path as `bridgetwin simulate`
//! (`bridgetwin::app::run::run_to_files`), off the GIL. The Python package in
//! `python/bridgetwin` turns the columns into pandas DataFrames.

mod convert;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use numpy::IntoPyArray;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use bridgetwin::app::run::{run_to_files, FilesOptions, FilesOutcome};
use bridgetwin::app::space::SpaceCheck;
use bridgetwin::input::{read_run as read_files, Column, ReadOptions, RunData, Values};
use bridgetwin::scenario::{Scenario, DEFAULT_SCENARIO_TOML};
use bridgetwin::Error;

pyo3::create_exception!(
    _native,
    ScenarioError,
    PyValueError,
    "A scenario is not valid: the message names the field and the value, as the command \
     line does; `field`, `value` and `reason` are set when one parameter is out of range."
);
pyo3::create_exception!(
    _native,
    ReadError,
    PyOSError,
    "A run could not be read at all (missing file, not an MCAP file, parts of different \
     runs). A damaged file is read up to the damage with a warning instead."
);
pyo3::create_exception!(
    _native,
    SimulationError,
    pyo3::exceptions::PyRuntimeError,
    "A run failed (divergence, output not writable); nothing half-written is left."
);

/// A library error as the Python exception of its kind, with the CLI's message.
fn scenario_error(py: Python<'_>, e: &Error) -> PyErr {
    let err = ScenarioError::new_err(e.to_string());
    if let Error::InvalidParameter {
        field,
        value,
        reason,
    } = e
    {
        let instance = err.value(py);
        for (name, text) in [("field", field), ("value", value), ("reason", reason)] {
            // Setting an attribute on a fresh exception instance cannot fail.
            let _ = instance.setattr(name, text);
        }
    }
    err
}

/// A scenario from its TOML text (`source` names it in errors) or its file.
fn load(
    text: Option<&str>,
    path: Option<PathBuf>,
    source: &str,
) -> Result<(Scenario, String), Error> {
    match (text, path) {
        (_, Some(path)) => Scenario::from_file(&path),
        (Some(text), None) => Ok((Scenario::from_toml(text, source)?, text.to_string())),
        (None, None) => Ok((
            Scenario::default_scenario(),
            DEFAULT_SCENARIO_TOML.to_string(),
        )),
    }
}

/// The default scenario's TOML text.
#[pyfunction]
fn default_scenario_toml() -> &'static str {
    DEFAULT_SCENARIO_TOML
}

/// TOML text as a dict; errors (ScenarioError) name `source`.
#[pyfunction]
fn toml_to_dict<'py>(py: Python<'py>, text: &str, source: &str) -> PyResult<Bound<'py, PyAny>> {
    let value: toml::Value =
        toml::from_str(text).map_err(|e| ScenarioError::new_err(format!("{source}: {e}")))?;
    convert::to_python(py, &value)
}

/// A scenario dict as TOML text (infinities and NaN kept: the checks name them).
#[pyfunction]
fn dict_to_toml(scenario: &Bound<'_, PyAny>) -> PyResult<String> {
    let value = convert::to_toml(scenario, "")?;
    toml::to_string(&value).map_err(|e| ScenarioError::new_err(format!("scenario: {e}")))
}

/// Parses and resolves a scenario exactly as `bridgetwin scenario check` does; returns
/// the warnings, raises ScenarioError.
#[pyfunction]
#[pyo3(signature = (text=None, path=None, source="scenario"))]
fn check(
    py: Python<'_>,
    text: Option<&str>,
    path: Option<PathBuf>,
    source: &str,
) -> PyResult<Vec<String>> {
    let resolved = load(text, path, source)
        .and_then(|(scenario, _)| scenario.resolve())
        .map_err(|e| scenario_error(py, &e))?;
    Ok(resolved.warnings())
}

/// Runs a scenario into `out` as `bridgetwin simulate` does (the same bytes for the same
/// scenario and seed). The time loop runs on its own thread without the GIL; this thread
/// checks for Ctrl-C every 50 ms and, on it, stops the run (its file is kept as
/// `.partial`, as the command line keeps it) and raises KeyboardInterrupt. A run whose
/// estimated size exceeds the free space of `out`'s file system is refused (OSError)
/// before anything is written, unless `skip_space_check`. Returns the files written.
#[pyfunction]
#[pyo3(signature = (out, text=None, path=None, source="scenario", seed=None, duration_s=None, force=false, skip_space_check=false))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    out: PathBuf,
    text: Option<&str>,
    path: Option<PathBuf>,
    source: &str,
    seed: Option<u64>,
    duration_s: Option<f64>,
    force: bool,
    skip_space_check: bool,
) -> PyResult<Vec<PathBuf>> {
    let (mut scenario, original) = load(text, path, source).map_err(|e| scenario_error(py, &e))?;
    if let Some(seed) = seed {
        scenario.seed = seed;
    }
    if let Some(d) = duration_s {
        scenario.duration_s = Some(d);
    }
    let mut resolved = scenario.resolve().map_err(|e| scenario_error(py, &e))?;
    resolved.source_toml = original;
    let stop = Arc::new(AtomicBool::new(false));
    let worker = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let mut progress = |_: &bridgetwin::sim::RunProgress| {};
            let mut control = bridgetwin::sim::Control {
                progress: &mut progress,
                stop: Some(&stop),
            };
            let options = FilesOptions {
                force,
                space_check: match skip_space_check {
                    true => SpaceCheck::Skip,
                    false => SpaceCheck::default(),
                },
            };
            run_to_files(&resolved, &out, options, &mut control, &mut |_| {})
        })
    };
    let mut interrupted = None;
    loop {
        if py.detach(|| wait_a_little(&worker)) {
            break;
        }
        if let Err(e) = py.check_signals() {
            // Ctrl-C (or another signal handler's exception): stop at the next step.
            stop.store(true, Ordering::Relaxed);
            interrupted = Some(e);
            break;
        }
    }
    let outcome = py
        .detach(|| worker.join())
        .map_err(|_| SimulationError::new_err("the simulation thread panicked"))?;
    match (outcome, interrupted) {
        (Ok(FilesOutcome::Finished { paths, .. }), None) => Ok(paths),
        (Ok(FilesOutcome::Stopped { partial, .. }), Some(e)) => {
            let note = format!(
                "interrupted: kept the data written so far in {}",
                partial.display()
            );
            let _ = e
                .value(py)
                .setattr("partial", partial.display().to_string());
            let _ = e.value(py).setattr("note", note);
            Err(e)
        }
        (Ok(FilesOutcome::Finished { paths, .. }), Some(e)) => {
            // The run ended just as the signal came: it is whole; still honour the signal.
            let _ = e.value(py).setattr(
                "paths",
                paths
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>(),
            );
            Err(e)
        }
        (Ok(FilesOutcome::Stopped { partial, .. }), None) => Err(SimulationError::new_err(
            format!("the run stopped early; data kept in {}", partial.display()),
        )),
        (Err((e, _)), _) => Err(match e {
            Error::InvalidParameter { .. } => scenario_error(py, &e),
            Error::File { .. } | Error::Output { .. } | Error::InsufficientSpace { .. } => {
                PyOSError::new_err(e.to_string())
            }
            _ => SimulationError::new_err(e.to_string()),
        }),
    }
}

/// Waits up to 50 ms for the thread to finish; true when it has.
fn wait_a_little<T>(worker: &JoinHandle<T>) -> bool {
    for _ in 0..10 {
        if worker.is_finished() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    worker.is_finished()
}

/// Reads a run (one file, or the hourly parts of a split run) into columns, off the GIL.
///
/// Returns a dict: `topics` (name -> dict of `schema`, `metadata`, `rows`, `columns`:
/// a list of `(name, kind, data, extra, missing)`), `metadata`, `attachments`,
/// `start_time_ns`, `parts` (dicts of `path`, `part`, `messages`, `damage`),
/// `undecoded` (topic -> schema).
#[pyfunction]
#[pyo3(signature = (paths, topics=None))]
fn read_run(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    topics: Option<Vec<String>>,
) -> PyResult<Py<PyDict>> {
    let options = ReadOptions { topics };
    let run = py
        .detach(|| read_files(&paths, &options))
        .map_err(|e| ReadError::new_err(e.to_string()))?;
    run_to_dict(py, run)
}

fn run_to_dict(py: Python<'_>, run: RunData) -> PyResult<Py<PyDict>> {
    let out = PyDict::new(py);
    let topics = PyDict::new(py);
    for (name, topic) in run.topics {
        let t = PyDict::new(py);
        t.set_item("schema", topic.schema)?;
        t.set_item("metadata", topic.metadata)?;
        t.set_item("rows", topic.table.rows)?;
        let columns = PyList::empty(py);
        for column in topic.table.columns {
            columns.append(column_to_tuple(py, column)?)?;
        }
        t.set_item("columns", columns)?;
        topics.set_item(name, t)?;
    }
    out.set_item("topics", topics)?;
    out.set_item("metadata", run.metadata)?;
    let attachments = PyDict::new(py);
    for (name, bytes) in run.attachments {
        attachments.set_item(name, PyBytes::new(py, &bytes))?;
    }
    out.set_item("attachments", attachments)?;
    out.set_item("start_time_ns", run.start_time_ns)?;
    let parts = PyList::empty(py);
    for part in run.parts {
        let p = PyDict::new(py);
        p.set_item("path", part.path.display().to_string())?;
        p.set_item("part", part.part)?;
        p.set_item("messages", part.messages)?;
        p.set_item("damage", part.damage.map(|d| d.to_string()))?;
        parts.append(p)?;
    }
    out.set_item("parts", parts)?;
    out.set_item("undecoded", run.undecoded)?;
    Ok(out.unbind())
}

/// `(name, kind, data, extra, missing)`: `data` a numpy array that owns the column's
/// vector (no copy); `extra` the categories of a string column or the values of a list
/// column (whose `data` are the row offsets); `missing` a bool array or None.
fn column_to_tuple<'py>(py: Python<'py>, column: Column) -> PyResult<Bound<'py, PyAny>> {
    let missing = column.missing.map(|m| m.into_pyarray(py).into_any());
    let none = || py.None().into_bound(py);
    let (kind, data, extra): (&str, Bound<'py, PyAny>, Bound<'py, PyAny>) = match column.values {
        Values::F64(v) => ("f64", v.into_pyarray(py).into_any(), none()),
        Values::I64(v) => ("i64", v.into_pyarray(py).into_any(), none()),
        Values::U32(v) => ("u32", v.into_pyarray(py).into_any(), none()),
        Values::I32(v) => ("i32", v.into_pyarray(py).into_any(), none()),
        Values::Bool(v) => ("bool", v.into_pyarray(py).into_any(), none()),
        Values::Str { codes, categories } => (
            "category",
            codes.into_pyarray(py).into_any(),
            PyList::new(py, categories)?.into_any(),
        ),
        Values::F64List { offsets, values } => (
            "f64_list",
            offsets_array(py, offsets),
            values.into_pyarray(py).into_any(),
        ),
        Values::U32List { offsets, values } => (
            "u32_list",
            offsets_array(py, offsets),
            values.into_pyarray(py).into_any(),
        ),
        Values::StrList { offsets, values } => (
            "str_list",
            offsets_array(py, offsets),
            PyList::new(py, values)?.into_any(),
        ),
    };
    let missing = missing.unwrap_or_else(none);
    Ok((column.name, kind, data, extra, missing)
        .into_pyobject(py)?
        .into_any())
}

fn offsets_array(py: Python<'_>, offsets: Vec<usize>) -> Bound<'_, PyAny> {
    let offsets: Vec<u64> = offsets.into_iter().map(|o| o as u64).collect();
    offsets.into_pyarray(py).into_any()
}

/// The project's Welch PSD (`bridgetwin::base::signal::welch_psd`: Hann windows, 50 %
/// overlap, each segment's mean removed, one-sided density), off the GIL. Returns
/// `(frequencies, density)` for bins 1 .. segment_len/2 - 1.
#[pyfunction]
fn welch_psd<'py>(
    py: Python<'py>,
    samples: numpy::PyReadonlyArray1<'py, f64>,
    spacing: f64,
    segment_len: usize,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let samples = samples.as_array().to_vec();
    let psd = py
        .detach(|| bridgetwin::base::signal::welch_psd(&samples, spacing, segment_len))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((
        psd.frequencies.into_pyarray(py).into_any(),
        psd.density.into_pyarray(py).into_any(),
    ))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("ReadError", m.py().get_type::<ReadError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add_function(wrap_pyfunction!(default_scenario_toml, m)?)?;
    m.add_function(wrap_pyfunction!(toml_to_dict, m)?)?;
    m.add_function(wrap_pyfunction!(dict_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(read_run, m)?)?;
    m.add_function(wrap_pyfunction!(welch_psd, m)?)?;
    Ok(())
}
