//! Reading and writing point sets as files: CSV/TSV text, JSON and NumPy `.npy`.
//!
//! Reading is forgiving about layout (delimiters, comments, a header line) and strict
//! about content: every refusal names the file and what is wrong. Writing is atomic, so a
//! crash or a full disk never leaves a half-written point set behind, and every format
//! round-trips the coordinates bit for bit.

use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::{Error, PointSet};

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

const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// The largest input file the readers take: 1 GiB, about 25 million points in 2-D as
/// CSV or 6 million in 20-D as `.npy` — far more than any set this tool optimises.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The deepest nesting of arrays and objects a JSON point file may have (a point file
/// needs 2 or 3 levels, its provenance a few more).
pub const MAX_JSON_DEPTH: usize = 64;

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

/// The deepest nesting of `[` and `{` outside strings, stopping as soon as it passes
/// `limit` (so that no recursive parser is handed a deeper text).
fn json_depth_exceeds(text: &str, limit: usize) -> bool {
    let (mut depth, mut in_string, mut escaped) = (0usize, false, false);
    for b in text.bytes() {
        if in_string {
            match (escaped, b) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => in_string = false,
                _ => {}
            }
            continue;
        }
        match b {
            b'"' => in_string = true,
            b'[' | b'{' => {
                depth += 1;
                if depth > limit {
                    return true;
                }
            }
            b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    false
}

/// Checks a `.npy` header before any other code parses it: the version, a length the
/// format allows, printable ASCII, and one flat dictionary with exactly the keys
/// `descr`, `fortran_order` and `shape` (the header grammar is a Python literal; a
/// general parser of it can take exponential time on nested braces).
fn check_npy_header(bytes: &[u8], file: &str) -> Result<(), IoError> {
    let bad = |why: &str| {
        format_error(
            file,
            format!(
                "not a valid .npy file ({why}); expected a NumPy .npy file of a 2-D float64 \
                 or float32 array"
            ),
        )
    };
    let major = *bytes.get(6).ok_or_else(|| bad("too short"))?;
    let (len, start) = match major {
        1 => (
            u16::from_le_bytes([
                *bytes.get(8).ok_or_else(|| bad("too short"))?,
                *bytes.get(9).ok_or_else(|| bad("too short"))?,
            ]) as usize,
            10,
        ),
        2 | 3 => {
            let b = bytes.get(8..12).ok_or_else(|| bad("too short"))?;
            (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize, 12)
        }
        v => return Err(bad(&format!("format version {v}, expected 1, 2 or 3"))),
    };
    if len > 1 << 16 {
        return Err(bad(&format!(
            "a header of {len} bytes, at most 65536 accepted"
        )));
    }
    let header = bytes
        .get(start..start + len)
        .ok_or_else(|| bad("the header is cut short"))?;
    if !header
        .iter()
        .all(|&b| (0x20..0x7f).contains(&b) || b == b'\n')
    {
        return Err(bad("the header is not printable ASCII"));
    }
    let text = std::str::from_utf8(header).map_err(|_| bad("the header is not ASCII"))?;
    let body = text.trim_end_matches([' ', '\n']);
    let opens = body.matches('{').count();
    let closes = body.matches('}').count();
    if !(body.starts_with('{') && body.ends_with('}') && opens == 1 && closes == 1) {
        return Err(bad("the header is not one flat dictionary"));
    }
    for key in ["descr", "fortran_order", "shape"] {
        if !(body.contains(&format!("'{key}'")) || body.contains(&format!("\"{key}\""))) {
            return Err(bad(&format!("the header has no '{key}'")));
        }
    }
    if body.matches(':').count() != 3 {
        return Err(bad(
            "the header has keys other than 'descr', 'fortran_order' and 'shape'",
        ));
    }
    Ok(())
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
    if bytes.starts_with(NPY_MAGIC) {
        return parse_npy(&bytes, &file);
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
        parse_json(text, &file)
    } else {
        parse_text(text, &file)
    }
}

/// Parses delimited text into a point set; `source` names the input in error messages.
///
/// Blank lines and lines starting with `#` are skipped. The first remaining line fixes the
/// delimiter: `;` if it has one, else `,`, else tab, else runs of whitespace. If every
/// field of that line is non-numeric it is a header and skipped; if only its first field
/// is empty it is a pandas header with an index column, and the first column of every row
/// is dropped. Fields may be padded with spaces or wrapped in double quotes, one trailing
/// delimiter is allowed, and with `;` a decimal comma (`0,5`) is accepted. Every row must
/// have the same number of coordinates and each must be a finite number.
pub fn parse_text(text: &str, source: &str) -> Result<PointSet, IoError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut delim: Option<Delim> = None;
    let mut skip_first_column = false;
    let mut s = 0usize;
    let mut first_line = 0usize;
    let mut n = 0usize;
    let mut data: Vec<f64> = Vec::new();

    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let d = match delim {
            Some(d) => d,
            None => {
                let d = Delim::detect(line);
                delim = Some(d);
                let fields: Vec<&str> = d.fields(raw).collect();
                let names = |f: &[&str]| f.iter().all(|f| parse_field(f, d).is_none());
                // pandas' default `to_csv` writes the index as an unnamed first column, and
                // names columns 0, 1, ... unless told otherwise. An empty first field is
                // otherwise an error, so treating it as this header loses nothing.
                let index_header = fields.len() > 1
                    && fields[0].is_empty()
                    && (names(&fields[1..])
                        || fields[1..]
                            .iter()
                            .enumerate()
                            .all(|(k, f)| *f == k.to_string()));
                if index_header || names(&fields) {
                    skip_first_column = index_header;
                    continue;
                }
                d
            }
        };

        let mut count = 0usize;
        for (f, field) in d.fields(raw).enumerate() {
            if skip_first_column && f == 0 {
                continue;
            }
            let v = parse_field(field, d).ok_or_else(|| IoError::NotANumber {
                file: source.to_string(),
                line: line_no,
                field: f + 1,
                text: field.to_string(),
            })?;
            count += 1;
            if !v.is_finite() {
                return Err(IoError::Points {
                    file: source.to_string(),
                    error: Error::invalid(
                        format!("point {}, coordinate {count} (line {line_no})", n + 1),
                        v,
                        "a finite number",
                    ),
                });
            }
            data.push(v);
        }
        if n == 0 {
            s = count;
            first_line = line_no;
            // The first row tells the width; reserving for the rest of the file by its
            // byte count avoids repeated regrowth on large inputs.
            data.reserve(s * (text.len() / line.len().max(1)));
        } else if count != s {
            return Err(IoError::Ragged {
                file: source.to_string(),
                line: line_no,
                count,
                first_line,
                first_count: s,
            });
        }
        n += 1;
    }

    if n == 0 || s == 0 {
        return Err(IoError::Empty {
            file: source.to_string(),
        });
    }
    PointSet::new(n, s, data).map_err(|error| IoError::Points {
        file: source.to_string(),
        error,
    })
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Delim {
    Char(char),
    Whitespace,
}

