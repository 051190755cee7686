//! Design spaces as users have them: continuous variables with bounds or distributions,
//! integer ranges, ordered and unordered categorical levels. A design is made in the
//! unit cube, where the discrepancy is defined and optimised, then levels are dealt by
//! rank (so every level count is as even as n allows), categorical slices are balanced
//! and stratified ([`balance`]), and each continuous coordinate is mapped through its
//! marginal's quantile function ([`dist`]). A path variable ([`path`]) takes m
//! coordinates and maps them together. [`figures`] measures the result.

#![deny(missing_docs)]

use stillpoint_domains::{Error, PointSet};

pub mod balance;
pub mod copula;
pub mod dist;
pub mod exchange;
pub mod figures;
pub mod path;
pub mod slices;
pub mod table;

pub use dist::Marginal;
use stillpoint_parse::design::{self, TypeText, VariableText};

/// What one variable of a design space takes.
#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    /// A real number following a marginal distribution.
    Continuous(Marginal),
    /// A whole number in [lo, hi], both ends included.
    Integer {
        /// Lowest value.
        lo: i64,
        /// Highest value.
        hi: i64,
    },
    /// One of a list of labels; `ordered` levels are spread like a coordinate, unordered
    /// ones are balanced in pairs and slice the continuous part.
    Levels {
        /// The labels, in the order given.
        labels: Vec<String>,
        /// Whether the order of the labels means something (low < mid < high).
        ordered: bool,
    },
    /// One coordinate W(t_{step+1}) of a Brownian path: `NAME=brownian(T,m,…)` becomes m
    /// variables `NAME_1` … `NAME_m`, mapped together (see [`path`]).
    Path {
        /// The name as typed (`W` for the columns `W_1` … `W_m`).
        base: String,
        /// The path.
        path: path::Brownian,
        /// Which coordinate of the path, from 0.
        step: usize,
    },
}

impl Kind {
    /// The number of levels of a discrete variable; `None` for a continuous one.
    pub fn levels(&self) -> Option<usize> {
        match self {
            Kind::Continuous(_) | Kind::Path { .. } => None,
            Kind::Integer { lo, hi } => Some((hi - lo) as usize + 1),
            Kind::Levels { labels, .. } => Some(labels.len()),
        }
    }

    /// Whether the variable is continuous on the unit scale (a marginal's variable or a
    /// path's coordinate): stratified, sliced and polished there like any other.
    pub fn is_continuous(&self) -> bool {
        matches!(self, Kind::Continuous(_) | Kind::Path { .. })
    }

    /// Whether this is an unordered categorical factor (the ones that slice the design).
    pub fn is_categorical(&self) -> bool {
        matches!(self, Kind::Levels { ordered: false, .. })
    }

    /// The variable's type as a user writes it after `NAME=`.
    pub fn text(&self) -> String {
        match self {
            Kind::Continuous(m) => m.text(),
            Kind::Path { path, .. } => path.text(),
            Kind::Integer { lo, hi } => format!("int({lo},{hi})"),
            Kind::Levels { labels, ordered } => {
                format!(
                    "{}{{{}}}",
                    if *ordered { "ordered" } else { "" },
                    labels.join(",")
                )
            }
        }
    }
}

/// One named variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// Its name: the CSV header and Python column.
    pub name: String,
    /// What it takes.
    pub kind: Kind,
}

/// The variables of a design, in the order given: one column each.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSpace {
    /// The variables.
    pub vars: Vec<Variable>,
    /// The continuous variables' correlation, if any (a Gaussian copula).
    pub copula: Option<copula::Copula>,
}

