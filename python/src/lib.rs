//! The extension module `stillpoint._core`: the library's point generation, metrics,
//! baselines and test integrals on NumPy arrays.
//!
//! Every function copies its input into a [`PointSet`], releases the GIL for the
//! computation (other Python threads run meanwhile), and turns every refusal of the
//! library into a `ValueError` carrying the library's message (a panic, which would be a
//! bug, becomes a `RuntimeError`, never a crash). The Python package `stillpoint` wraps
//! these functions: it casts any array-like to C-ordered float64, scales to bounds, and
//! adds the SciPy engine.

#![deny(missing_docs)]

pub mod config;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

use config::{GenerateArgs, OptValue, Plan, OPTIONS};
use stillpoint::pipeline::{self, Event};
use stillpoint::sequences::Baseline;
use stillpoint::{metrics, PointSet};

/// A refusal as Python sees it.
fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// Runs `f` without the GIL; a library refusal becomes a `ValueError`, a panic a
/// `RuntimeError`.
fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, String> + Send) -> PyResult<T> {
    let outcome = py.detach(move || catch_unwind(AssertUnwindSafe(f)));
    match outcome {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(message)) => Err(value_error(message)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(PyRuntimeError::new_err(format!(
                "internal error in stillpoint (please report it): {what}"
            )))
        }
    }
}

/// Copies a 2-D float64 array (any memory layout) into a point set named `name` in
/// messages.
fn point_set(name: &str, x: &PyReadonlyArray2<'_, f64>) -> PyResult<PointSet> {
    let view = x.as_array();
    let (n, s) = view.dim();
    let data: Vec<f64> = view.iter().copied().collect();
    PointSet::new(n, s, data).map_err(|e| value_error(format!("{name}: {e}")))
}

/// A point set of the unit cube (what the discrepancies and test integrals assume).
fn unit_points(name: &str, x: &PyReadonlyArray2<'_, f64>) -> PyResult<PointSet> {
    let p = point_set(name, x)?;
    p.check_unit_cube()
        .map_err(|e| value_error(format!("{name}: {e}")))?;
    Ok(p)
}

/// A point set as an (n, s) array, without copying the buffer.
fn to_array<'py>(py: Python<'py>, p: PointSet) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (n, s) = (p.n(), p.s());
    let a = Array2::from_shape_vec((n, s), p.into_vec())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// A keyword option's value from Python.
fn option_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<OptValue> {
    if v.is_none() {
        return Ok(OptValue::None);
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(OptValue::Bool(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return v
            .extract::<i64>()
            .map(OptValue::Int)
            .map_err(|_| value_error(format!("invalid {key} = {v}: expected a 64-bit integer")));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(OptValue::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(OptValue::Str(v.extract()?));
    }
    if let Ok(a) = v.extract::<PyReadonlyArray2<'_, f64>>() {
        return point_set(key, &a).map(OptValue::Points);
    }
    let expected = OPTIONS
        .iter()
        .find(|(name, _)| *name == key)
        .map_or("a number, a string or None", |(_, e)| e);
    let shown = v.repr().map(|r| r.to_string()).unwrap_or_default();
    Err(value_error(format!(
        "invalid {key} = {shown}: expected {expected}"
    )))
}

/// Progress lines on standard error, at most five a second.
struct Progress {
    stage: &'static str,
    steps: Option<u64>,
    last: Option<Instant>,
}

impl Progress {
    fn event(&mut self, e: Event) {
        match e {
            Event::Stage { name, steps } => {
                if self.last.is_some() {
                    eprintln!();
                }
                self.stage = name;
                self.steps = steps;
                self.last = Some(Instant::now());
                eprint!("\rstillpoint: {name}");
            }
            Event::Progress(step) => {
                let due = self.last.is_none_or(|t| t.elapsed().as_secs_f64() >= 0.2);
                if due {
                    self.last = Some(Instant::now());
                    match self.steps {
                        Some(total) => eprint!("\rstillpoint: {} {step}/{total}", self.stage),
                        None => eprint!("\rstillpoint: {} {step}", self.stage),
                    }
                }
            }
            Event::Record(_) => {}
        }
    }

    fn finish(&self) {
        if self.last.is_some() {
            eprintln!();
        }
    }
}

/// The arguments of `generate` and `check_generate` as the configuration module takes
/// them.
#[allow(clippy::too_many_arguments)]
fn generate_args(
    n: i64,
    d: Option<i64>,
    seed: u64,
    method: Option<String>,
    energy: Option<String>,
    integrator: Option<String>,
    steps: Option<i64>,
    region: Option<String>,
    bbox: Option<Vec<f64>>,
    shape: Option<String>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<GenerateArgs> {
    let mut opts = Vec::new();
    if let Some(dict) = options {
        for (k, v) in dict.iter() {
            let key: String = k.extract()?;
            let value = option_value(&key, &v)?;
            opts.push((key, value));
        }
    }
    Ok(GenerateArgs {
        n,
        d,
        seed,
        method,
        energy,
        integrator,
        steps,
        region,
        bbox,
        shape,
        options: opts,
    })
}

/// Generates n points: the library's run (by default exactly `stillpoint generate -n N
/// -s D`), in the cube or in a region, or a baseline. See the Python wrapper for the
/// arguments.
#[pyfunction]
#[pyo3(signature = (
    n, d=None, *, seed=0, method=None, energy=None, integrator=None, steps=None,
    region=None, r#box=None, shape=None, progress=false, **options
))]
#[allow(clippy::too_many_arguments)]
fn generate<'py>(
    py: Python<'py>,
    n: i64,
    d: Option<i64>,
    seed: u64,
    method: Option<String>,
    energy: Option<String>,
    integrator: Option<String>,
    steps: Option<i64>,
    region: Option<String>,
    r#box: Option<Vec<f64>>,
    shape: Option<String>,
    progress: bool,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let args = generate_args(
        n, d, seed, method, energy, integrator, steps, region, r#box, shape, options,
    )?;
    let plan = args.plan().map_err(value_error)?;
    let points = detached(py, move || match plan {
        Plan::Baseline(b, n, s, seed) => b.generate(n, s, seed).map_err(|e| e.to_string()),
        Plan::Run(cfg) => {
            let mut bar = Progress {
                stage: "",
                steps: None,
                last: None,
            };
            let report = pipeline::generate_with(&cfg, None, |e| {
                if progress {
                    bar.event(e)
                }
            });
            bar.finish();
            report.map(|r| r.output.points).map_err(|e| e.to_string())
        }
    })?;
    to_array(py, points)
}