impl Delim {
    fn detect(line: &str) -> Delim {
        // `;` first: spreadsheets in decimal-comma locales write `0,5;0,25`.
        for c in [';', ',', '\t'] {
            if line.contains(c) {
                return Delim::Char(c);
            }
        }
        Delim::Whitespace
    }

    /// The trimmed, unquoted fields of a non-blank line, borrowing from it.
    fn fields(self, line: &str) -> impl Iterator<Item = &str> {
        let (by_char, by_space) = match self {
            Delim::Char(c) => {
                // Trimming must keep a leading tab in TSV: it marks an empty first field.
                let line = line.trim_matches(|ch: char| ch.is_whitespace() && ch != c);
                let line = line.strip_suffix(c).unwrap_or(line);
                (Some(line.split(c).map(unquote)), None)
            }
            Delim::Whitespace => (None, Some(line.split_ascii_whitespace().map(unquote))),
        };
        by_char
            .into_iter()
            .flatten()
            .chain(by_space.into_iter().flatten())
    }
}

fn unquote(field: &str) -> &str {
    let field = field.trim();
    field
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .map(str::trim)
        .unwrap_or(field)
}

fn parse_field(field: &str, delim: Delim) -> Option<f64> {
    if let Ok(v) = field.parse::<f64>() {
        return Some(v);
    }
    if delim == Delim::Char(';') && field.contains(',') && !field.contains('.') {
        return field.replacen(',', ".", 1).parse().ok();
    }
    None
}

const JSON_SHAPE: &str = r#"expected {"points": [[x1, x2, ...], ...]} or [[x1, x2, ...], ...]"#;

