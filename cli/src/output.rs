//! Writing the points and the trajectory, and parsing `compare --cases`.

use super::*;

/// `--cases 2x1500,3x1500` as (s, n) pairs.
pub(crate) fn parse_cases(text: &str) -> Result<Vec<(usize, usize)>> {
    text.split(',')
        .map(|c| {
            let (s, n) = c.trim().split_once(['x', 'X']).with_context(|| {
                format!("invalid --cases = {text}: {c:?} is not SxN (e.g. 2x1500)")
            })?;
            let parse = |v: &str, what: &str| -> Result<usize> {
                match v.trim().parse::<usize>() {
                    Ok(k) if k >= 1 => Ok(k),
                    _ => bail!("invalid --cases = {text}: {what} {v:?} is not an integer ≥ 1"),
                }
            };
            let (s, n) = (parse(s, "s")?, parse(n, "n")?);
            stillpoint::sequences::check_size(n, s)
                .with_context(|| format!("invalid --cases = {text}: case {c}"))?;
            Ok((s, n))
        })
        .collect()
}

/// Writes the points (to `output`, or as CSV to standard output) and the summary: a JSON
/// object (printed to standard output, with the points when there is no output file) or a
/// table (to standard output, or to standard error when the points went there).
///
/// The outputs written under `staging` (the points among them) are put in place before
/// anything is printed.
pub(crate) fn emit(
    points: &PointSet,
    meta: &Value,
    output: Option<&PathBuf>,
    summary: Value,
    staging: io::Staging,
) -> Result<()> {
    if let Some(path) = output {
        io::write_points(path, points, meta)?;
    }
    staging.commit()?;
    match summary {
        Value::String(table) => match output {
            Some(_) => out!("{table}"),
            None => {
                out!("{}", io::to_csv_string(points, meta));
                note!("{table}");
            }
        },
        mut v => {
            if output.is_none() {
                v["points"] = points_json(points);
            }
            outln!("{}", serde_json::to_string_pretty(&v)?);
        }
    }
    Ok(())
}

/// The run's trajectory as JSON (energy every step, logged metrics), written atomically.
pub(crate) fn write_trajectory(
    path: &std::path::Path,
    energy: &str,
    output: &stillpoint::integrators::RunOutput,
) -> Result<()> {
    let traj = serde_json::to_vec_pretty(&json!({
        "energy": energy,
        "records": output.trajectory,
    }))?;
    io::write_atomic(path, &traj)?;
    Ok(())
}