/// Checks the arguments of `generate` without running it (a cheap check of names and
/// ranges; the run itself may still refuse, e.g. a start set too large for memory).
#[pyfunction]
#[pyo3(signature = (
    n, d=None, *, seed=0, method=None, energy=None, integrator=None, steps=None,
    region=None, r#box=None, shape=None, progress=false, **options
))]
#[allow(clippy::too_many_arguments)]
fn check_generate(
    n: i64,
    d: Option<i64>,
    seed: u64,
    method: Option<String>,
    energy: Option<String>,
    integrator: Option<String>,
    steps: Option<i64>,
    region: Option<String>,
    r#box: Option<Vec<f64>>,
    shape: Option<String>,
    progress: bool,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<()> {
    let _ = progress;
    let args = generate_args(
        n, d, seed, method, energy, integrator, steps, region, r#box, shape, options,
    )?;
    args.plan().map_err(value_error)?;
    Ok(())
}

/// Every figure of `stillpoint eval --json` for points in [0, 1]^d, as JSON text.
#[pyfunction]
fn metrics_json(py: Python<'_>, x: PyReadonlyArray2<'_, f64>) -> PyResult<String> {
    let p = unit_points("x", &x)?;
    detached(py, move || {
        serde_json::to_string(&stillpoint::quality::evaluate::eval_json(&p))
            .map_err(|e| e.to_string())
    })
}

/// One L2 discrepancy (the root): `l2star`, `md` (modified), `cd` (centred) or `wd`
/// (wrap-around).
#[pyfunction]
fn discrepancy(py: Python<'_>, x: PyReadonlyArray2<'_, f64>, kind: &str) -> PyResult<f64> {
    let f: fn(&PointSet) -> f64 = match kind.trim().to_ascii_lowercase().as_str() {
        "l2star" | "l2-star" => metrics::star_l2,
        "md" => metrics::modified_l2,
        "cd" => metrics::centered_l2,
        "wd" | "periodic" => metrics::wrap_around_l2,
        _ => {
            return Err(value_error(format!(
                "invalid kind = {kind:?}: expected 'l2star' (star L2), 'md' (modified L2), \
                 'cd' (centred L2) or 'wd' (wrap-around L2)"
            )))
        }
    };
    let p = unit_points("x", &x)?;
    detached(py, move || Ok(f(&p)))
}

/// n points of a baseline generator (`stillpoint baseline NAME -n N -s D --seed SEED`).
#[pyfunction]
#[pyo3(signature = (name, n, d, seed=0))]
fn baseline<'py>(
    py: Python<'py>,
    name: &str,
    n: i64,
    d: i64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let b = Baseline::parse(name).map_err(value_error)?;
    if n < 1 {
        return Err(value_error(format!(
            "invalid n = {n}: expected at least 1 point"
        )));
    }
    if d < 1 {
        return Err(value_error(format!(
            "invalid d = {d}: expected at least 1 dimension"
        )));
    }
    let points = detached(py, move || {
        b.generate(n as usize, d as usize, seed)
            .map_err(|e| e.to_string())
    })?;
    to_array(py, points)
}

/// The baselines as (name, paper label, description) triples.
#[pyfunction]
fn baselines() -> Vec<(&'static str, &'static str, &'static str)> {
    Baseline::all()
        .iter()
        .map(|b| (b.name(), b.label(), b.describe()))
        .collect()
}

/// The F1–F8 test integrals of points in [0, 1]^d as JSON text (`stillpoint integrate
/// --json` without the file name).
#[pyfunction]
fn integrate_json(py: Python<'_>, x: PyReadonlyArray2<'_, f64>) -> PyResult<String> {
    let p = unit_points("x", &x)?;
    detached(py, move || {
        let report = stillpoint::quality::integrands::integrate(&p).map_err(|e| e.to_string())?;
        let rows: Vec<serde_json::Value> = stillpoint::quality::integrands::TestFunction::all()
            .iter()
            .zip(report.estimates)
            .map(|(f, e)| {
                serde_json::json!({"function": f.name(), "formula": f.formula(),
                                   "estimate": e, "error": e.map(f64::abs)})
            })
            .collect();
        let v = serde_json::json!({"n": p.n(), "s": p.s(), "exact": 0.0, "functions": rows});
        serde_json::to_string(&v).map_err(|e| e.to_string())
    })
}

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    m.add_function(wrap_pyfunction!(check_generate, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_json, m)?)?;
    m.add_function(wrap_pyfunction!(discrepancy, m)?)?;
    m.add_function(wrap_pyfunction!(baseline, m)?)?;
    m.add_function(wrap_pyfunction!(baselines, m)?)?;
    m.add_function(wrap_pyfunction!(integrate_json, m)?)?;
    Ok(())
}