/// Where in a point file a JSON value sits, which decides what it may be.
#[derive(Debug, Clone, Copy)]
enum Place {
    /// The whole document: the list of points, or an object holding it.
    Root,
    /// The value of the `"points"` key.
    Points,
    /// Point `i` (1-based): a list of coordinates, or one number in a flat list.
    Point(usize),
    /// Coordinate `k` of point `i`.
    Coordinate(usize, usize),
}

/// One read of a JSON point file, in a single pass of serde_json straight into the
/// coordinates (no tree of values in between, which for a large file is many times the
/// size of its numbers).
struct JsonReader<'a> {
    file: &'a str,
    data: Vec<f64>,
    n: usize,
    /// Coordinates per point, fixed by point 1.
    s: usize,
    /// Point 1 was a bare number: the file is a flat list of one-dimensional points.
    flat: bool,
    /// The `"n"` and `"s"` of an object, checked against what `"points"` holds.
    hints: Vec<(&'static str, serde_json::Number)>,
    /// A refusal of ours, kept aside while serde_json unwinds: its errors carry only
    /// text, and a refusal must name the file, the point and what is accepted.
    refusal: Option<IoError>,
    /// The value being read when serde_json stopped, to name a number it cannot hold.
    at: Option<Place>,
}

impl JsonReader<'_> {
    /// The refusal for a read that stopped with `error`.
    fn explain(self, error: serde_json::Error, text: &str) -> IoError {
        let file = self.file;
        if let Some(refusal) = self.refusal {
            return refusal;
        }
        let place = match self.at {
            Some(Place::Coordinate(i, k)) => format!("point {i}, coordinate {k}"),
            Some(Place::Point(i)) if self.flat || i == 1 => format!("point {i}, coordinate 1"),
            Some(Place::Point(i)) => format!("point {i}"),
            _ => return format_error(file, format!("not valid JSON ({error})")),
        };
        // serde_json refuses a number beyond the largest double rather than round it to
        // infinity; say which number, as the text reader does for `inf`.
        let number = number_at(text, error.line(), error.column());
        if number.parse::<f64>().is_ok_and(f64::is_infinite) {
            return IoError::Points {
                file: file.to_string(),
                error: Error::invalid(
                    place,
                    shorten(number),
                    "a finite number, at most 1.7976931348623157e308 in magnitude",
                ),
            };
        }
        format_error(file, format!("{place}: not valid JSON ({error})"))
    }
}

/// The number around serde_json's error position (1-based line; byte column just past
/// what it read), or `""` if there is none.
fn number_at(text: &str, line: usize, column: usize) -> &str {
    let start_of_line: usize = text
        .split('\n')
        .take(line.saturating_sub(1))
        .map(|l| l.len() + 1)
        .sum();
    let at = (start_of_line + column).min(text.len());
    let bytes = text.as_bytes();
    let numeric = |b: &&u8| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E');
    let start = at - bytes[..at].iter().rev().take_while(numeric).count();
    let end = at + bytes[at..].iter().take_while(numeric).count();
    // `get`: with no number there, `at` may fall inside a multi-byte character.
    text.get(start..end).unwrap_or("")
}

/// At most 40 characters of `text`, marked when cut.
fn shorten(text: &str) -> String {
    let shown: String = text.chars().take(40).collect();
    let dots = if shown.len() < text.len() { "..." } else { "" };
    format!("{shown}{dots}")
}

/// The JSON value at `place`, read into `reader`; serves as its own visitor.
struct Seed<'r, 'a> {
    reader: &'r mut JsonReader<'a>,
    place: Place,
}

impl<'de> serde::de::DeserializeSeed<'de> for Seed<'_, '_> {
    type Value = ();

    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let Seed { reader, place } = self;
        reader.at = Some(place);
        d.deserialize_any(Seed {
            reader: &mut *reader,
            place,
        })?;
        reader.at = None;
        Ok(())
    }
}

impl Seed<'_, '_> {
    fn refuse<E: serde::de::Error>(self, refusal: IoError) -> E {
        self.reader.refusal = Some(refusal);
        E::custom("refused")
    }

    fn shape<E: serde::de::Error>(self, detail: String) -> E {
        let refusal = format_error(self.reader.file, format!("{JSON_SHAPE} ({detail})"));
        self.refuse(refusal)
    }

