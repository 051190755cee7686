//! A design as a table of text, both ways: written with a header of names and labels
//! in their cells (numbers so that they read back to the same bits), and read back
//! into the unit scale for `eval --space`, every cell checked against its variable.

use super::{Design, DesignSpace, Kind};
use crate::{Error, PointSet};

impl Design {
    /// The design as text with `sep` between cells: `#` comment lines with `meta` (a JSON
    /// object), the header of names, then one row per point.
    pub fn to_text(&self, meta: &serde_json::Value, sep: char) -> String {
        let mut out = format!("# stillpoint {}\n", env!("CARGO_PKG_VERSION"));
        if let Some(map) = meta.as_object() {
            for (k, v) in map {
                out.push_str(&format!("# {k}: {v}\n"));
            }
        }
        let sep = sep.to_string();
        let names: Vec<&str> = self.space.vars.iter().map(|v| v.name.as_str()).collect();
        out.push_str(&names.join(&sep));
        out.push('\n');
        let columns = self.columns();
        for i in 0..self.n() {
            let cells: Vec<String> = columns
                .iter()
                .map(|c| match c {
                    super::Column::Real(v) => format!("{:?}", v[i]),
                    super::Column::Int(v) => v[i].to_string(),
                    super::Column::Label(v) => v[i].clone(),
                })
                .collect();
            out.push_str(&cells.join(&sep));
            out.push('\n');
        }
        out
    }

    /// Reads a design written as [`Design::to_text`] writes it (comma- or tab-separated,
    /// `#` lines skipped, the header naming every variable of `space` once, in any
    /// order): continuous values go back to the unit scale through their CDF, integers
    /// and labels to their levels. A leading byte-order mark is skipped and a cell may be
    /// quoted as RFC 4180 quotes it (`"0.5"`, `""` for a quote inside), as spreadsheets
    /// write them. `source` names the input in refusals.
    pub fn from_text(space: &DesignSpace, text: &str, source: &str) -> Result<Design, Error> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim_start().starts_with('#') && !l.trim().is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(Error::invalid(
                source,
                "no rows",
                "a header of names, then rows",
            ));
        };
        let sep = if header.contains('\t') { '\t' } else { ',' };
        let names = cells(header, sep);
        let rows =
            lines.map(|(line, row)| (format!("{source} line {}", line + 1), cells(row, sep)));
        Design::from_rows(space, &names, rows, source, &format!("header {header:?}"))
    }

    /// Reads a design given as named columns of cells (each cell as a CSV cell reads,
    /// without quoting: a label, a whole number, a number), every column of the same
    /// length. `source` names the table in refusals.
    pub fn from_columns(
        space: &DesignSpace,
        columns: &[(String, Vec<String>)],
        source: &str,
    ) -> Result<Design, Error> {
        let n = columns.first().map_or(0, |c| c.1.len());
        if let Some((name, c)) = columns.iter().find(|c| c.1.len() != n) {
            return Err(Error::invalid(
                format!("{source} column {name}"),
                format!("{} values", c.len()),
                format!(
                    "as many values as column {}, {n} (one per point)",
                    columns[0].0
                ),
            ));
        }
        let names: Vec<String> = columns.iter().map(|c| c.0.clone()).collect();
        let rows = (0..n).map(|i| {
            (
                format!("{source} row {}", i + 1),
                columns
                    .iter()
                    .map(|c| c.1[i].clone())
                    .collect::<Vec<String>>(),
            )
        });
        Design::from_rows(space, &names, rows, source, &format!("columns {names:?}"))
    }

    /// Reads a design written as numbers (`.npy`, `.json`: one coordinate per variable in
    /// the space's order); a space with labels has no numeric form.
    pub fn from_numbers(
        space: &DesignSpace,
        points: &PointSet,
        source: &str,
    ) -> Result<Design, Error> {
        if space.has_labels() {
            return Err(Error::invalid(
                source,
                "a file of numbers",
                "a .csv or .tsv file for a space with levels (their labels are text)",
            ));
        }
        if points.s() != space.dim() {
            return Err(Error::invalid(
                source,
                format!("{} columns", points.s()),
                format!("exactly the space's {} variables", space.dim()),
            ));
        }
        let columns: Vec<(String, Vec<String>)> = space
            .vars
            .iter()
            .enumerate()
            .map(|(j, v)| {
                let cells = (0..points.n())
                    .map(|i| format!("{:?}", points.point(i)[j]))
                    .collect();
                (v.name.clone(), cells)
            })
            .collect();
        Design::from_columns(space, &columns, source)
    }

    /// The design as its values are written ([`Design::to_text`]) and read back: a
    /// report's figures are those of what the file holds, with every value rounded to a
    /// float (a continuous column whose range holds too few floats shows its ties).
    pub fn as_written(&self) -> Result<Design, Error> {
        Design::from_text(
            &self.space,
            &self.to_text(&serde_json::Value::Null, ','),
            "the design as written",
        )
    }

    fn from_rows(
        space: &DesignSpace,
        names: &[String],
        rows: impl Iterator<Item = (String, Vec<String>)>,
        source: &str,
        shown_header: &str,
    ) -> Result<Design, Error> {
        let mut at = Vec::with_capacity(space.dim());
        for v in &space.vars {
            match names.iter().position(|h| *h == v.name) {
                Some(k) => at.push(k),
                None => {
                    return Err(Error::invalid(
                        source,
                        shown_header,
                        format!("a column named {} (every variable of the space)", v.name),
                    ))
                }
            }
        }
        if names.len() != space.dim() {
            return Err(Error::invalid(
                source,
                format!("{} columns", names.len()),
                format!("exactly the space's {} variables", space.dim()),
            ));
        }
        let s = space.dim();
        let mut unit = Vec::new();
        let mut levels: Vec<Vec<usize>> = vec![Vec::new(); s];
        for (place, cells) in rows {
            if cells.len() != names.len() {
                return Err(Error::invalid(
                    place,
                    format!("{} cells", cells.len()),
                    format!("{} cells, as the header", names.len()),
                ));
            }
            for (j, v) in space.vars.iter().enumerate() {
                let cell = cells[at[j]].as_str();
                let bad = |expected: String| {
                    // A cell with a line break (a label from Python) is shown quoted,
                    // so that the refusal stays one line.
                    let shown = if cell.chars().any(char::is_control) {
                        format!("{cell:?}")
                    } else {
                        cell.to_string()
                    };
                    Error::invalid(format!("{place}, {}", v.name), shown, expected)
                };
                let u = match &v.kind {
                    Kind::Continuous(m) => {
                        let x: f64 = cell
                            .parse()
                            .ok()
                            .filter(|x: &f64| x.is_finite())
                            .ok_or_else(|| bad(format!("a finite number ({})", m.text())))?;
                        let (lo, hi) = m.support();
                        if x < lo || x > hi {
                            return Err(bad(format!("a value in the support of {}", m.text())));
                        }
                        m.cdf(x)
                    }
                    Kind::Integer { lo, hi } => {
                        let x = whole(cell)
                            .filter(|x| (lo..=hi).contains(&x))
                            .ok_or_else(|| bad(format!("a whole number in [{lo}, {hi}]")))?;
                        let level = (x - lo) as usize;
                        levels[j].push(level);
                        (level as f64 + 0.5) / (hi - lo + 1) as f64
                    }
                    Kind::Levels { labels, .. } => {
                        let level = labels
                            .iter()
                            .position(|l| l == cell)
                            .ok_or_else(|| bad(format!("one of {}", labels.join(", "))))?;
                        levels[j].push(level);
                        (level as f64 + 0.5) / labels.len() as f64
                    }
                };
                unit.push(u);
            }
            if let Some(c) = &space.copula {
                // The file holds correlated values: back to the independent scores.
                let row = unit.len() - s;
                let cont = space.continuous();
                let v: Vec<f64> = cont.iter().map(|&j| unit[row + j]).collect();
                for (k, u) in c.decorrelate(&v).into_iter().enumerate() {
                    unit[row + cont[k]] = u;
                }
            }
        }
        let n = unit.len() / s.max(1);
        if n == 0 {
            return Err(Error::invalid(source, "a header only", "at least one row"));
        }
        Ok(Design {
            space: space.clone(),
            unit: PointSet::new(n, s, unit)?,
            levels,
        })
    }
}

