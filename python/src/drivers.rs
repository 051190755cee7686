//! Integration to a tolerance and Sobol' indices for Python: the library's state machines
//! `Cubature` and `Sensitivity` as classes, made from `quad`'s and `sobol_indices`'s
//! keyword arguments by the library's one resolution (`Cubature::from_request`:
//! defaults, checks and refused combinations; the keywords read by
//! [`stillpoint::pipeline::calls::with_request`]); the Python side evaluates f on each
//! batch. Also the extensible randomised lattice sequence's points by index.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use stillpoint::cubature::{Cubature, QuadOptions, Rule, StopReason};
use stillpoint::pipeline::calls::{feed, space_parts, with_request};
use stillpoint::pipeline::integration::FromRequest;
use stillpoint::sensitivity::{Sensitivity, SensitivityOptions};
use stillpoint::sequences::{ExtensibleLattice, SequenceTable};
use stillpoint::PointSet;

use super::{keywords, to_array, value_error};

/// What `resolve` returns besides the state: the space's names and its correlation,
/// row-major (for the map Python applies to each batch).
type SpaceParts = (Option<Vec<String>>, Option<Vec<f64>>);

/// Declares a driver class: made from keyword arguments (or continued), handing out
/// batches and taking f's values, its figures as getters, picklable (JSON, readable by
/// later versions; an earlier version's pickles load).
macro_rules! driver {
    ($py:ident, $name:literal, $inner:ident, $options:ident,
     { $($getter:ident -> $t:ty = $e:expr;)* } $($extra:item)*) => {
        #[doc = concat!("The state of a `", $name, "` run (see the module documentation).")]
        #[pyclass(name = $name, module = "stillpoint._core")]
        pub(crate) struct $py {
            inner: $inner,
            /// The batch handed out and not yet fed (not pickled: it is made again).
            batch: Option<PointSet>,
        }

        #[pymethods]
        impl $py {
            /// A state of d inputs with the defaults (unpickling makes one, then sets
            /// its state).
            #[new]
            fn new(d: usize) -> PyResult<Self> {
                let inner = $inner::new(d, $options::default()).map_err(value_error)?;
                Ok($py { inner, batch: None })
            }

            /// The state the keyword arguments ask for, or `start` continued with them;
            /// and the space's names and correlation.
            #[staticmethod]
            #[pyo3(signature = (start=None, **kwargs))]
            fn resolve(
                start: Option<PyRef<'_, Self>>,
                kwargs: Option<&Bound<'_, PyDict>>,
            ) -> PyResult<(Self, SpaceParts)> {
                let (inner, space) = with_request(keywords(kwargs)?.0, |r, sp| match &start {
                    Some(s) => s.inner.continued(r, sp).map(|i| (i, None)),
                    None => $inner::from_request(r, sp),
                })
                .map_err(value_error)?;
                Ok(($py { inner, batch: None }, space_parts(space)))
            }

            /// The next batch as an array (the same until it is fed); None when the
            /// budget is spent.
            fn next_points<'py>(
                &mut self,
                py: Python<'py>,
            ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
                let Some(points) = self.inner.next_points() else {
                    return Ok(None);
                };
                self.batch = Some(points.clone());
                to_array(py, points).map(Some)
            }

            /// f's values at the batch of `next_points()`, an (n, k) array.
            fn feed(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
                let v: Vec<f64> = values.as_array().iter().copied().collect();
                feed(&mut self.inner, &mut self.batch, &v).map_err(value_error)
            }

            /// Why the run stops here ([`StopReason::as_str`]); None while another
            /// doubling may be made.
            #[getter]
            fn reason(&self) -> Option<&'static str> {
                self.inner.reason().map(StopReason::as_str)
            }

            $(
                #[getter]
                fn $getter(&self) -> $t {
                    read(&self.inner, $e)
                }
            )*

            /// The progress line after a round (the library's, as the command line
            /// prints it), `prefix` first.
            fn progress_line(&self, prefix: &str, seconds: f64) -> String {
                self.inner.progress_line(prefix, seconds)
            }

            $($extra)*

            fn __getnewargs__(&self) -> (usize,) {
                (self.inner.d(),)
            }

            fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
                let bytes = serde_json::to_vec(&self.inner).map_err(value_error)?;
                Ok(PyBytes::new(py, &bytes))
            }

            fn __setstate__(&mut self, state: &[u8]) -> PyResult<()> {
                self.inner = serde_json::from_slice(state).map_err(value_error)?;
                self.batch = None;
                Ok(())
            }
        }
    };
}

/// `f` applied to a state (lets the getters' closures infer their argument's type).
fn read<T, R>(state: &T, f: impl Fn(&T) -> R) -> R {
    f(state)
}