    /// A number: a coordinate, or point 1 of a flat list and any point after it.
    fn number<E: serde::de::Error>(self, v: f64, written: &dyn std::fmt::Debug) -> Result<(), E> {
        match self.place {
            Place::Coordinate(..) => {}
            Place::Point(i) if i == 1 || self.reader.flat => {
                self.reader.flat = true;
                self.reader.s = 1;
            }
            _ => return self.other(&format!("the number {written:?}"), ""),
        }
        self.reader.data.push(v);
        Ok(())
    }

    /// A value that has no place here: `what` describes it, `raw` is its text.
    fn other<E: serde::de::Error>(self, what: &str, raw: &str) -> Result<(), E> {
        let file = self.reader.file;
        Err(match self.place {
            Place::Root => self.shape(format!("got {what}")),
            Place::Points => self.shape(format!("\"points\" is {what}")),
            Place::Point(i) if self.reader.flat => {
                self.shape(format!("point {i} is {what} but point 1 is a number"))
            }
            Place::Point(i) => self.shape(format!("point {i} is {what}, not a list of numbers")),
            Place::Coordinate(i, k) => self.refuse(format_error(
                file,
                format!(
                    "point {i}, coordinate {k}: {} is not a number",
                    shorten(raw)
                ),
            )),
        })
    }

    /// The list of points.
    fn list<'de, A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut n = 0;
        while seq
            .next_element_seed(Seed {
                reader: &mut *self.reader,
                place: Place::Point(n + 1),
            })?
            .is_some()
        {
            n += 1;
        }
        self.reader.n = n;
        Ok(())
    }

    /// The coordinates of point `i`.
    fn row<'de, A: serde::de::SeqAccess<'de>>(self, i: usize, mut seq: A) -> Result<(), A::Error> {
        if self.reader.flat {
            return Err(self.shape(format!("point {i} is a list but point 1 is a number")));
        }
        let mut count = 0;
        while seq
            .next_element_seed(Seed {
                reader: &mut *self.reader,
                place: Place::Coordinate(i, count + 1),
            })?
            .is_some()
        {
            count += 1;
        }
        let file = self.reader.file;
        let s = self.reader.s;
        if i == 1 && count == 0 {
            return Err(self.refuse(format_error(file, "point 1 has no coordinates")));
        }
        if i == 1 {
            self.reader.s = count;
        } else if count != s {
            let message = format!(
                "point {i} has {}, point 1 has {s} (every point needs the same number)",
                coordinates(count)
            );
            return Err(self.refuse(format_error(file, message)));
        }
        Ok(())
    }

    /// The top-level object: `"points"`, with `"n"` and `"s"` checked if present and any
    /// other key (`"meta"`, provenance) skipped.
    fn object<'de, A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let file = self.reader.file;
        let mut seen: Vec<&'static str> = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            let key = match key.as_str() {
                "points" => "points",
                "n" => "n",
                "s" => "s",
                _ => {
                    map.next_value::<serde::de::IgnoredAny>()?;
                    continue;
                }
            };
            // JSON leaves a repeated key's meaning open, and parsers differ on which one
            // wins: a second `"points"` is more likely a mistake than a choice.
            if seen.contains(&key) {
                let message = format!("duplicate key \"{key}\"; a point file has each key once");
                return Err(self.refuse(format_error(file, message)));
            }
            seen.push(key);
            if key == "points" {
                map.next_value_seed(Seed {
                    reader: &mut *self.reader,
                    place: Place::Points,
                })?;
            } else if let serde_json::Value::Number(v) = map.next_value()? {
                self.reader.hints.push((key, v));
            }
        }
        if !seen.contains(&"points") {
            return Err(self.shape("the object has no \"points\" key".to_string()));
        }
        Ok(())
    }
}

