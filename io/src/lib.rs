//! Reading and writing point sets as files: CSV/TSV text, JSON and NumPy `.npy`.
//!
//! Reading is forgiving about layout (delimiters, comments, a header line) and strict
//! about content: every refusal names the file and what is wrong. Writing is atomic, so a
//! crash or a full disk never leaves a half-written point set behind, and every format
//! round-trips the coordinates bit for bit.
//!
//! This module picks the format (by extension, or by content for a file that names
//! none) and bounds what is read; each format is a module of its own: `text`
//! (delimited text, split by the csv crate), `json`, `npy`, the header lines of text
//! files (`header`) and atomic writing (`atomic`).

#![deny(missing_docs)]

use stillpoint_domains::{Error, PointSet};

use std::fs;
use std::path::{Path, PathBuf};

mod atomic;
pub(crate) mod header;
mod json;
mod npy;
pub(crate) mod text;

pub use atomic::{abandon_writes, check_output, write_atomic, Staging, MAX_OUTPUT_NAME};
pub use header::{push_header, push_meta_comments};
pub use json::MAX_JSON_DEPTH;
pub use text::{parse_text, records, unquote, Records};

/// A point-set file format, chosen by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated text with `#` comment lines and an `x1,x2,...` header.
    Csv,
    /// Tab-separated text, otherwise as [`Format::Csv`].
    Tsv,
    /// `{"n": .., "s": .., "meta": {..}, "points": [[..], ..]}`.
    Json,
    /// NumPy `.npy`: float64, shape `[n, s]`, C order.
    Npy,
}

impl Format {
    /// The format for a path by its extension (case-insensitive): `.csv`, `.tsv`/`.tab`,
    /// `.json`, `.npy`; anything else, or no extension, is [`Format::Csv`].
    pub fn from_path(path: &Path) -> Format {
        Format::from_extension(path).unwrap_or(Format::Csv)
    }

    /// `None` for an extension that names no format, which reading treats as "look at the
    /// content" rather than assuming CSV.
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(Format::Csv),
            "tsv" | "tab" => Some(Format::Tsv),
            "json" => Some(Format::Json),
            "npy" => Some(Format::Npy),
            _ => None,
        }
    }
}

/// Why a point-set file could not be read or written. Every message starts with the file.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused to read, create, write or rename a file.
    #[error("{}: {action}: {error}", path.display())]
    Io {
        /// The file the caller asked for (not the temporary file of an atomic write).
        path: PathBuf,
        /// What was being attempted, e.g. `cannot read`.
        action: String,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// A text field that should hold a number does not.
    #[error("{file}: line {line}, field {field}: {}", not_a_number(.text))]
    NotANumber {
        /// The file (or source name) being parsed.
        file: String,
        /// 1-based line number in the file, counting comments and blank lines.
        line: usize,
        /// 1-based field number within the line.
        field: usize,
        /// The offending field as written.
        text: String,
    },
    /// Two text rows with different numbers of coordinates.
    #[error(
        "{file}: line {line} has {}, line {first_line} has {first_count} \
         (every point needs the same number)",
        coordinates(*.count)
    )]
    Ragged {
        /// The file (or source name) being parsed.
        file: String,
        /// The line that disagrees.
        line: usize,
        /// Its number of coordinates.
        count: usize,
        /// The first data line, which fixed the dimension.
        first_line: usize,
        /// The dimension it fixed.
        first_count: usize,
    },
    /// The file holds no points at all.
    #[error("{file}: no points found")]
    Empty {
        /// The file (or source name) being parsed.
        file: String,
    },
    /// The file is not laid out as a point set (wrong JSON shape, wrong array dtype or
    /// rank, invalid UTF-8, ...); the message says what was found and what is accepted.
    #[error("{file}: {message}")]
    Format {
        /// The file (or source name) being parsed.
        file: String,
        /// What is wrong and what is accepted.
        message: String,
    },
    /// The numbers parsed but do not make a point set (a NaN or infinite coordinate).
    #[error("{file}: {error}")]
    Points {
        /// The file (or source name) being parsed.
        file: String,
        /// The refusal from [`PointSet::new`] or an equivalent one with a line number.
        error: Error,
    },
}

fn not_a_number(text: &str) -> String {
    if text.is_empty() {
        "empty field (expected a number)".to_string()
    } else {
        let shown: String = text.chars().take(40).collect();
        let dots = if shown.len() < text.len() { "..." } else { "" };
        format!("{shown:?}{dots} is not a number")
    }
}

fn coordinates(count: usize) -> String {
    if count == 1 {
        "1 coordinate".to_string()
    } else {
        format!("{count} coordinates")
    }
}

fn io_error(path: &Path, action: impl Into<String>, error: std::io::Error) -> IoError {
    IoError::Io {
        path: path.to_path_buf(),
        action: action.into(),
        error,
    }
}