/// A whole number written as an integer (`3`) or as a float with no fraction (`3.0`, as
/// pandas writes an integer column with a gap).
fn whole(cell: &str) -> Option<i64> {
    cell.parse::<i64>().ok().or_else(|| {
        cell.parse::<f64>()
            .ok()
            .filter(|x| x.fract() == 0.0 && x.abs() < 9.0e15)
            .map(|x| x as i64)
    })
}

/// The cells of one line, trimmed, each unquoted as RFC 4180 quotes it (a cell in double
/// quotes may hold the separator, and `""` for a quote).
fn cells(line: &str, sep: char) -> Vec<String> {
    let mut out = Vec::new();
    let mut cell = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut was_quoted = false;
    while let Some(c) = chars.next() {
        if quoted {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    chars.next();
                    cell.push('"');
                } else {
                    quoted = false;
                }
            } else {
                cell.push(c);
            }
        } else if c == sep {
            out.push(finish(&cell, was_quoted));
            cell.clear();
            was_quoted = false;
        } else if c == '"' && cell.trim().is_empty() {
            cell.clear();
            quoted = true;
            was_quoted = true;
        } else {
            cell.push(c);
        }
    }
    out.push(finish(&cell, was_quoted));
    out
}

fn finish(cell: &str, quoted: bool) -> String {
    if quoted {
        // Spaces after the closing quote are padding; inside, they are the cell's.
        cell.trim_end().to_string()
    } else {
        cell.trim().to_string()
    }
}
