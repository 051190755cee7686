//! Regions from the command line: `--region EXPR --box ...` and `--shape ...`.

use super::*;

/// Parses a comma-separated list of numbers for the option `name`.
pub(crate) fn number_list(name: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| {
                    format!("invalid {name} = {text}: {t:?} is not a finite number (expected comma-separated numbers)")
                })
        })
        .collect()
}

/// `--box LO1,HI1,LO2,HI2,...` as (lo, hi).
pub(crate) fn parse_box(text: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    parse_intervals("--box", text)
}

/// `--bounds LO1,HI1,...` for `s` coordinates, as (lo, hi).
pub(crate) fn parse_bounds(text: &str, s: usize) -> Result<(Vec<f64>, Vec<f64>)> {
    let (lo, hi) = parse_intervals("--bounds", text)?;
    if lo.len() != s {
        bail!(
            "invalid --bounds = {text}: it has {} intervals, the points have s = {s} \
             coordinates (expected LO1,HI1,...,LO{s},HI{s})",
            lo.len()
        );
    }
    Ok((lo, hi))
}

/// The points of [0, 1]^s mapped to the box, x ↦ lo + x·(hi − lo), as `qmc.scale` does.
pub(crate) fn scale_to(points: &PointSet, lo: &[f64], hi: &[f64]) -> Result<PointSet> {
    let s = points.s();
    let data = points
        .as_slice()
        .iter()
        .enumerate()
        .map(|(i, &x)| lo[i % s] + x * (hi[i % s] - lo[i % s]))
        .collect();
    Ok(PointSet::new(points.n(), s, data)?)
}

/// Points of the box mapped back to [0, 1]^s; a point outside the box is refused.
pub(crate) fn unscale_from(
    points: &PointSet,
    lo: &[f64],
    hi: &[f64],
    file: &std::path::Path,
) -> Result<PointSet> {
    let s = points.s();
    let mut data = Vec::with_capacity(points.as_slice().len());
    for (i, &x) in points.as_slice().iter().enumerate() {
        let k = i % s;
        if !(lo[k] <= x && x <= hi[k]) {
            bail!(
                "{}: point {}, coordinate {} = {x} lies outside --bounds [{}, {}]",
                file.display(),
                i / s + 1,
                k + 1,
                lo[k],
                hi[k]
            );
        }
        data.push(((x - lo[k]) / (hi[k] - lo[k])).clamp(0.0, 1.0));
    }
    Ok(PointSet::new(points.n(), s, data)?)
}

/// Two numbers per coordinate, LO < HI each, with a usable width.
fn parse_intervals(flag: &str, text: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let v = number_list(flag, text)?;
    Ok(stillpoint::plan::space::intervals(flag, text, &v)?)
}

/// The domain of `--region EXPR --box ..` or `--shape SPEC`.
pub(crate) fn region_domain(
    region: Option<&str>,
    bbox: Option<&str>,
    shape: Option<&str>,
    s: Option<usize>,
) -> Result<Arc<dyn Domain>> {
    let dim_check = |got: usize| -> Result<()> {
        match s {
            Some(s) if s != got => {
                bail!("invalid -s = {s}: the region has dimension {got}")
            }
            _ => Ok(()),
        }
    };
    if region.is_some() && shape.is_some() {
        bail!("give either --region EXPR or --shape SHAPE, not both");
    }
    if let Some(expr) = region {
        let (lo, hi) = parse_box(bbox.context("--region needs --box LO1,HI1,LO2,HI2,...")?)?;
        dim_check(lo.len())?;
        let g = stillpoint::expr::RegionExpr::parse(expr, lo.len())
            .with_context(|| "invalid --region".to_string())?;
        let r = ImplicitRegion::new(g.into_fn(), lo, hi)?;
        r.check(4096, 0).context("--region")?;
        return Ok(Arc::new(r));
    }
    let spec = shape.unwrap_or_default();
    let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let need_s = || s.context("this --shape needs -s S (the dimension)");
    let split_at = |text: &str| -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        match text.split_once('@') {
            Some((a, c)) => Ok((number_list("--shape", a)?, Some(number_list("--shape", c)?))),
            None => Ok((number_list("--shape", text)?, None)),
        }
    };
    let domain: Arc<dyn Domain> = match kind {
        "ball" => {
            let (r, c) = split_at(rest)?;
            if r.len() != 1 {
                bail!("invalid --shape = {spec}: expected ball:R or ball:R@C1,C2,...");
            }
            let c = match c {
                Some(c) => c,
                None => vec![0.0; need_s()?],
            };
            Arc::new(Ball::new(c, r[0])?)
        }
        "ellipsoid" => {
            let (a, c) = split_at(rest)?;
            let c = c.unwrap_or_else(|| vec![0.0; a.len()]);
            Arc::new(Ellipsoid::new(c, a)?)
        }
        "box" => {
            let (lo, hi) =
                parse_box(rest).map_err(|e| anyhow::anyhow!("invalid --shape = {spec}: {e}"))?;
            Arc::new(BoxRegion::new(lo, hi)?)
        }
        "simplex" => Arc::new(Simplex::new(need_s()?)?),
        "polytope" => {
            let rows =
                io::read_points(std::path::Path::new(rest)).context("--shape polytope:FILE")?;
            if rows.s() < 2 {
                bail!("invalid --shape = {spec}: each row needs a1 .. as b (at least 2 numbers)");
            }
            let a: Vec<Vec<f64>> = rows.rows().map(|r| r[..r.len() - 1].to_vec()).collect();
            let b: Vec<f64> = rows.rows().map(|r| r[r.len() - 1]).collect();
            let (lo, hi) = parse_box(bbox.context("--shape polytope:FILE needs --box")?)?;
            Arc::new(Polytope::new(a, b, lo, hi)?)
        }
        _ => bail!(
            "invalid --shape = {spec}: expected ball:R[@C..], ellipsoid:A1,..[@C..], \
             box:LO1,HI1,.., simplex or polytope:FILE"
        ),
    };
    dim_check(domain.dim())?;
    Ok(domain)
}

/// `--region EXPR --box ..` / `--shape ..` as given on the command line.
#[derive(Clone, Copy)]
pub(crate) struct RegionSpec<'a> {
    pub(crate) region: Option<&'a str>,
    pub(crate) bbox: Option<&'a str>,
    pub(crate) shape: Option<&'a str>,
}
