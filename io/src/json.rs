//! JSON point files: read in one pass of serde_json straight into the coordinates, with
//! every refusal naming the point and coordinate; written with the provenance under its
//! own `"meta"` key.

use std::fmt::Write as _;

use super::{coordinates, format_error, IoError};
use crate::{Error, PointSet};

/// The deepest nesting of arrays and objects a JSON point file may have (a point file
/// needs 2 or 3 levels, its provenance a few more).
pub const MAX_JSON_DEPTH: usize = 64;

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

pub(super) fn parse_json(text: &str, file: &str) -> Result<PointSet, IoError> {
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

pub(super) fn to_json(points: &PointSet, meta: &serde_json::Value) -> String {
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