impl<'de> serde::de::Visitor<'de> for Seed<'_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(JSON_SHAPE)
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<(), E> {
        // `as` rounds to the nearest double, ties to even.
        self.number(v as f64, &v)
    }

    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<(), E> {
        self.number(v as f64, &v)
    }

    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<(), E> {
        self.number(v, &v)
    }

    fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<(), E> {
        let text = if v { "true" } else { "false" };
        self.other(text, text)
    }

    fn visit_unit<E: serde::de::Error>(self) -> Result<(), E> {
        self.other("null", "null")
    }

    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<(), E> {
        let raw = serde_json::to_string(v).unwrap_or_default();
        self.other("a string", &raw)
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<(), A::Error> {
        match self.place {
            Place::Root | Place::Points => self.list(seq),
            Place::Point(i) => self.row(i, seq),
            Place::Coordinate(..) => self.other("a list", "[...]"),
        }
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<(), A::Error> {
        match self.place {
            Place::Root => self.object(map),
            _ => self.other("an object", "{...}"),
        }
    }
}

fn parse_json(text: &str, file: &str) -> Result<PointSet, IoError> {
    if json_depth_exceeds(text, MAX_JSON_DEPTH) {
        return Err(format_error(
            file,
            format!("JSON nested more than {MAX_JSON_DEPTH} levels deep; {JSON_SHAPE}"),
        ));
    }
    let mut reader = JsonReader {
        file,
        data: Vec::new(),
        n: 0,
        s: 0,
        flat: false,
        hints: Vec::new(),
        refusal: None,
        at: None,
    };
    let mut de = serde_json::Deserializer::from_str(text);
    let root = Seed {
        reader: &mut reader,
        place: Place::Root,
    };
    if let Err(e) = serde::de::DeserializeSeed::deserialize(root, &mut de).and_then(|()| de.end()) {
        return Err(reader.explain(e, text));
    }
    let JsonReader {
        n, s, data, hints, ..
    } = reader;
    if n == 0 {
        return Err(IoError::Empty {
            file: file.to_string(),
        });
    }
    for (key, written) in hints {
        let (actual, what) = if key == "n" {
            (n, "points")
        } else {
            (s, "coordinates per point")
        };
        if written.as_f64() != Some(actual as f64) {
            return Err(format_error(
                file,
                format!("\"{key}\" is {written} but \"points\" holds {actual} {what}"),
            ));
        }
    }
    PointSet::new(n, s, data).map_err(|error| IoError::Points {
        file: file.to_string(),
        error,
    })
}

fn parse_npy(bytes: &[u8], file: &str) -> Result<PointSet, IoError> {
    const EXPECTED: &str = "expected a 2-D array of float64 or float32";
    check_npy_header(bytes, file)?;
    let mut rest = bytes;
    let header = npyz::NpyHeader::from_reader(&mut rest)
        .map_err(|e| format_error(file, format!("not a valid .npy file ({e})")))?;
    let shape = header.shape().to_vec();
    let (n, s) = match shape[..] {
        [n] => (n, 1),
        [n, s] => (n, s),
        _ => {
            return Err(format_error(
                file,
                format!("{EXPECTED} (got shape {shape:?})"),
            ))
        }
    };
    if n == 0 {
        return Err(IoError::Empty {
            file: file.to_string(),
        });
    }
    if s == 0 {
        return Err(format_error(
            file,
            format!("{EXPECTED} (got shape {shape:?})"),
        ));
    }
    let dtype = header.dtype();
    let width = match &dtype {
        npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Float => match t.size_field() {
            8 => 8u64,
            4 => 4u64,
            _ => 0,
        },
        _ => 0,
    };
    if width == 0 {
        return Err(format_error(
            file,
            format!("{EXPECTED} (got dtype {})", dtype.descr()),
        ));
    }
    // Checked before decoding so that a corrupt header cannot ask for a huge allocation.
    let needed = n.checked_mul(s).and_then(|len| len.checked_mul(width));
    if needed.is_none_or(|b| b > rest.len() as u64) {
        return Err(format_error(
            file,
            format!(
                "truncated: shape {shape:?} needs {} bytes of data, the file has {}",
                needed.map_or_else(|| "more than 2^64".to_string(), |b| b.to_string()),
                rest.len()
            ),
        ));
    }
    let (n, s) = (n as usize, s as usize);
    let fortran = header.order() == npyz::Order::Fortran;
    let npy = npyz::NpyFile::with_header(header, rest);
    let decoded = if width == 8 {
        npy.into_vec::<f64>()
    } else {
        npy.into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect())
    };
    let flat = decoded.map_err(|e| format_error(file, format!("corrupt .npy data ({e})")))?;
    let data = if fortran && s > 1 {
        // Column-major on disk: element (i, k) sits at k·n + i.
        let mut data = vec![0.0; n * s];
        for (k, column) in flat.chunks_exact(n).enumerate() {
            for (i, &v) in column.iter().enumerate() {
                data[i * s + k] = v;
            }
        }
        data
    } else {
        flat
    };
    PointSet::new(n, s, data).map_err(|error| IoError::Points {
        file: file.to_string(),
        error,
    })
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

/// Appends `v` so that parsing the text gives back the same bits: Rust's shortest
/// round-trip digits, positional for ordinary magnitudes and with an exponent for tiny or
/// huge ones (where positional form would run to hundreds of digits).
fn push_coord(out: &mut String, v: f64) {
    let a = v.abs();
    if a == 0.0 || (1e-5..1e16).contains(&a) {
        let _ = write!(out, "{v}");
    } else {
        let _ = write!(out, "{v:e}");
    }
}

/// One `# key: value` line per entry of a JSON object; any other non-null value becomes a
/// single `# meta: value` line.
fn push_meta_comments(out: &mut String, meta: &serde_json::Value) {
    let mut line = |key: &str, value: &serde_json::Value| {
        // A newline in a key would end the comment and corrupt the data that follows.
        let key: String = key
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let _ = writeln!(out, "# {key}: {value}");
    };
    match meta {
        serde_json::Value::Null => {}
        serde_json::Value::Object(map) => map.iter().for_each(|(k, v)| line(k, v)),
        other => line("meta", other),
    }
}

fn to_text(points: &PointSet, meta: &serde_json::Value, sep: char) -> String {
    let mut out = String::with_capacity(64 + points.coordinate_count() * 21);
    let _ = writeln!(out, "# stillpoint {}", env!("CARGO_PKG_VERSION"));
    push_meta_comments(&mut out, meta);
    for k in 1..=points.s() {
        if k > 1 {
            out.push(sep);
        }
        let _ = write!(out, "x{k}");
    }
    out.push('\n');
    for row in points.rows() {
        for (k, &v) in row.iter().enumerate() {
            if k > 0 {
                out.push(sep);
            }
            push_coord(&mut out, v);
        }
        out.push('\n');
    }
    out
}

fn to_json(points: &PointSet, meta: &serde_json::Value) -> String {
    let mut out = String::with_capacity(128 + points.coordinate_count() * 21);
    let _ = write!(
        out,
        "{{\n  \"stillpoint\": \"{}\",\n  \"n\": {},\n  \"s\": {},\n",
        env!("CARGO_PKG_VERSION"),
        points.n(),
        points.s()
    );
    if !meta.is_null() {
        let _ = writeln!(out, "  \"meta\": {meta},");
    }
    out.push_str("  \"points\": [\n");
    for (i, row) in points.rows().enumerate() {
        out.push_str("    [");
        for (k, &v) in row.iter().enumerate() {
            if k > 0 {
                out.push_str(", ");
            }
            // Debug adds ".0" to whole numbers, so JSON readers see floats throughout,
            // and switches to an exponent at the same magnitudes as `push_coord`.
            let _ = write!(out, "{v:?}");
        }
        out.push_str(if i + 1 < points.n() { "],\n" } else { "]\n" });
    }
    out.push_str("  ]\n}\n");
    out
}

fn to_npy(points: &PointSet) -> Vec<u8> {
    // Format version 1.0: magic, version, u16 header length, a Python dict literal padded
    // with spaces and ended by a newline so that the data starts 64-byte aligned.
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}",
        points.n(),
        points.s()
    );
    let unpadded = NPY_MAGIC.len() + 2 + 2 + header.len() + 1;
    header.extend(std::iter::repeat_n(
        ' ',
        unpadded.next_multiple_of(64) - unpadded,
    ));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + 8 * points.coordinate_count());
    out.extend_from_slice(NPY_MAGIC);
    out.extend_from_slice(&[1, 0]);
    // A dict for two dimensions is far below the 65 535-byte limit of version 1.0.
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for &v in points.as_slice() {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// The bytes of `points` in `format`, exactly as [`write_points`] stores them. `meta` (a
/// JSON object; `null` for none) goes into the comment lines of CSV/TSV and under the
/// `"meta"` key of JSON, and is dropped for `.npy`.
pub fn encode(points: &PointSet, meta: &serde_json::Value, format: Format) -> Vec<u8> {
    match format {
        Format::Csv => to_text(points, meta, ',').into_bytes(),
        Format::Tsv => to_text(points, meta, '\t').into_bytes(),
        Format::Json => to_json(points, meta).into_bytes(),
        Format::Npy => to_npy(points),
    }
}

/// The CSV form of `points` (as [`write_points`] writes a `.csv`), e.g. for stdout:
/// `# stillpoint <version>`, one `# key: value` line per entry of `meta`, the header
/// `x1,...,xs`, then one row per point.
pub fn to_csv_string(points: &PointSet, meta: &serde_json::Value) -> String {
    to_text(points, meta, ',')
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
    write_atomic(path, &encode(points, meta, Format::from_path(path)))
}

static TEMP_COUNTER: AtomicUsize = AtomicUsize::new(0);

/// The temporary files of the writes under way, so that an interrupted run can remove
/// them ([`abandon_writes`]).
static IN_FLIGHT: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

fn in_flight() -> std::sync::MutexGuard<'static, Vec<std::path::PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporary files of the writes under way and keeps any other write from
/// starting: for a handler of SIGINT or SIGTERM that then exits, so that an interrupted
/// run leaves every output either as it was or complete, and no temporary behind.
pub fn abandon_writes() {
    let mut writes = in_flight();
    for tmp in writes.drain(..) {
        let _ = fs::remove_file(tmp);
    }
    // The lock stays taken until the process exits: no new temporary can appear.
    std::mem::forget(writes);
}

thread_local! {
    /// The writes of the current staging: (temporary, final path), renamed on commit.
    static STAGED: std::cell::RefCell<Option<Vec<(std::path::PathBuf, std::path::PathBuf)>>> =
        const { std::cell::RefCell::new(None) };
}

/// A group of outputs that appear together or not at all. While a `Staging` is alive on
/// this thread, [`write_atomic`] leaves each complete, synced file under its temporary
/// name; [`Staging::commit`] renames them all into place. If any write fails, or the
/// staging is dropped without a commit (an error returned early), every temporary is
/// removed and no output of the group appears. FIFOs and devices are written at once.
#[derive(Debug)]
pub struct Staging {
    _private: (),
}

impl Staging {
    /// Starts staging the writes of this thread.
    pub fn begin() -> Staging {
        STAGED.with(|st| *st.borrow_mut() = Some(Vec::new()));
        Staging { _private: () }
    }

    /// Renames every staged file into place.
    pub fn commit(self) -> Result<(), IoError> {
        let staged = STAGED.with(|st| st.borrow_mut().take()).unwrap_or_default();
        let mut result = Ok(());
        for (tmp, path) in &staged {
            if result.is_ok() {
                result = fs::rename(tmp, path).map_err(|e| {
                    io_error(path, format!("cannot rename {} onto it", tmp.display()), e)
                });
            }
            if result.is_err() {
                let _ = fs::remove_file(tmp);
            }
            in_flight().retain(|t| t != tmp);
        }
        result
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if let Some(staged) = STAGED.with(|st| st.borrow_mut().take()) {
            for (tmp, _) in staged {
                let _ = fs::remove_file(&tmp);
                in_flight().retain(|t| *t != tmp);
            }
        }
    }
}

/// The longest file name an output may have: its temporary name `.{name}.tmp-{pid}-{k}`
/// must still fit the usual 255-byte limit of a directory entry.
pub const MAX_OUTPUT_NAME: usize = 255 - 32;

/// Checks, before any work is done, that `path` can take an output: its directory
/// exists, its name is not too long, and what is there (links followed) is a regular
/// file, a FIFO or a character device, or nothing yet. `what` names the option.
pub fn check_output(path: &Path) -> Result<(), IoError> {
    let refuse = |why: &str| io_error(path, "cannot write", std::io::Error::other(why.to_string()));
    let name = path
        .file_name()
        .ok_or_else(|| refuse("it names a directory; expected a file name"))?;
    if name.len() > MAX_OUTPUT_NAME {
        return Err(refuse(&format!(
            "a file name of {} bytes; at most {MAX_OUTPUT_NAME} are accepted",
            name.len()
        )));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(refuse(&format!(
            "the directory {} does not exist",
            dir.display()
        )));
    }
    // A directory may exist and refuse new files (read-only, full quota): try one.
    let probe = dir.join(format!(".stillpoint-probe-{}", std::process::id()));
    match fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = fs::remove_file(&probe);
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => {
            return Err(refuse(&format!(
                "no file can be created in {} ({e})",
                dir.display()
            )))
        }
    }
    #[cfg(unix)]
    if let Ok(meta) = fs::metadata(path) {
        use std::os::unix::fs::FileTypeExt;
        let kind = meta.file_type();
        if !(kind.is_file() || kind.is_fifo() || kind.is_char_device()) {
            return Err(refuse(
                "it is a directory, socket or block device; expected a file name",
            ));
        }
    }
    Ok(())
}

