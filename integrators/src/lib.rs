//! Integrators that drive a point set to rest under an energy in a domain, and the one
//! executor that runs them.
//!
//! A [`Problem`] holds an energy and its domain, checked to agree. An [`Integrator`] says
//! how to start and how to take one step from its serialisable state; the [`Executor`]
//! owns the loop, the budget, the stop rules, the records, the [`Observer`] (progress
//! bars, discrepancy logging, early stop) and checkpoints ([`Snapshot`]), so every
//! integrator can be observed, checkpointed and resumed bit for bit. [`Dem`] is the
//! damped central-difference scheme of the paper (eqs. 21–26, parameters eqs. 39–41,
//! periodic wrap eq. 42, restart for unbiasedness eqs. 43–45); [`lbfgs::Lbfgs`] is
//! argmin's L-BFGS over the same problems. Every run returns its trajectory as
//! [`Record`]s so that runs can be compared side by side.
#![deny(missing_docs)]

mod dem;
mod executor;
pub mod lbfgs;
mod problem;

pub use dem::{Dem, DemState, Kappa, Restart};
pub use executor::{Best, Executor, Integrator, Move, SaveSnapshot, Snapshot, Step};
pub use problem::Problem;

use serde::{Deserialize, Deserializer, Serialize};
use stillpoint_energies::PointSet;

/// One entry of a trajectory: the state x^(step) before the step is taken.
///
/// Serialised as `{"step", "energy", "seconds", "max_move", "restarted", "metrics":
/// [[name, value], ..]}`; a non-finite number is written as `null` by JSON writers and
/// read back as NaN.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Step index j of x^(j); 0 is the start.
    pub step: usize,
    /// Energy at x^(j).
    #[serde(deserialize_with = "number_or_nan")]
    pub energy: f64,
    /// Wall time since the run began, in seconds (not part of any reproducible output).
    #[serde(deserialize_with = "number_or_nan")]
    pub seconds: f64,
    /// Largest coordinate change of the step that produced x^(j) (0 at the start).
    #[serde(deserialize_with = "number_or_nan")]
    pub max_move: f64,
    /// Whether x^(j) came from a restart (§4.3) rather than a dynamic step.
    pub restarted: bool,
    /// Extra named values an observer attached (for example discrepancies every k steps).
    #[serde(deserialize_with = "metrics_or_nan")]
    pub metrics: Vec<(String, f64)>,
}

/// f64 in JSON that may be ±∞ or NaN: finite values as numbers, the others as the
/// strings `"inf"`, `"-inf"` and `"NaN"`, so that a checkpoint keeps every bit.
mod json_f64 {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_f64(*v)
        } else if v.is_nan() {
            s.serialize_str("NaN")
        } else if *v > 0.0 {
            s.serialize_str("inf")
        } else {
            s.serialize_str("-inf")
        }
    }

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Raw {
        Number(f64),
        Text(String),
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        match Raw::deserialize(d)? {
            Raw::Number(v) => Ok(v),
            Raw::Text(t) => match t.as_str() {
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                "NaN" => Ok(f64::NAN),
                _ => Err(serde::de::Error::custom(format!("not a number: {t}"))),
            },
        }
    }
}

fn number_or_nan<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

fn metrics_or_nan<'de, D: Deserializer<'de>>(
    d: D,
) -> std::result::Result<Vec<(String, f64)>, D::Error> {
    let raw = Vec::<(String, Option<f64>)>::deserialize(d)?;
    Ok(raw
        .into_iter()
        .map(|(k, v)| (k, v.unwrap_or(f64::NAN)))
        .collect())
}

/// What an observer asks the integrator to do next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on.
    Continue,
    /// Stop now and return the current state.
    Stop,
}

/// Called by an integrator with every record, before it is stored.
pub trait Observer {
    /// Sees the record and the points it describes; may attach metrics to the record.
    fn observe(&mut self, record: &mut Record, points: &PointSet) -> Control;
}

/// An observer that does nothing.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoObserver;

impl Observer for NoObserver {
    fn observe(&mut self, _record: &mut Record, _points: &PointSet) -> Control {
        Control::Continue
    }
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The step budget was used up.
    StepBudget,
    /// Steps and forces fell below the tolerance.
    Converged,
    /// An observer asked to stop.
    Observer,
}

/// The outcome of a run.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// The final points.
    pub points: PointSet,
    /// One record per state visited, starting with the start; the last record describes
    /// the returned points (for a non-smooth energy the DEM returns the lowest state seen
    /// and repeats its record at the end).
    pub trajectory: Vec<Record>,
    /// Why the run ended.
    pub stop: StopReason,
    /// Free-form facts about the run (κ used, restarts, trials), for reports.
    pub info: Vec<(String, f64)>,
}

impl RunOutput {
    /// A value from [`RunOutput::info`] by name.
    pub fn info(&self, key: &str) -> Option<f64> {
        self.info.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
    }
}
