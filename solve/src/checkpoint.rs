//! Checkpoint files: where a run writes its snapshots and how often ([`CheckpointPlan`]),
//! the file's layout (format, version, the run's settings, a checksum and the executor's
//! snapshot as JSON), and the checks a file passes before a run continues from it. The
//! snapshot itself is untrusted until the executor has checked it against the run.

use crate::Error;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};
use stillpoint_integrators::Snapshot;

/// The `format` field of every checkpoint file.
pub const CHECKPOINT_FORMAT: &str = "stillpoint checkpoint";

/// The layout version of checkpoint files this build reads and writes.
pub const CHECKPOINT_VERSION: u32 = 2;

/// Where a run writes its checkpoints, how often, and where it resumes from.
#[derive(Debug, Clone)]
pub struct CheckpointPlan {
    /// The checkpoint file, replaced atomically every `every` steps.
    pub path: PathBuf,
    /// Steps between checkpoints (0: none are written; a resume still reads `resume`).
    pub every: usize,
    /// A checkpoint to continue from (often `path` itself).
    pub resume: Option<PathBuf>,
    /// More configuration to record and compare on resume, beyond what the run's own
    /// configuration holds (for example the text of a region's expression).
    pub extra: Value,
    /// How the caller names a setting when a resume is refused for a difference (the
    /// command line shows its flags); the parameter's own name by default.
    pub names: fn(&str) -> String,
}

impl CheckpointPlan {
    /// Checkpoints to `path` every `every` steps, no resume.
    pub fn new(path: impl Into<PathBuf>, every: usize) -> Self {
        CheckpointPlan {
            path: path.into(),
            every,
            resume: None,
            extra: Value::Null,
            names: str::to_string,
        }
    }

    fn config(&self, config: &Value) -> Value {
        let mut config = config.clone();
        if let (Value::Object(map), Value::Object(extra)) = (&mut config, &self.extra) {
            for (k, v) in extra {
                map.insert(k.clone(), v.clone());
            }
        }
        config
    }

    /// Writes `state` to [`CheckpointPlan::path`] atomically.
    pub(crate) fn save<S: Serialize>(
        &self,
        config: &Value,
        state: &Snapshot<S>,
    ) -> Result<(), Error> {
        let bytes = encode_checkpoint(&self.config(config), state).map_err(|e| {
            Error::invalid(
                stillpoint_parse::names::CHECKPOINT,
                self.path.display(),
                format!("a state that can be written as JSON ({e})"),
            )
        })?;
        stillpoint_io::write_atomic(&self.path, &bytes).map_err(|e| {
            Error::invalid(
                stillpoint_parse::names::CHECKPOINT,
                self.path.display(),
                format!("a file that can be written ({e})"),
            )
        })
    }

    /// Reads [`CheckpointPlan::resume`], if set, and checks it against `config`.
    pub(crate) fn load_state<S: DeserializeOwned>(
        &self,
        config: &Value,
    ) -> Result<Option<Snapshot<S>>, Error> {
        let Some(path) = &self.resume else {
            return Ok(None);
        };
        let checkpoint = read_checkpoint(path)?;
        let expected = self.config(config);
        let differences = config_differences(&checkpoint.config, &expected, self.names);
        if !differences.is_empty() {
            return Err(Error::invalid(
                "resume checkpoint",
                path.display(),
                format!(
                    "a checkpoint of this configuration; it was made with {} (resume with the \
                     same settings, or start afresh)",
                    differences.join(", ")
                ),
            ));
        }
        serde_json::from_value(checkpoint.state)
            .map(Some)
            .map_err(|e| {
                Error::invalid(
                    "resume checkpoint",
                    path.display(),
                    format!("a checkpoint of this run's solver ({e})"),
                )
            })
    }
}

/// A checkpoint file: what made it and the executor's [`Snapshot`] (kept as JSON here,
/// read into the solver's state type when resumed).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Always [`CHECKPOINT_FORMAT`].
    pub format: String,
    /// The layout version, [`CHECKPOINT_VERSION`].
    pub version: u32,
    /// The stillpoint version that wrote it; a resume needs the same one, since another
    /// version may step differently.
    pub stillpoint: String,
    /// The run's configuration, as `stillpoint::config::config_json` gives it (plus the plan's extra keys).
    pub config: Value,
    /// FNV-1a 64 of the compact JSON of `state`, in hex: detects an edited or damaged
    /// state that still parses.
    pub checksum: String,
    /// The snapshot of the run.
    pub state: Value,
}