/// Removes `.{name}.tmp-{pid}-{k}` files in `dir` whose process no longer runs: what a
/// killed write of this output left behind. Best effort: a file that cannot be removed
/// is left.
fn remove_stale_temporaries(dir: &Path, name: &std::ffi::OsStr) {
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let file_name = file_name.to_string_lossy();
        let Some(rest) = file_name.strip_prefix(&prefix) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let alive = pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists();
        if !alive && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Replaces `path` with `bytes` so that readers see either the old file or the complete
/// new one: the bytes go to `.{name}.tmp-{pid}-{k}` in the same directory, are synced to
/// disk and renamed over `path`. On any failure the temporary file is removed and `path`
/// is left as it was. An existing file's permissions are kept.
///
/// What is at `path` decides how: a symbolic link is written through (its final target is
/// replaced atomically, the link stays); a FIFO or a character device (`/dev/stdout`) is
/// streamed to directly, since it cannot be replaced; a directory, socket or block device
/// is refused. Temporaries that an earlier run of a killed process left for this output
/// are removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let name = path.file_name().ok_or_else(|| {
        io_error(
            path,
            "cannot write",
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        // What the path leads to (links followed) decides whether it can be replaced.
        if let Ok(meta) = fs::metadata(path) {
            let kind = meta.file_type();
            if kind.is_fifo() || kind.is_char_device() {
                let mut f = fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| io_error(path, "cannot open", e))?;
                return f
                    .write_all(bytes)
                    .and_then(|()| f.flush())
                    .map_err(|e| io_error(path, "cannot write", e));
            }
            if !kind.is_file() {
                return Err(io_error(
                    path,
                    "cannot write",
                    std::io::Error::other(
                        "it is a directory, socket or block device; expected a file name",
                    ),
                ));
            }
        }
        if fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
            // Replace the file the link leads to, next to it, and keep the link; a
            // dangling link is followed by hand to where the file will be.
            let target = match fs::canonicalize(path) {
                Ok(t) => t,
                Err(_) => {
                    let link = fs::read_link(path)
                        .map_err(|e| io_error(path, "cannot read the link", e))?;
                    path.parent().unwrap_or(Path::new(".")).join(link)
                }
            };
            if fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
                return Err(io_error(
                    path,
                    "cannot write",
                    std::io::Error::other("a chain of links that does not end in a file"),
                ));
            }
            return write_atomic(&target, bytes);
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };

    remove_stale_temporaries(dir, name);
    // Registered while the lock is held, so that an interrupt sees every temporary.
    let mut writes = in_flight();
    let (tmp, mut file) = loop {
        let k = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".tmp-{}-{k}", std::process::id()));
        let tmp = dir.join(tmp_name);
        // create_new: never truncate or follow something that is already there.
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => {
                writes.push(tmp.clone());
                break (tmp, file);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && k < 1 << 20 => continue,
            Err(e) => {
                return Err(io_error(
                    path,
                    format!("cannot create temporary file {}", tmp.display()),
                    e,
                ))
            }
        }
    };

    drop(writes);
    let written = (|| {
        file.write_all(bytes)
            .map_err(|e| io_error(path, format!("cannot write {}", tmp.display()), e))?;
        file.flush()
            .and_then(|()| file.sync_all())
            .map_err(|e| io_error(path, format!("cannot sync {}", tmp.display()), e))?;
        if let Ok(old) = fs::metadata(path) {
            if old.is_file() {
                let _ = file.set_permissions(old.permissions());
            }
        }
        drop(file);
        // Under a staging, the rename waits for its commit.
        let staged = STAGED.with(|st| match st.borrow_mut().as_mut() {
            Some(list) => {
                list.push((tmp.clone(), path.to_path_buf()));
                true
            }
            None => false,
        });
        if staged {
            return Ok(true);
        }
        fs::rename(&tmp, path)
            .map_err(|e| io_error(path, format!("cannot rename {} onto it", tmp.display()), e))
            .map(|()| false)
    })();

    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    if written.as_ref().is_ok_and(|staged| *staged) {
        return Ok(());
    }
    in_flight().retain(|t| *t != tmp);
    written?;
    // The rename is durable only once the directory entry is; best effort, since some
    // platforms and file systems cannot sync a directory.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
