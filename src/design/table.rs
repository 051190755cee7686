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
    /// and labels to their levels. `source` names the input in refusals.
    pub fn from_text(space: &DesignSpace, text: &str, source: &str) -> Result<Design, Error> {
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
        let names: Vec<&str> = header.split(sep).map(str::trim).collect();
        let mut at = Vec::with_capacity(space.dim());
        for v in &space.vars {
            match names.iter().position(|&h| h == v.name) {
                Some(k) => at.push(k),
                None => {
                    return Err(Error::invalid(
                        source,
                        format!("header {header:?}"),
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
        for (line, row) in lines {
            let cells: Vec<&str> = row.split(sep).map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(Error::invalid(
                    format!("{source} line {}", line + 1),
                    format!("{} cells", cells.len()),
                    format!("{} cells, as the header", names.len()),
                ));
            }
            for (j, v) in space.vars.iter().enumerate() {
                let cell = cells[at[j]];
                let bad = |expected: String| {
                    Error::invalid(
                        format!("{source} line {}, {}", line + 1, v.name),
                        cell,
                        expected,
                    )
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
                        let x: i64 = cell
                            .parse()
                            .ok()
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
