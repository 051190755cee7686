//! Delimited text: points read from CSV, TSV, semicolon- or whitespace-separated files,
//! and written as CSV or TSV.
//!
//! Records are split by the csv crate, so quoting, CRLF line ends and a byte-order mark
//! are read as RFC 4180 and pandas write them; the design table reads its cells through
//! the same [`records`]. What makes a point file out of the records (the delimiter, a
//! header of names, pandas' index column, decimal commas) is decided here.

use std::fmt::Write as _;

use super::{header, IoError};
use crate::{Error, PointSet};

/// The records of delimited text, each with the 1-based line it starts on: blank lines
/// and lines whose first non-blank character is `#` are skipped, a leading byte-order
/// mark is dropped, and fields keep their padding (see [`unquote`]).
pub struct Records<'a> {
    text: &'a str,
    reader: csv::Reader<&'a [u8]>,
}

/// The records of `text` split at `delimiter` (see [`Records`]).
pub fn records(text: &str, delimiter: u8) -> Records<'_> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let reader = csv::ReaderBuilder::new()
        .delimiter(delimiter)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    Records { text, reader }
}

impl Iterator for Records<'_> {
    /// A record and its line, or the line and why the text cannot be split.
    type Item = Result<(usize, csv::StringRecord), (usize, String)>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let mut record = csv::StringRecord::new();
            match self.reader.read_record(&mut record) {
                Ok(false) => return None,
                Ok(true) => {}
                Err(e) => {
                    let line = e.position().map_or(0, |p| p.line() as usize);
                    return Some(Err((line, e.to_string())));
                }
            }
            let (line, byte) = record.position().map_or((1, 0), |p| {
                start_of(self.text.as_bytes(), p.byte() as usize, p.line() as usize)
            });
            // The csv crate skips a `#` in the first column only; a comment may also be
            // indented, and a line of spaces is blank.
            let first = self.text.get(byte..).and_then(|t| t.lines().next());
            let first = first.unwrap_or("").trim();
            if first.is_empty() || first.starts_with('#') {
                if record.iter().any(|f| f.contains(['\n', '\r'])) {
                    let why = "an indented comment line opens a quoted field that runs on \
                               to later lines; start comment lines with '#' in the first column";
                    return Some(Err((line, why.to_string())));
                }
                continue;
            }
            return Some(Ok((line, record)));
        }
    }
}

/// The line and byte where a record starts, from where the csv crate began to look for
/// it (`byte` on `line`): past the line ends and the comment lines it skipped first.
fn start_of(text: &[u8], mut byte: usize, mut line: usize) -> (usize, usize) {
    while let Some(&b) = text.get(byte) {
        match b {
            b'\n' => line += 1,
            b'\r' => {}
            b'#' => {
                let rest = &text[byte..];
                byte += rest
                    .iter()
                    .position(|&b| matches!(b, b'\r' | b'\n'))
                    .unwrap_or(rest.len());
                continue;
            }
            _ => break,
        }
        byte += 1;
    }
    (line, byte)
}

/// A field without its padding, and without the double quotes around it if it still has
/// them (quotes after leading spaces, which RFC 4180 leaves as text).
pub fn unquote(field: &str) -> &str {
    let field = field.trim();
    field
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .map(str::trim)
        .unwrap_or(field)
}