/// FNV-1a, 64 bits: a fixed, dependency-free fingerprint (not a cryptographic hash).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The bytes of a checkpoint file for `state` under `config`.
pub fn encode_checkpoint<S: Serialize>(
    config: &Value,
    state: &Snapshot<S>,
) -> serde_json::Result<Vec<u8>> {
    let state = serde_json::to_value(state)?;
    let checksum = format!("{:016x}", fnv1a64(&serde_json::to_vec(&state)?));
    serde_json::to_vec(&Checkpoint {
        format: CHECKPOINT_FORMAT.to_string(),
        version: CHECKPOINT_VERSION,
        stillpoint: env!("CARGO_PKG_VERSION").to_string(),
        config: config.clone(),
        checksum,
        state,
    })
}

/// Reads and checks a checkpoint file: its format, version, checksum and the shape of
/// its state. Every refusal names the file and says what is accepted.
pub fn read_checkpoint(path: &Path) -> Result<Checkpoint, Error> {
    let refuse = |why: String| {
        Error::invalid(
            "resume checkpoint",
            path.display(),
            format!("a stillpoint checkpoint file ({why})"),
        )
    };
    let bytes =
        stillpoint_io::read_bounded(path).map_err(|e| refuse(format!("cannot read it: {e}")))?;
    let head: Value = serde_json::from_slice(&bytes).map_err(|e| {
        refuse(format!(
            "not valid JSON, the file is damaged or truncated: {e}"
        ))
    })?;
    if head.get("format").and_then(Value::as_str) != Some(CHECKPOINT_FORMAT) {
        return Err(refuse(format!(
            "it has no \"format\": \"{CHECKPOINT_FORMAT}\" field"
        )));
    }
    if head.get("version").and_then(Value::as_u64) != Some(CHECKPOINT_VERSION as u64) {
        return Err(refuse(format!(
            "layout version {}, this build reads version {CHECKPOINT_VERSION}",
            head.get("version").unwrap_or(&Value::Null)
        )));
    }
    let made_by = head
        .get("stillpoint")
        .and_then(Value::as_str)
        .unwrap_or("?");
    if made_by != env!("CARGO_PKG_VERSION") {
        return Err(refuse(format!(
            "made by stillpoint {made_by}, this is {}; another version may step differently",
            env!("CARGO_PKG_VERSION")
        )));
    }
    let checkpoint: Checkpoint =
        serde_json::from_value(head).map_err(|e| refuse(format!("its fields are damaged: {e}")))?;
    let state_json = serde_json::to_vec(&checkpoint.state)
        .map_err(|e| refuse(format!("its state cannot be re-encoded: {e}")))?;
    if format!("{:016x}", fnv1a64(&state_json)) != checkpoint.checksum {
        return Err(refuse(
            "its checksum does not match its state: the file was changed or damaged".into(),
        ));
    }
    Ok(checkpoint)
}

/// The settings `expected` holds that `found` (a checkpoint's) does not, as
/// `--key = found (this run: expected)`.
fn config_differences<'a>(
    found: &'a Value,
    expected: &'a Value,
    names: fn(&str) -> String,
) -> Vec<String> {
    let (Value::Object(f), Value::Object(e)) = (found, expected) else {
        return vec![format!("configuration {found} (this run: {expected})")];
    };
    let mut keys: Vec<&String> = f.keys().chain(e.keys()).collect();
    keys.sort();
    keys.dedup();
    // A key that is absent and a key that is null both mean "not set".
    let get = |m: &'a serde_json::Map<String, Value>, k: &str| m.get(k).filter(|v| !v.is_null());
    keys.into_iter()
        .filter(|k| get(f, k) != get(e, k))
        .map(|k| {
            let show = |v: Option<&Value>| match v {
                None | Some(Value::Null) => "(none)".to_string(),
                Some(Value::String(s)) => s.clone(),
                Some(v) => v.to_string(),
            };
            format!(
                "{} = {} (this run: {})",
                names(k),
                show(f.get(k)),
                show(e.get(k))
            )
        })
        .collect()
}