impl DesignSpace {
    /// Parses variables written `NAME=TYPE`: `uniform(lo,hi)`, `normal(mu,sigma)`,
    /// `truncnormal(mu,sigma,lo,hi)`, `lognormal(mu,sigma)`, `beta(a,b[,lo,hi])`,
    /// `triangular(lo,mode,hi)`, `int(lo,hi)`, `{a,b,c}`, `ordered{low,mid,high}` or
    /// `brownian(T,m[,construction])` (m variables `NAME_1` … `NAME_m`).
    /// `option` names the option in refusals (`--var`, `space`).
    pub fn parse<S: AsRef<str>>(option: &str, items: &[S]) -> Result<DesignSpace, Error> {
        if items.is_empty() {
            return Err(Error::invalid(
                option,
                "[]",
                "at least one variable NAME=TYPE",
            ));
        }
        let mut vars: Vec<Variable> = Vec::with_capacity(items.len());
        for item in items {
            for v in parse_variable(option, item.as_ref())? {
                if vars.iter().any(|w| w.name == v.name) {
                    return Err(Error::invalid(
                        option,
                        item.as_ref(),
                        format!("a new name: {} is already a variable", v.name),
                    ));
                }
                vars.push(v);
            }
        }
        Ok(DesignSpace { vars, copula: None })
    }

    /// Correlates the continuous variables (in their order) by a Gaussian copula with
    /// this k × k correlation matrix, row-major; `option` and `shown` name it in refusals.
    /// A path's coordinates are not among them: they are the path's own normal scores,
    /// independent of the rest, and a matrix that counts them is refused naming the path.
    pub fn correlate(&mut self, option: &str, shown: &str, matrix: Vec<f64>) -> Result<(), Error> {
        let k = self.marginals().len();
        let paths: Vec<String> = self.texts_of(|kind| matches!(kind, Kind::Path { .. }));
        if !paths.is_empty() && (k < 2 || matrix.len() != k * k) {
            let names = self
                .marginals()
                .iter()
                .map(|&j| self.vars[j].name.as_str())
                .collect::<Vec<_>>()
                .join(", ");
            let want = if k < 2 {
                format!("two or more continuous variables besides the paths (this space has {k}: {names})")
            } else {
                format!(
                    "a {k} × {k} matrix over the continuous variables other than paths ({names})"
                )
            };
            return Err(Error::invalid(
                option,
                shown,
                format!(
                    "{want}: a path ({}) is a Brownian motion of its own, independent of the \
                     other variables, and takes no correlation",
                    paths.join(", ")
                ),
            ));
        }
        if k < 2 {
            return Err(Error::invalid(
                option,
                shown,
                format!("a space with two or more continuous variables to correlate (it has {k})"),
            ));
        }
        self.copula = Some(copula::Copula::new(option, shown, k, matrix)?);
        Ok(())
    }

