//! A design as a table of text, both ways: written with a header of names and labels
//! in their cells (numbers so that they read back to the same bits), and read back
//! into the unit scale for `eval --space`, every cell checked against its variable.
//! Cells are split by the csv crate, as point files are (`io::text`).

use super::{Design, DesignSpace, Kind};
use crate::{Error, PointSet};
use stillpoint_io::unquote;

impl Design {
    /// The design as text with `sep` between cells: `#` comment lines with `meta` (a JSON
    /// object), the header of names, then one row per point. A cell that holds the
    /// separator, a quote or a line break is quoted as RFC 4180 quotes it.
    pub fn to_text(&self, meta: &serde_json::Value, sep: char) -> String {
        let mut out = String::new();
        stillpoint_io::push_header(&mut out, meta);
        let mut table = csv::WriterBuilder::new()
            .delimiter(sep as u8)
            .terminator(csv::Terminator::Any(b'\n'))
            .from_writer(Vec::new());
        let columns = self.columns();
        let rows = (0..self.n()).map(|i| {
            columns
                .iter()
                .map(|c| match c {
                    super::Column::Real(v) => format!("{:?}", v[i]),
                    super::Column::Int(v) => v[i].to_string(),
                    super::Column::Label(v) => v[i].clone(),
                })
                .collect::<Vec<String>>()
        });
        let names = self.space.vars.iter().map(|v| v.name.clone()).collect();
        for row in std::iter::once(names).chain(rows) {
            // Writing to memory cannot fail.
            let _ = table.write_record(&row);
        }
        let bytes = table.into_inner().unwrap_or_default();
        out.push_str(&String::from_utf8_lossy(&bytes));
        out
    }

    /// Reads a design written as [`Design::to_text`] writes it (comma- or tab-separated,
    /// `#` lines skipped, the header naming every variable of `space` once, in any
    /// order): continuous values go back to the unit scale through their CDF, integers
    /// and labels to their levels. A leading byte-order mark is skipped, lines may end in
    /// CRLF and a cell may be quoted as RFC 4180 quotes it (`"0.5"`, `""` for a quote
    /// inside, a separator or a line break within the quotes), as spreadsheets and pandas
    /// write them. `source` names the input in refusals.
    pub fn from_text(space: &DesignSpace, text: &str, source: &str) -> Result<Design, Error> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let header = text
            .lines()
            .find(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty());
        let Some(header) = header else {
            return Err(Error::invalid(
                source,
                "no rows",
                "a header of names, then rows",
            ));
        };
        let sep = if header.contains('\t') { b'\t' } else { b',' };
        let mut rows = stillpoint_io::records(text, sep).map(|record| match record {
            Ok((line, cells)) => Ok((
                format!("{source} line {line}"),
                cells.iter().map(|c| unquote(c).to_string()).collect(),
            )),
            Err((line, why)) => Err(Error::invalid(
                format!("{source} line {line}"),
                "text that cannot be split into cells",
                why,
            )),
        });
        let names = match rows.next() {
            Some(header) => header?.1,
            None => Vec::new(),
        };
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
            Ok((
                format!("{source} row {}", i + 1),
                columns
                    .iter()
                    .map(|c| c.1[i].clone())
                    .collect::<Vec<String>>(),
            ))
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
        rows: impl Iterator<Item = Result<(String, Vec<String>), Error>>,
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
        for row in rows {
            let (place, cells) = row?;
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
                    // The path's value for now; the row's paths go back together below.
                    Kind::Path { path, .. } => cell
                        .parse()
                        .ok()
                        .filter(|x: &f64| x.is_finite())
                        .ok_or_else(|| bad(format!("a finite number ({})", path.text())))?,
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
                let cont = space.marginals();
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
        // Each path's values back to its coordinates, all rows at once (its map is made
        // once).
        for (first, path) in space.paths() {
            let w: Vec<f64> = unit
                .chunks_exact(s)
                .flat_map(|row| row[first..first + path.m].to_vec())
                .collect();
            for (row, u) in unit
                .chunks_exact_mut(s)
                .zip(path.unit(&w).chunks_exact(path.m))
            {
                row[first..first + path.m].copy_from_slice(u);
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A space of a continuous variable and one with labels, with `label` as level 1.
    fn space_with(label: &str) -> DesignSpace {
        let mut space = DesignSpace::parse("--var", &["x=uniform(0,1)", "c={a,b}"]).unwrap();
        if let Kind::Levels { labels, .. } = &mut space.vars[1].kind {
            labels[1] = label.to_string();
        }
        space
    }

    fn design(space: &DesignSpace) -> Design {
        Design {
            space: space.clone(),
            unit: PointSet::new(3, 2, vec![0.125, 0.25, 0.5, 0.75, 0.875, 0.25]).unwrap(),
            levels: vec![Vec::new(), vec![0, 1, 0]],
        }
    }

    #[test]
    fn a_label_with_a_comma_a_quote_and_a_line_break_round_trips() {
        let label = "dark, \"deep\"\nred";
        let space = space_with(label);
        let d = design(&space);
        for sep in [',', '\t'] {
            let text = d.to_text(&serde_json::json!({"note": "a, b"}), sep);
            // Quoted as RFC 4180 quotes it: the quote doubled, the cell in quotes.
            assert!(text.contains("\"dark, \"\"deep\"\"\nred\""), "{text}");
            let back = Design::from_text(&space, &text, "t").unwrap();
            assert_eq!(back.levels, d.levels);
            assert_eq!(
                back.to_text(&serde_json::Value::Null, sep),
                d.to_text(&serde_json::Value::Null, sep)
            );
        }
    }

    #[test]
    fn a_table_written_as_pandas_writes_it_reads_as_the_plain_one() {
        let space = space_with("b");
        let plain = "x,c\n0.125,a\n0.5,b\n0.875,a\n";
        let pandas =
            "\u{feff}\"x\",\"c\"\r\n\"0.125\",\"a\"\r\n\"0.5\",\"b\"\r\n\"0.875\",\"a\"\r\n";
        let a = Design::from_text(&space, plain, "plain").unwrap();
        let b = Design::from_text(&space, pandas, "pandas").unwrap();
        assert_eq!(a.levels, b.levels);
        assert_eq!(a.unit.as_slice(), b.unit.as_slice());
        assert_eq!(a.levels[1], vec![0, 1, 0]);
        // A refusal names the line the row starts on, comments and blank lines counted.
        let e = Design::from_text(&space, "# c\nx,c\n\n0.5,\"z\"\r\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("f.csv line 4, c"), "{e}");
    }
}
