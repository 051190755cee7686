//! The start set of a run, in the cube or in a region.

use crate::config::{GenerateConfig, Init};
use crate::Error;
use stillpoint_domains::{Domain, PointSet};
use stillpoint_sequences as sequences;

/// The most candidate shifts the shift selection tries (each costs one discrepancy
/// evaluation; beyond this the selection gains nothing measurable).
pub const MAX_SHIFTS: usize = 1 << 20;

/// Builds the start set of a configuration, checked against n, s and the space.
pub fn start_set(cfg: &GenerateConfig) -> Result<PointSet, Error> {
    sequences::check_size(cfg.n, cfg.s)?;
    if cfg.shifts > MAX_SHIFTS {
        return Err(Error::invalid(
            stillpoint_parse::names::SHIFTS,
            cfg.shifts,
            format!("at most {MAX_SHIFTS} candidate shifts"),
        ));
    }
    if let Some(domain) = cfg.region() {
        // When a set grows, the start holds the new points only.
        let n = cfg.n - cfg.extend.as_ref().map_or(0, |p| p.n().min(cfg.n));
        return crate::plan::start::start_in_region(domain.as_ref(), n, &cfg.init, cfg.seed);
    }
    match &cfg.init {
        Init::Halton => sequences::halton(cfg.n, cfg.s),
        Init::Random => sequences::random(cfg.n, cfg.s, cfg.seed),
        Init::Points(p) => {
            if p.n() != cfg.n || p.s() != cfg.s {
                return Err(Error::invalid(
                    "init points",
                    format!("{} points in {} dimensions", p.n(), p.s()),
                    format!("{} points in {} dimensions (-n, -s)", cfg.n, cfg.s),
                ));
            }
            p.check_unit_cube()?;
            Ok(p.clone())
        }
    }
}

/// The start of a run in a region: the paper's (uniform in the box, the first n inside),
/// Halton points in the box (the first n inside), or given points, all inside.
pub fn start_in_region(
    d: &dyn Domain,
    n: usize,
    init: &Init,
    seed: u64,
) -> Result<PointSet, Error> {
    if n == 0 {
        return Err(Error::invalid("n", n, "at least 1 point"));
    }
    match init {
        Init::Random => d.sample(n, seed),
        Init::Halton => {
            let (lo, hi) = d.bounding_box();
            let s = lo.len();
            let budget = 10_000.max(1000 * n);
            let h = sequences::halton(budget, s)?;
            let mut data = Vec::with_capacity(n * s);
            let mut y = vec![0.0; s];
            for row in h.rows() {
                for k in 0..s {
                    y[k] = lo[k] + (hi[k] - lo[k]) * row[k];
                }
                if d.contains(&y) {
                    data.extend_from_slice(&y);
                    if data.len() == n * s {
                        return PointSet::new(n, s, data);
                    }
                }
            }
            Err(Error::invalid(
                stillpoint_parse::names::REGION,
                format!("{} of {budget} Halton points inside", data.len() / s),
                format!("a region filling enough of its box to hold {} points", n),
            ))
        }
        Init::Points(p) => {
            if p.s() != d.dim() {
                return Err(Error::invalid(
                    "init points",
                    format!("dimension {}", p.s()),
                    format!("the region's dimension {}", d.dim()),
                ));
            }
            if let Some(i) = (0..p.n()).find(|&i| !d.contains(p.point(i))) {
                return Err(Error::invalid(
                    format!("init point {}", i + 1),
                    format!("{:?}", p.point(i)),
                    "a point inside the region",
                ));
            }
            Ok(p.clone())
        }
    }
}