    /// [`DesignSpace::correlate`] with the matrix written as rows, `1,0.5;0.5,1` (as the
    /// command line and the request's text take it).
    pub fn correlate_rows(&mut self, option: &str, text: &str) -> Result<(), Error> {
        let matrix = text
            .split([';', ','])
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|_| Error::invalid(option, text, "rows of numbers: 1,0.5;0.5,1"))?;
        self.correlate(option, text, matrix)
    }

    /// The correlation as `--correlation` takes it (`1,0.7;0.7,1`, each number in the
    /// form that reads back to the same bits), or `None` without one: a file's header
    /// records it so that its figures can be reproduced from the file alone.
    pub fn correlation_text(&self) -> Option<String> {
        let c = self.copula.as_ref()?;
        let k = c.k();
        Some(
            c.matrix
                .chunks(k)
                .map(|row| {
                    row.iter()
                        .map(|v| format!("{v:?}"))
                        .collect::<Vec<_>>()
                        .join(",")
                })
                .collect::<Vec<_>>()
                .join(";"),
        )
    }

    /// The indices of the variables continuous on the unit scale (marginals' variables
    /// and paths' coordinates).
    pub fn continuous(&self) -> Vec<usize> {
        (0..self.dim())
            .filter(|&j| self.vars[j].kind.is_continuous())
            .collect()
    }

    /// The indices of the variables with a marginal distribution (those a copula
    /// correlates).
    pub fn marginals(&self) -> Vec<usize> {
        (0..self.dim())
            .filter(|&j| matches!(self.vars[j].kind, Kind::Continuous(_)))
            .collect()
    }

    /// The paths of the space: each one's first column and its path.
    pub fn paths(&self) -> Vec<(usize, path::Brownian)> {
        self.vars
            .iter()
            .enumerate()
            .filter_map(|(j, v)| match &v.kind {
                Kind::Path { path, step: 0, .. } => Some((j, *path)),
                _ => None,
            })
            .collect()
    }

    /// The number of variables (the dimension of the unit-cube design).
    pub fn dim(&self) -> usize {
        self.vars.len()
    }

    /// Per coordinate, whether its law is unbounded (normal, lognormal, …): where the
    /// quantile function, and with it the integrand seen on the cube, blows up at a face.
    pub fn unbounded(&self) -> Vec<bool> {
        self.vars
            .iter()
            .map(|v| match &v.kind {
                Kind::Continuous(m) => !m.bounded(),
                Kind::Path { .. } => true,
                _ => false,
            })
            .collect()
    }

    /// The variables as `NAME=TYPE`, as they parse back (a path once, as
    /// `W=brownian(1,64,pca)`).
    pub fn texts(&self) -> Vec<String> {
        self.texts_of(|_| true)
    }

    /// [`DesignSpace::texts`] of the variables whose kind passes `keep`.
    fn texts_of(&self, keep: impl Fn(&Kind) -> bool) -> Vec<String> {
        self.vars
            .iter()
            .filter(|v| keep(&v.kind))
            .filter_map(|v| match &v.kind {
                Kind::Path { step: 0, base, .. } => Some(format!("{base}={}", v.kind.text())),
                Kind::Path { .. } => None,
                kind => Some(format!("{}={}", v.name, kind.text())),
            })
            .collect()
    }

    /// Whether any variable writes labels rather than numbers.
    pub fn has_labels(&self) -> bool {
        self.vars
            .iter()
            .any(|v| matches!(v.kind, Kind::Levels { .. }))
    }

    /// Refuses an `n` too small for every label to appear at least once: a design that
    /// never shows a level cannot say anything about it.
    /// Refuses as well a continuous variable whose range cannot hold n distinct values in
    /// floating point (`uniform(1e15,1e15+0.1)` at n = 20): its written column would
    /// collapse into ties that no figure on the unit scale could show.
    pub fn check_n(&self, option: &str, n: usize) -> Result<(), Error> {
        // The n cell centres, where a stratified column's values sit.
        let centre = |k: usize| (k as f64 + 0.5) / n as f64;
        // Every normal and lognormal variable maps the same normal scores at the centres:
        // Φ⁻¹ once per call, not once per variable (an integration checks 4 096 centres
        // each time it is asked, and Φ⁻¹ is most of the check's cost).
        let mut scores: Option<Vec<f64>> = None;
        for v in &self.vars {
            if let Kind::Continuous(m) = &v.kind {
                let z = m.from_normal_score(0.0).map(|_| {
                    scores.get_or_insert_with(|| {
                        (0..n).map(|k| Marginal::normal_score(centre(k))).collect()
                    })
                });
                let mut distinct = 0usize;
                let mut last = f64::NAN;
                for k in 0..n {
                    let x = match &z {
                        Some(z) => m.from_normal_score(z[k]).unwrap_or(f64::NAN),
                        None => m.ppf(centre(k)),
                    };
                    if x != last && x.is_finite() {
                        distinct += 1;
                    }
                    last = x;
                }
                if distinct < n {
                    return Err(Error::invalid(
                        format!("{option} {}", v.name),
                        v.kind.text(),
                        format!(
                            "a range that holds n = {n} distinct values in floating point \
                             (its quantiles at the n cell centres take only {distinct} \
                             distinct values); widen the range or move it nearer 0"
                        ),
                    ));
                }
            }
        }
        for v in &self.vars {
            if let Kind::Levels { labels, .. } = &v.kind {
                if n < labels.len() {
                    return Err(Error::invalid(
                        "n",
                        n,
                        format!(
                            "at least {} points, so that every level of {} ({} in {option}) \
                             appears",
                            labels.len(),
                            v.name,
                            v.kind.text()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

fn parse_variable(option: &str, item: &str) -> Result<Vec<Variable>, Error> {
    let VariableText { name, ty } = design::variable(option, item)?;
    let kind = match ty {
        TypeText::Brownian { args } => {
            let path = path::Brownian::parse(args, |expected| {
                Error::invalid(option, item, format!("{name}={expected}"))
            })?;
            return Ok((0..path.m)
                .map(|step| Variable {
                    name: format!("{name}_{}", step + 1),
                    kind: Kind::Path {
                        base: name.to_string(),
                        path,
                        step,
                    },
                })
                .collect());
        }
        TypeText::Levels { labels, ordered } => Kind::Levels { labels, ordered },
        TypeText::Integer { lo, hi } => Kind::Integer { lo, hi },
        TypeText::Law { func, numbers } => law(option, item, name, &func, &numbers)?,
    };
    Ok(vec![Variable {
        name: name.to_string(),
        kind,
    }])
}

/// A law by its name and parameters, checked.
fn law(option: &str, item: &str, name: &str, func: &str, numbers: &[f64]) -> Result<Kind, Error> {
    let bad = |expected: String| Error::invalid(option, item, expected);
    let arity = |k: &[usize]| -> Result<(), Error> {
        if k.contains(&numbers.len()) {
            Ok(())
        } else {
            Err(bad(format!(
                "{name}={func}(...) with {} parameters",
                k.iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            )))
        }
    };
    let m = match func {
        "uniform" => {
            arity(&[2])?;
            Marginal::Uniform {
                lo: numbers[0],
                hi: numbers[1],
            }
        }
        "normal" => {
            arity(&[2])?;
            Marginal::Normal {
                mu: numbers[0],
                sigma: numbers[1],
            }
        }
        "truncnormal" => {
            arity(&[4])?;
            Marginal::TruncNormal {
                mu: numbers[0],
                sigma: numbers[1],
                lo: numbers[2],
                hi: numbers[3],
            }
        }
        "lognormal" => {
            arity(&[2])?;
            Marginal::LogNormal {
                mu: numbers[0],
                sigma: numbers[1],
            }
        }
        "beta" => {
            arity(&[2, 4])?;
            let (lo, hi) = if numbers.len() == 4 {
                (numbers[2], numbers[3])
            } else {
                (0.0, 1.0)
            };
            Marginal::Beta {
                a: numbers[0],
                b: numbers[1],
                lo,
                hi,
            }
        }
        "triangular" => {
            arity(&[3])?;
            Marginal::Triangular {
                lo: numbers[0],
                mode: numbers[1],
                hi: numbers[2],
            }
        }
        _ => return Err(bad(format!("{name}= one of {}", design::TYPES))),
    };
    m.check(&format!("{option} {name}"))?;
    Ok(Kind::Continuous(m))
}

/// One column of a design as written.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// A continuous variable's values.
    Real(Vec<f64>),
    /// An integer variable's values.
    Int(Vec<i64>),
    /// A categorical variable's labels.
    Label(Vec<String>),
}

/// A design: its space, the unit-cube set it was made from (continuous coordinates as
/// optimised; a discrete coordinate at the centre of its level's share of [0, 1)), and
/// the level index of every discrete value.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// The space.
    pub space: DesignSpace,
    /// The design on the unit scale, one coordinate per variable.
    pub unit: PointSet,
    /// Per variable, the level index of each point (empty for a continuous variable).
    pub levels: Vec<Vec<usize>>,
}

impl Design {
    /// Makes the design from a unit-cube set with one coordinate per variable (the
    /// run's stratified set): levels dealt by rank, categorical pairs balanced, slices
    /// stratified. `seed` drives the balancing's random order; `finish` says what the
    /// continuous part's exchanges lower afterwards (see [`balance::arrange`]).
    pub fn build(
        space: &DesignSpace,
        base: &PointSet,
        seed: u64,
        finish: balance::Finish,
    ) -> Result<Design, Error> {
        check_dim(space, base)?;
        let (unit, levels) = balance::arrange(space, base, seed, finish);
        Ok(Design {
            space: space.clone(),
            unit,
            levels,
        })
    }

    /// Number of points.
    pub fn n(&self) -> usize {
        self.unit.n()
    }

    /// The columns as written: continuous values through the copula (if any) and the
    /// marginal's quantile function, paths through their map, integers, labels.
    pub fn columns(&self) -> Vec<Column> {
        let n = self.n();
        let cont = self.space.marginals();
        // Each continuous variable's uniform score per point, correlated once per point.
        let mut scores: Vec<Vec<f64>> = cont
            .iter()
            .map(|&j| (0..n).map(|i| self.unit.point(i)[j]).collect())
            .collect();
        if let Some(c) = &self.space.copula {
            for i in 0..n {
                let u: Vec<f64> = scores.iter().map(|col| col[i]).collect();
                for (col, v) in scores.iter_mut().zip(c.correlate(&u)) {
                    col[i] = v;
                }
            }
        }
        let mut scores = scores.into_iter();
        // Each path's m coordinates per point, mapped together, then cut into columns.
        let mut paths: Vec<Vec<f64>> = Vec::new();
        for (first, path) in self.space.paths() {
            let m = path.m;
            let u: Vec<f64> = (0..n)
                .flat_map(|i| self.unit.point(i)[first..first + m].to_vec())
                .collect();
            paths.push(path.paths(&u));
        }
        let mut path_at = 0usize;
        self.space
            .vars
            .iter()
            .enumerate()
            .map(|(j, v)| match &v.kind {
                Kind::Continuous(m) => {
                    let mut column = scores.next().unwrap_or_default();
                    m.ppf_in_place(&mut column);
                    Column::Real(column)
                }
                Kind::Path { path, step, .. } => {
                    let w = &paths[path_at];
                    if step + 1 == path.m {
                        path_at += 1;
                    }
                    Column::Real((0..n).map(|i| w[i * path.m + step]).collect())
                }
                Kind::Integer { lo, .. } => {
                    Column::Int(self.levels[j].iter().map(|&l| lo + l as i64).collect())
                }
                Kind::Levels { labels, .. } => {
                    Column::Label(self.levels[j].iter().map(|&l| labels[l].clone()).collect())
                }
            })
            .collect()
    }

    /// The design as numbers, one row per point: continuous values, integers, and a
    /// label's index in its list (for formats without text).
    pub fn numbers(&self) -> Result<PointSet, Error> {
        let (n, s) = (self.n(), self.space.dim());
        let mut data = vec![0.0; n * s];
        for (j, column) in self.columns().into_iter().enumerate() {
            let values: Vec<f64> = match column {
                Column::Real(v) => v,
                Column::Int(v) => v.into_iter().map(|x| x as f64).collect(),
                Column::Label(_) => self.levels[j].iter().map(|&l| l as f64).collect(),
            };
            for (i, v) in values.into_iter().enumerate() {
                data[i * s + j] = v;
            }
        }
        PointSet::new(n, s, data)
    }
}
/// The design whose points are `unit` carried into `space` by the inverse CDF of its
/// law, point by point: continuous variables through the copula (if any) and their
/// quantile functions ([`Design::columns`]), a discrete variable with L equally likely
/// levels to level ⌊u·L⌋. A point uniform in the cube becomes a point of the space's
/// law, so a randomised set stays unbiased; levels are not dealt by rank, which would
/// tie each point's level to the others' coordinates and break that. `unit` is kept as
/// the design's unit-scale set: every column is its exact image.
pub fn mapped(space: &DesignSpace, unit: &PointSet) -> Result<Design, Error> {
    check_dim(space, unit)?;
    let levels = space
        .vars
        .iter()
        .enumerate()
        .map(|(j, v)| match v.kind.levels() {
            None => Vec::new(),
            // A coordinate of 1 (the tent's fold can reach it) is the last level's.
            Some(l) => (0..unit.n())
                .map(|i| ((unit.point(i)[j] * l as f64) as usize).min(l - 1))
                .collect(),
        })
        .collect();
    Ok(Design {
        space: space.clone(),
        unit: unit.clone(),
        levels,
    })
}

/// `mapped(space, unit)?.numbers()` ([`Design::numbers`]), bit for bit, without building
/// the design where every variable is continuous and uncorrelated: each column through
/// its quantile function straight from the unit set's rows into the result's (`quad`
/// maps every batch this way, and the design's copies, gathers and checks cost as much
/// as the quantiles of normal laws' central region).
pub fn mapped_numbers(space: &DesignSpace, unit: &PointSet) -> Result<PointSet, Error> {
    let plain: Option<Vec<&Marginal>> = match space.copula {
        Some(_) => None,
        None => space
            .vars
            .iter()
            .map(|v| match &v.kind {
                Kind::Continuous(m) => Some(m),
                _ => None,
            })
            .collect(),
    };
    let Some(marginals) = plain else {
        return mapped(space, unit)?.numbers();
    };
    check_dim(space, unit)?;
    let (n, s) = (unit.n(), unit.s());
    let mut data = vec![0.0; n * s];
    let mut column = vec![0.0; n];
    for (j, m) in marginals.iter().enumerate() {
        for (c, row) in column.iter_mut().zip(unit.as_slice().chunks_exact(s)) {
            *c = row[j];
        }
        m.ppf_in_place(&mut column);
        for (row, &v) in data.chunks_exact_mut(s).zip(&column) {
            row[j] = v;
        }
    }
    PointSet::new(n, s, data)
}

/// Refuses a unit set whose dimension is not the space's, naming the space.
fn check_dim(space: &DesignSpace, unit: &PointSet) -> Result<(), Error> {
    if unit.s() != space.dim() {
        return Err(Error::invalid(
            stillpoint_parse::names::SPACE,
            format!("{} variables", space.dim()),
            format!(
                "one variable per coordinate of the {}-dimensional set",
                unit.s()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mapped_numbers_are_the_design_s_numbers_bit_for_bit() {
        // Coordinates at the ends, in both tails of Φ⁻¹, in its central region, and a run
        // longer than a block of eight lanes.
        let mut u: Vec<f64> = vec![0.0, 1e-300, 1e-12, 0.02, 0.3, 0.5, 0.77, 0.98, 1.0 - 1e-12];
        u.extend((0..40).map(|k| (k as f64 * 0.618_033_988_75).fract()));
        let plain = [
            "a=normal(1,2)",
            "b=lognormal(0,0.5)",
            "c=uniform(-1,3)",
            "d=beta(2,3)",
            "e=triangular(0,1,4)",
            "f=truncnormal(0,1,-1,2)",
        ];
        let mixed = [
            "a=normal(1,2)",
            "k=int(1,5)",
            "c={x,y,z}",
            "W=brownian(1,3,pca)",
        ];
        let bits = |p: &PointSet| p.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for texts in [&plain[..], &mixed[..]] {
            let space = DesignSpace::parse("space", texts).unwrap();
            let s = space.dim();
            let n = u.len();
            let data: Vec<f64> = (0..n * s).map(|i| u[(i * 7 + i / s) % n]).collect();
            let unit = PointSet::new(n, s, data).unwrap();
            let want = mapped(&space, &unit).unwrap().numbers().unwrap();
            assert_eq!(bits(&mapped_numbers(&space, &unit).unwrap()), bits(&want));
        }
        // Correlated laws go through the design's copula.
        let mut space = DesignSpace::parse("space", &["x=normal(0,1)", "y=normal(0,1)"]).unwrap();
        space
            .correlate("correlation", "x-y 0.6", vec![1.0, 0.6, 0.6, 1.0])
            .unwrap();
        let unit = PointSet::new(4, 2, vec![0.1, 0.2, 0.5, 0.5, 0.9, 0.3, 0.01, 0.99]).unwrap();
        let want = mapped(&space, &unit).unwrap().numbers().unwrap();
        assert_eq!(bits(&mapped_numbers(&space, &unit).unwrap()), bits(&want));
        // A set of another dimension is refused, naming the space.
        let e = mapped_numbers(&space, &PointSet::new(1, 3, vec![0.5; 3]).unwrap()).unwrap_err();
        assert!(e.to_string().contains("space"), "{e}");
    }
}