fn format_error(file: &str, message: impl Into<String>) -> IoError {
    IoError::Format {
        file: file.to_string(),
        message: message.into(),
    }
}

// ---------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------

/// The largest input file the readers take: 1 GiB, about 25 million points in 2-D as
/// CSV or 6 million in 20-D as `.npy` — far more than any set this tool optimises.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The whole of a file, refused beyond [`MAX_INPUT_BYTES`] — also a device or a pipe that
/// never ends, which is read only up to the bound.
pub fn read_bounded(path: &Path) -> Result<Vec<u8>, IoError> {
    use std::io::Read;
    let too_large = || {
        format_error(
            &path.display().to_string(),
            format!(
                "larger than {} MiB, the most a point file may hold",
                MAX_INPUT_BYTES >> 20
            ),
        )
    };
    let file = fs::File::open(path).map_err(|e| io_error(path, "cannot read", e))?;
    if let Ok(meta) = file.metadata() {
        if meta.is_dir() {
            return Err(format_error(
                &path.display().to_string(),
                "a directory, expected a point file",
            ));
        }
        if meta.is_file() && meta.len() > MAX_INPUT_BYTES {
            return Err(too_large());
        }
    }
    let mut bytes = Vec::new();
    file.take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io_error(path, "cannot read", e))?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Reads a point set from `path`.
///
/// The NumPy magic bytes select `.npy` whatever the extension. Otherwise `.npy` and
/// `.json` are read as such, `.csv`/`.tsv`/`.tab` as text ([`parse_text`]), and any other
/// extension by content: JSON if it starts with `{` or `[`, text otherwise. The [0, 1]
/// range is not checked here.
pub fn read_points(path: &Path) -> Result<PointSet, IoError> {
    let bytes = read_bounded(path)?;
    let file = path.display().to_string();
    if bytes.starts_with(npy::NPY_MAGIC) {
        return npy::parse_npy(&bytes, &file);
    }
    let format = Format::from_extension(path);
    if format == Some(Format::Npy) {
        return Err(format_error(
            &file,
            "not a NumPy .npy file (it does not start with the \\x93NUMPY magic bytes)",
        ));
    }
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        format_error(
            &file,
            format!(
                "not UTF-8 text (invalid byte at offset {}); expected CSV/TSV text, JSON or .npy",
                e.valid_up_to()
            ),
        )
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let is_json = match format {
        Some(Format::Json) => true,
        Some(_) => false,
        None => matches!(text.trim_start().as_bytes().first(), Some(b'{' | b'[')),
    };
    if is_json {
        json::parse_json(text, &file)
    } else {
        text::parse_text(text, &file)
    }
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

/// The bytes of `points` in `format`, exactly as [`write_points`] stores them. `meta` (a
/// JSON object; `null` for none) goes into the comment lines of CSV/TSV and under the
/// `"meta"` key of JSON, and is dropped for `.npy`.
pub fn encode(points: &PointSet, meta: &serde_json::Value, format: Format) -> Vec<u8> {
    match format {
        Format::Csv => text::to_text(points, meta, ',').into_bytes(),
        Format::Tsv => text::to_text(points, meta, '\t').into_bytes(),
        Format::Json => json::to_json(points, meta).into_bytes(),
        Format::Npy => npy::to_npy(points),
    }
}

/// The CSV form of `points` (as [`write_points`] writes a `.csv`), e.g. for stdout:
/// `# stillpoint <version>`, one `# key: value` line per entry of `meta`, the header
/// `x1,...,xs`, then one row per point.
pub fn to_csv_string(points: &PointSet, meta: &serde_json::Value) -> String {
    text::to_text(points, meta, ',')
}

/// Writes `points` to `path` atomically in the format its extension names
/// ([`Format::from_path`]; CSV when it names none).
///
/// CSV/TSV start with `#` comment lines (version, then `key: value` per entry of `meta`)
/// and a header line; JSON is `{"stillpoint": version, "n", "s", "meta": meta, "points"}`
/// with `meta` kept under its own key so that it can never clobber the data; NPY is
/// float64 `[n, s]` in C order without `meta`. Reading any of them back with
/// [`read_points`] gives identical bits.
pub fn write_points(
    path: &Path,
    points: &PointSet,
    meta: &serde_json::Value,
) -> Result<(), IoError> {
    let text = |sep| move |w: &mut dyn std::io::Write| text::write_text(w, points, meta, sep);
    match Format::from_path(path) {
        // Streamed: the text is the largest form, several times the points' memory.
        Format::Csv => atomic::write_atomic_with(path, &text(',')),
        Format::Tsv => atomic::write_atomic_with(path, &text('\t')),
        // Streamed too: a copy would double the peak of a large run.
        Format::Npy => atomic::write_atomic_with(path, &|w| npy::write_npy(w, points)),
        format => write_atomic(path, &encode(points, meta, format)),
    }
}
