//! `stillpoint integrate --expr`: an expression integrated to a tolerance by the
//! library's `stillpoint::cubature` driver, with its refusals in the flags' names.

use super::*;
use stillpoint::cubature::{quad, QuadOptions};
use stillpoint::parse::expr::RegionExpr;

/// The flag that sets a `QuadOptions` field or a `Cubature` argument.
fn quad_flag(name: &str) -> String {
    match name {
        "d" => "-s".to_string(),
        "a" | "b" => "--bounds".to_string(),
        other => format!("--{}", other.replace('_', "-")),
    }
}

/// Runs `integrate --expr` and prints the estimate, half-width, evaluations and whether
/// the tolerance was met.
pub(crate) fn quad_command(q: QuadArgs, json: bool) -> Result<()> {
    let (Some(text), Some(s)) = (q.expr.as_deref(), q.s) else {
        bail!("--expr needs -s");
    };
    let expr = RegionExpr::parse(text, s).map_err(|e| anyhow::anyhow!("invalid --expr: {e}"))?;
    let (a, b) = match q.bounds.as_deref() {
        Some(text) => {
            let bounds = parse_bounds(text, s)?;
            (Some(bounds.lo), Some(bounds.hi))
        }
        None => (None, None),
    };
    let options = QuadOptions {
        a,
        b,
        abs_tol: q.abs_tol,
        rel_tol: q.rel_tol,
        level: q.level,
        replicates: q.replicates,
        max_n: q.max_n,
        seed: q.seed,
        ..QuadOptions::default()
    };
    let f = |x: &PointSet| x.rows().map(|p| expr.eval(p)).collect();
    let r = quad(f, s, options).map_err(|e| match e {
        stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        } if name == "f" => {
            anyhow::anyhow!("--expr {text:?} is not finite: {value}; expected {expected}")
        }
        stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        } => stillpoint::Error::invalid(quad_flag(&name), value, expected).into(),
        other => other.into(),
    })?;
    for w in &r.warnings {
        noteln!("warning: {w}");
    }
    if json {
        let v = json!({"expr": text, "s": s, "estimate": r.estimate[0],
                       "half_width": r.half_width[0], "n": r.n, "replicates": r.replicates,
                       "level": q.level, "rel_tol": q.rel_tol, "abs_tol": q.abs_tol,
                       "met": r.met});
        outln!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        outln!("estimate     {}", r.estimate[0]);
        outln!("half-width   {} (level {})", r.half_width[0], q.level);
        outln!("evaluations  {} ({} replicates)", r.n, r.replicates);
        outln!(
            "met          {}",
            if r.met {
                "yes".to_string()
            } else {
                format!("no: --max-n {} reached first", q.max_n)
            }
        );
    }
    Ok(())
}