/// Parses delimited text into a point set; `source` names the input in error messages.
///
/// Blank lines and lines starting with `#` are skipped. The first remaining line fixes the
/// delimiter: `;` if it has one, else `,`, else tab, else runs of whitespace. If every
/// field of that line is non-numeric it is a header and skipped; if only its first field
/// is empty it is a pandas header with an index column, and the first column of every row
/// is dropped. Fields may be padded with spaces or quoted as RFC 4180 quotes them, lines
/// may end in CRLF, one trailing delimiter is allowed, and with `;` a decimal comma
/// (`0,5`) is accepted. Every row must have the same number of coordinates and each must
/// be a finite number.
pub fn parse_text(text: &str, source: &str) -> Result<PointSet, IoError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let empty = || IoError::Empty {
        file: source.to_string(),
    };
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .ok_or_else(empty)?;
    let d = Delim::detect(first);
    let mut header_seen = false;
    let mut skip_first_column = false;
    let mut s = 0usize;
    let mut first_line = 0usize;
    let mut n = 0usize;
    let mut data: Vec<f64> = Vec::new();

    for record in records(text, d.byte()) {
        let (line_no, record) = record
            .map_err(|(line, why)| super::format_error(source, format!("line {line}: {why}")))?;
        let fields = d.fields(&record);
        if !header_seen {
            header_seen = true;
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
        }

        let mut count = 0usize;
        for (f, field) in fields.iter().enumerate() {
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
            let width = record.as_slice().len() + record.len();
            data.reserve(s * (text.len() / width.max(1)));
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
        return Err(empty());
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

    /// The byte the csv crate splits at; runs of whitespace are split again afterwards.
    fn byte(self) -> u8 {
        match self {
            Delim::Char(c) => c as u8,
            Delim::Whitespace => b' ',
        }
    }

    /// The unpadded, unquoted fields of a record, without the empty field after a
    /// trailing delimiter.
    fn fields(self, record: &csv::StringRecord) -> Vec<&str> {
        match self {
            Delim::Char(_) => {
                let mut fields: Vec<&str> = record.iter().map(unquote).collect();
                if fields.len() > 1 && fields.last() == Some(&"") {
                    fields.pop();
                }
                fields
            }
            Delim::Whitespace => record
                .iter()
                .flat_map(str::split_ascii_whitespace)
                .map(unquote)
                .collect(),
        }
    }
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

/// `points` as text with `sep` between coordinates: the header lines
/// ([`header::push_header`]), `x1,...,xs`, then one row per point.
pub(super) fn to_text(points: &PointSet, meta: &serde_json::Value, sep: char) -> String {
    let mut out = Vec::new();
    write_text(&mut out, points, meta, sep).expect("writing to memory");
    String::from_utf8(out).expect("the text is UTF-8")
}

/// [`to_text`] written to `w` row by row, so that a large set's file never stands whole
/// in memory beside its points.
pub(super) fn write_text(
    w: &mut dyn std::io::Write,
    points: &PointSet,
    meta: &serde_json::Value,
    sep: char,
) -> std::io::Result<()> {
    let mut out = String::new();
    header::push_header(&mut out, meta);
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
        if out.len() >= 1 << 16 {
            w.write_all(out.as_bytes())?;
            out.clear();
        }
    }
    w.write_all(out.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of every coordinate, to compare two reads exactly.
    fn bits(p: &PointSet) -> (usize, usize, Vec<u64>) {
        (
            p.n(),
            p.s(),
            p.as_slice().iter().map(|v| v.to_bits()).collect(),
        )
    }

    const PLAIN: &str = "x1,x2\n0.25,0.5\n0.75,1e-7\n";

    #[test]
    fn a_file_written_as_pandas_writes_it_reads_as_the_plain_one() {
        let plain = bits(&parse_text(PLAIN, "plain").unwrap());
        assert_eq!(plain.0, 2);
        // pandas' to_csv with quoting=csv.QUOTE_ALL, lineterminator="\r\n" and
        // encoding="utf-8-sig"; then its default index column.
        let quoted = "\u{feff}\"x1\",\"x2\"\r\n\"0.25\",\"0.5\"\r\n\"0.75\",\"1e-7\"\r\n";
        let indexed = "\u{feff},x1,x2\r\n0,0.25,0.5\r\n1,0.75,1e-7\r\n";
        let numbered = ",0,1\n0,0.25,0.5\n1,0.75,1e-7\n";
        for text in [quoted, indexed, numbered] {
            assert_eq!(
                bits(&parse_text(text, "pandas").unwrap()),
                plain,
                "{text:?}"
            );
        }
        // A decimal comma inside quotes is one field, not two.
        let semicolons = "\"x1\";\"x2\"\r\n\"0,25\";\"0,5\"\r\n\"0,75\";\"1e-7\"\r\n";
        assert_eq!(bits(&parse_text(semicolons, "semi").unwrap()), plain);
    }

    #[test]
    fn every_layout_read_before_is_still_read() {
        let plain = bits(&parse_text(PLAIN, "plain").unwrap());
        for text in [
            "# stillpoint\n  # indented comment, \"quoted\"\n\n0.25,0.5\n   \n0.75,1e-7\n",
            "x1\tx2\n0.25\t0.5\t\n\t\n0.75\t1e-7\n",
            "0.25 0.5\n 0.75\t \t1e-7  \n",
            "x1 , x2 \n 0.25 , \"0.5\" ,\n0.75,1e-7,\n",
            "0.25;0.5\n0,75;1e-7\n",
        ] {
            assert_eq!(bits(&parse_text(text, "t").unwrap()), plain, "{text:?}");
        }
    }

    #[test]
    fn refusals_name_the_file_line_and_field() {
        let e = parse_text("x1,x2\n# note\n0.1,0.2\n0.3,abc\n", "f.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "f.csv: line 4, field 2: \"abc\" is not a number"
        );
        let e = parse_text("0.1,0.2\r\n\r\n0.3\r\n", "f.csv").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("f.csv: line 3 has 1 coordinate, line 1 has 2"));
        // A record whose quoted field spans lines is counted from the line it starts on.
        let e = parse_text("0.1,0.2\n\"0.3\n\",x\n", "f.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "f.csv: line 2, field 2: \"x\" is not a number"
        );
    }

    #[test]
    fn an_indented_comment_never_swallows_the_lines_after_it() {
        let e = parse_text("0.1 0.2\n  # \"open\n0.3 0.4\n", "w.txt").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("w.txt: line 2: an indented comment"),
            "{e}"
        );
    }

    #[test]
    fn a_huge_line_or_a_binary_file_is_refused_promptly() {
        let dir = std::env::temp_dir().join(format!("stillpoint-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let start = std::time::Instant::now();
        // 16 MiB on one line: one number too large to be finite, then no line end.
        let long = dir.join("long.csv");
        std::fs::write(&long, vec![b'7'; 16 << 20]).unwrap();
        let e = super::super::read_points(&long).unwrap_err().to_string();
        assert!(e.contains("expected a finite number"), "{e}");
        let names = dir.join("names.csv");
        std::fs::write(&names, vec![b'a'; 16 << 20]).unwrap();
        let e = super::super::read_points(&names).unwrap_err().to_string();
        assert!(e.ends_with("no points found"), "{e}");
        let binary = dir.join("binary.csv");
        std::fs::write(
            &binary,
            (0..=255u8).cycle().take(1 << 20).collect::<Vec<_>>(),
        )
        .unwrap();
        let e = super::super::read_points(&binary).unwrap_err().to_string();
        assert!(e.contains("not UTF-8 text"), "{e}");
        // Linear work: a few hundred MB/s at least, even unoptimised; a hang takes minutes.
        assert!(start.elapsed().as_secs() < 60, "{:?}", start.elapsed());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