driver!(PyCubature, "Cubature", Cubature, QuadOptions, {
    settings -> (f64, f64, f64, usize, u64, u64) = |s: &Cubature| {
        let o = s.options();
        (o.abs_tol, o.rel_tol, o.level, o.replicates, o.max_n, o.seed)
    };
    // While a face test is the next batch (over the cube, or after a probe that found f
    // not even) the rule reads "face test": its values choose the rule and may be
    // infinite.
    rule -> (&'static str, String) = |s: &Cubature| {
        let rule = if s.face_test_due() {
            Rule::FaceTest.as_str()
        } else {
            s.options().rule.as_str()
        };
        (rule, s.options().rule_reason.clone())
    };
    round_change -> Vec<Option<f64>> = Cubature::round_change;
    estimate -> Vec<f64> = Cubature::estimate;
    half_width -> Vec<f64> = Cubature::half_width;
    n -> u64 = Cubature::n;
    replicates -> usize = |s: &Cubature| s.options().replicates;
    d -> usize = Cubature::d;
    outputs -> usize = Cubature::outputs;
    met -> bool = Cubature::met;
    warnings -> Vec<String> = Cubature::warnings;
    replicate_means -> Vec<Vec<f64>> = Cubature::replicate_means;
    // A round larger than the library's batch comes as several batches: true while
    // some are fed and others due (no figure has moved since the last round).
    in_round -> bool = Cubature::in_round;
}
    /// Refuses an estimate or half-width beyond the largest float (where the run stops).
    fn check_representable(&self) -> PyResult<()> {
        self.inner.check_representable().map_err(value_error)
    }
);

driver!(PySensitivity, "Sensitivity", Sensitivity, SensitivityOptions, {
    current -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) = |s: &Sensitivity| {
        let [a, b, c, d] = s.current();
        (a, b, c, d)
    };
    settings -> (f64, f64, bool, &'static str, usize, u64, u64) = |s: &Sensitivity| {
        let o = s.options();
        let first = o.first_order.as_str();
        (o.abs_tol, o.level, o.simultaneous, first, o.replicates, o.max_n, o.seed)
    };
    second -> (Vec<f64>, Vec<f64>) = |s: &Sensitivity| {
        let [a, b] = s.second();
        (a, b)
    };
    second_order -> bool = |s: &Sensitivity| s.options().second_order;
    interval -> &'static str = |s: &Sensitivity| s.interval_used().as_str();
    n -> u64 = Sensitivity::n;
    d -> usize = Sensitivity::d;
    names -> Vec<String> = |s: &Sensitivity| s.names().to_vec();
    outputs -> usize = Sensitivity::outputs;
    met -> bool = Sensitivity::met;
    warnings -> Vec<String> = Sensitivity::warnings;
    // As the Cubature's, for a doubling.
    in_round -> bool = Sensitivity::in_round;
});

/// Points [start, start + count) of replicate `replicate` of the extensible randomised
/// lattice sequence in d dimensions seeded by `seed`, as a (count, d) array; `table`
/// names its generating vector ('tent', quad's, or 'first-order', the engine's), or
/// 'sobol' for Owen-scrambled Sobol' points in natural order instead of the lattice.
#[pyfunction]
#[pyo3(signature = (d, seed=0, replicate=0, start=0, count=1, table="tent"))]
fn sequence_points<'py>(
    py: Python<'py>,
    d: usize,
    seed: u64,
    replicate: u64,
    start: u64,
    count: usize,
    table: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let data = if table == "sobol" {
        owen_sobol(d, seed, replicate, start, count)?
    } else {
        let table = SequenceTable::from_name(table).map_err(|_| {
            value_error(format!(
                "invalid table = {table}: expected 'tent' (quad's), 'first-order' (the \
                 engine's) or 'sobol' (Owen-scrambled Sobol' points)"
            ))
        })?;
        let seq = ExtensibleLattice::with_table(table, d, seed, replicate).map_err(value_error)?;
        let mut data = vec![0.0; count * d];
        seq.fill(start, count, &mut data).map_err(value_error)?;
        data
    };
    Ok(Array2::from_shape_vec((count, d), data)
        .map_err(value_error)?
        .into_pyarray(py))
}

/// The label of the engine's scrambles ([`stillpoint::sequences::hash2`]), apart from
/// those `quad` and the Sobol' indices draw from the same seed.
const ENGINE_SOBOL_KEY: u64 = 0x656e_6769_6e65_736f;

/// Points `start..start + count` of one replicate of Owen-scrambled Sobol' points in
/// natural order (a sequence of at most 2^20 points, scrambled as `quad`'s Sobol' rule
/// scrambles one), row-major.
fn owen_sobol(d: usize, seed: u64, replicate: u64, start: u64, count: usize) -> PyResult<Vec<f64>> {
    use stillpoint::sequences::{hash2, mix64, sobol_scrambled_short_ranges};
    const MOST: usize = 1 << 20;
    let start = usize::try_from(start).map_err(value_error)?;
    if start.saturating_add(count) > MOST {
        return Err(value_error(format!(
            "invalid start = {start}: start + count = {} passes the sequence's {MOST} points",
            start.saturating_add(count)
        )));
    }
    if count == 0 || d == 0 {
        return Ok(Vec::new());
    }
    let scramble = hash2(hash2(mix64(seed), ENGINE_SOBOL_KEY), replicate);
    let mut sets = sobol_scrambled_short_ranges(start, start + count, d, &[scramble], MOST)
        .map_err(value_error)?;
    Ok(sets
        .pop()
        .expect("one set per scramble")
        .as_slice()
        .to_vec())
}

/// Registers the classes and the sequence's points in the extension module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCubature>()?;
    m.add_class::<PySensitivity>()?;
    m.add_function(wrap_pyfunction!(sequence_points, m)?)?;
    Ok(())
}
