//! Boxes, bounds and regions given as text on the command line, read by the library's
//! one grammar (`stillpoint::plan::space`) with the flags' names in its refusals.

use super::*;
use stillpoint::plan::space::{self, Bounds};

/// `--box LO1,HI1,LO2,HI2,...` as (lo, hi).
pub(crate) fn parse_box(text: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let v = space::number_list(flag(Opt::bbox), text, text)?;
    Ok(space::intervals(flag(Opt::bbox), text, &v)?)
}

/// `--bounds LO1,HI1,...` for `s` coordinates.
pub(crate) fn parse_bounds(text: &str, s: usize) -> Result<Bounds> {
    let v = space::number_list(flag(Opt::bounds), text, text)?;
    Ok(Bounds::new(flag(Opt::bounds), text, &v, s)?)
}

/// The domain of `--region EXPR --box ..` or `--shape SPEC`.
pub(crate) fn region_domain(
    region: Option<&str>,
    bbox: Option<&str>,
    shape: Option<&str>,
    s: Option<usize>,
) -> Result<Arc<dyn Domain>> {
    let bbox = match bbox {
        Some(text) => Some(space::number_list(flag(Opt::bbox), text, text)?),
        None => None,
    };
    let spec = space::RegionSpec {
        expression: region,
        bbox: bbox.as_deref(),
        shape,
        s,
    };
    Ok(spec.domain(&flag_name)?)
}

/// `--region EXPR --box ..` / `--shape ..` as given on the command line.
#[derive(Clone, Copy)]
pub(crate) struct RegionSpec<'a> {
    pub(crate) region: Option<&'a str>,
    pub(crate) bbox: Option<&'a str>,
    pub(crate) shape: Option<&'a str>,
}
