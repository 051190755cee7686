//! Sobol' indices for Python: the library's `Sensitivity` state machine as a class (the
//! Python side evaluates f on each batch, in one process or on an executor), and the
//! check that a design space's inputs are independent.

use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use stillpoint::cubature::StopReason;
use stillpoint::design::DesignSpace;
use stillpoint::sensitivity::{FirstOrder, Sensitivity, SensitivityOptions};
use stillpoint::PointSet;

use super::cubature::{hand_out, pickled, take_values, unpickled};
use super::value_error;

/// The state of a sensitivity analysis: `next_points()` gives the next batch (for each
/// point of each replicate, its rows A, B, AB_1 … AB_d; None when max_n would be
/// passed), `feed(values)` takes f's values there as an (n, k) array; `current` gives
/// (first, total, first half-width, total half-width), each d × k input-major.
/// Picklable.
#[pyclass(name = "Sensitivity", module = "stillpoint._core")]
pub(crate) struct PySensitivity {
    inner: Sensitivity,
    /// The batch handed out and not yet fed (not pickled: it is made again).
    batch: Option<PointSet>,
}

#[pymethods]
impl PySensitivity {
    #[new]
    #[pyo3(signature = (d, abs_tol=0.01, level=0.95, simultaneous=false,
                        first_order="saltelli", replicates=8, max_n=1u64 << 22,
                        seed=0, a=None, b=None, names=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        d: usize,
        abs_tol: f64,
        level: f64,
        simultaneous: bool,
        first_order: &str,
        replicates: usize,
        max_n: u64,
        seed: u64,
        a: Option<Vec<f64>>,
        b: Option<Vec<f64>>,
        names: Option<Vec<String>>,
    ) -> PyResult<Self> {
        let options = SensitivityOptions {
            a,
            b,
            names,
            abs_tol,
            level,
            simultaneous,
            first_order: FirstOrder::parse("first_order", first_order).map_err(value_error)?,
            replicates,
            max_n,
            seed,
            ..SensitivityOptions::default()
        };
        let inner = Sensitivity::new(d, options).map_err(value_error)?;
        Ok(PySensitivity { inner, batch: None })
    }

    /// The next batch of points as an (R·m·(d + 2), d) array (asking again before
    /// `feed` gives the same batch); None when the budget is spent.
    fn next_points<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        hand_out(py, &mut self.batch, self.inner.next_points())
    }

    /// f's values at the batch of `next_points()`, an (n, k) array.
    fn feed(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        take_values(&mut self.inner, &mut self.batch, values)
    }

    /// A new tolerance; the evaluations made are kept.
    fn set_tolerance(&mut self, abs_tol: f64) -> PyResult<()> {
        self.inner.set_tolerance(abs_tol).map_err(value_error)
    }

    /// A new budget (a larger one continues a run stopped by max_n).
    fn set_max_n(&mut self, max_n: u64) -> PyResult<()> {
        self.inner.set_max_n(max_n).map_err(value_error)
    }

    /// A new confidence level (the half-widths are recomputed).
    fn set_level(&mut self, level: f64) -> PyResult<()> {
        self.inner.set_level(level).map_err(value_error)
    }

    /// Whether the intervals hold all together (Bonferroni) or each on its own.
    fn set_simultaneous(&mut self, simultaneous: bool) {
        self.inner.set_simultaneous(simultaneous)
    }

    /// (first, total, first half-width, total half-width), each d·k values, input-major.
    #[getter]
    fn current(&self) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let [a, b, c, d] = self.inner.current();
        (a, b, c, d)
    }

    /// Why the run stops here: "met", "max_n" or "sequence"; None while another
    /// doubling may be made.
    #[getter]
    fn reason(&self) -> Option<&'static str> {
        self.inner.reason().map(StopReason::as_str)
    }

    /// (abs_tol, level, simultaneous, first_order, replicates, max_n, seed).
    #[getter]
    fn settings(&self) -> (f64, f64, bool, &'static str, usize, u64, u64) {
        let o = self.inner.options();
        (
            o.abs_tol,
            o.level,
            o.simultaneous,
            o.first_order.as_str(),
            o.replicates,
            o.max_n,
            o.seed,
        )
    }

    /// Evaluations of f so far.
    #[getter]
    fn n(&self) -> u64 {
        self.inner.n()
    }

    /// The number of inputs d.
    #[getter]
    fn d(&self) -> usize {
        self.inner.d()
    }

    /// The inputs' names.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.names().to_vec()
    }

    /// Outputs of f (0 before the first values).
    #[getter]
    fn outputs(&self) -> usize {
        self.inner.outputs()
    }

    /// Whether every half-width is within abs_tol.
    #[getter]
    fn met(&self) -> bool {
        self.inner.met()
    }

    /// Warnings about the settings (too few replicates).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings()
    }

    fn __getnewargs__(&self) -> (usize,) {
        (self.inner.d(),)
    }

    fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        pickled(py, &self.inner)
    }

    fn __setstate__(&mut self, state: &[u8]) -> PyResult<()> {
        self.inner = unpickled(state)?;
        self.batch = None;
        Ok(())
    }
}

/// Refuses a space whose inputs are not independent (a correlation, a Brownian path),
/// naming `space`, after the checks `quad` makes of its space.
#[pyfunction]
pub(crate) fn sensitivity_space(space: Vec<String>) -> PyResult<()> {
    let parsed = DesignSpace::parse("space", &space).map_err(value_error)?;
    stillpoint::sensitivity::check_independent("space", &parsed).map_err(value_error)
}

/// Registers the class and the check in the extension module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySensitivity>()?;
    m.add_function(wrap_pyfunction!(sensitivity_space, m)?)?;
    Ok(())
}
