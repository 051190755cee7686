//! `stillpoint plot` and `generate --plot`: point files, trajectories, start beside result.

use super::*;

/// `stillpoint plot FILE`: a scatter plot (s = 2, with the region's boundary when one is
/// given) or a matrix of projections of the first `dims` coordinates.
pub(crate) fn plot_points(
    file: &std::path::Path,
    output: &std::path::Path,
    dims: Option<String>,
    spec: RegionSpec,
    title: Option<String>,
    split: Option<String>,
) -> Result<()> {
    let points = io::read_points(file)?;
    let s = points.s();
    let n = points.n();
    // Both ranges end at the file's size, so the values are read once it is known.
    let k = match &dims {
        Some(typed) => whole(
            "--dims",
            typed,
            1..=s,
            &format!("1 ≤ K ≤ s = {s} (the file's dimension)"),
        )?,
        None => s.min(4),
    };
    let split = split
        .as_deref()
        .map(|typed| {
            whole(
                "--split",
                typed,
                0..=n,
                &format!("0 ≤ K ≤ n = {n} (the file's number of points)"),
            )
        })
        .transpose()?;
    if let Some(old) = split {
        // Only the scatter plot of s = 2 colours old and new points; the matrix of
        // projections (s ≠ 2, or --dims 1) draws every point alike, so a split there
        // would be dropped without a word.
        if !(s == 2 && k == 2) {
            let drawn = match s {
                2 => "--dims 1 draws histograms".to_string(),
                s => format!("the file has s = {s}, drawn as a matrix of projections"),
            };
            bail!(
                "invalid --split = {old}: expected points of s = 2 drawn as one scatter plot \
                 ({drawn}, which --split does not colour)"
            );
        }
    }
    let title = title.unwrap_or_else(|| {
        file.file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    });
    let domain = if spec.region.is_some() || spec.shape.is_some() {
        Some(region_domain(spec.region, spec.bbox, spec.shape, Some(s))?)
    } else {
        None
    };
    let (lo, hi) = match (&domain, spec.bbox) {
        (Some(d), _) => d.bounding_box(),
        (None, Some(b)) => {
            let (lo, hi) = parse_box(b)?;
            if lo.len() < k {
                bail!(
                    "invalid --box = {b}: it has {} dimensions, {k} are drawn (expected \
                     LO1,HI1,..,LO{k},HI{k})",
                    lo.len()
                );
            }
            (lo, hi)
        }
        (None, None) => plot_box(&points),
    };
    if k == 2 && s == 2 {
        let boundary = match &domain {
            Some(d) if d.level(&[lo[0], lo[1]]).is_some() => stillpoint_plot::boundary_polylines(
                &|x: &[f64]| d.level(x).unwrap_or(f64::NAN),
                [lo[0], lo[1]],
                [hi[0], hi[1]],
                300,
            ),
            _ => Vec::new(),
        };
        let panel = stillpoint_plot::Panel {
            title,
            points: &points,
            lo: [lo[0], lo[1]],
            hi: [hi[0], hi[1]],
            boundary,
            split,
        };
        stillpoint_plot::save_panels(output, &[panel], 1)?;
    } else {
        stillpoint_plot::save_projection_matrix(output, &title, &points, k, &lo, &hi)?;
    }
    Ok(())
}

/// The unit cube when the points lie in it, else their bounding box padded by 5 %.
pub(crate) fn plot_box(points: &PointSet) -> (Vec<f64>, Vec<f64>) {
    if points.check_unit_cube().is_ok() {
        return (vec![0.0; points.s()], vec![1.0; points.s()]);
    }
    (0..points.s())
        .map(|k| {
            let (a, b) = points
                .rows()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                    (a.min(r[k]), b.max(r[k]))
                });
            let pad = if b > a { 0.05 * (b - a) } else { 0.5 };
            (a - pad, b + pad)
        })
        .unzip()
}

/// A trajectory file as `generate --trajectory` writes it.
#[derive(serde::Deserialize)]
pub(crate) struct TrajectoryFile {
    #[serde(default)]
    pub(crate) energy: Option<String>,
    pub(crate) records: Vec<stillpoint::integrators::Record>,
}

/// `stillpoint plot --trajectory TRAJ`: energy (relative to the start) and the logged
/// discrepancies against step and against wall time.
pub(crate) fn plot_trajectory(
    path: &std::path::Path,
    output: &std::path::Path,
    title: Option<String>,
) -> Result<()> {
    use stillpoint_plot::{LineChart, Series};
    let refuse = |why: String| {
        anyhow::anyhow!(
            "invalid --trajectory {}: expected a trajectory written by generate --trajectory \
             ({why})",
            path.display()
        )
    };
    let bytes =
        stillpoint::io::read_bounded(path).map_err(|e| refuse(format!("cannot read it: {e}")))?;
    let traj: TrajectoryFile =
        serde_json::from_slice(&bytes).map_err(|e| refuse(format!("{e}")))?;
    // A non-smooth run repeats its returned state at the end; the curves follow the steps.
    let mut records = Vec::with_capacity(traj.records.len());
    for r in &traj.records {
        if records
            .last()
            .is_none_or(|l: &&stillpoint::integrators::Record| r.step > l.step)
        {
            records.push(r);
        }
    }
    let Some(first) = records.first() else {
        return Err(refuse("it has no records".into()));
    };
    let u0 = first.energy;
    if !(u0.is_finite() && u0 != 0.0) {
        return Err(refuse(format!("the start energy is {u0}")));
    }
    let title = title.unwrap_or_else(|| traj.energy.clone().unwrap_or_else(|| "energy".into()));
    let mut names: Vec<&str> = Vec::new();
    for r in &records {
        for (k, _) in &r.metrics {
            if !names.contains(&k.as_str()) {
                names.push(k);
            }
        }
    }
    let energy = |x: &dyn Fn(&stillpoint::integrators::Record) -> f64| Series {
        name: "U / U(start)".into(),
        points: records.iter().map(|r| (x(r), r.energy / u0)).collect(),
    };
    let metric = |x: &dyn Fn(&stillpoint::integrators::Record) -> f64| -> Vec<Series> {
        names
            .iter()
            .map(|name| Series {
                name: (*name).to_string(),
                points: records
                    .iter()
                    .filter_map(|r| {
                        r.metrics
                            .iter()
                            .find(|(k, _)| k == name)
                            .map(|(_, v)| (x(r), *v))
                    })
                    .collect(),
            })
            .collect()
    };
    let by_step = |r: &stillpoint::integrators::Record| r.step as f64;
    let by_time = |r: &stillpoint::integrators::Record| r.seconds;
    let chart = |t: String, x: &str, y: &str, series: Vec<Series>| LineChart {
        title: t,
        x_label: x.into(),
        y_label: y.into(),
        log_y: false,
        series,
    };
    let mut charts = vec![
        chart(
            format!("{title}: energy"),
            "step",
            "U / U(start)",
            vec![energy(&by_step)],
        ),
        chart(
            format!("{title}: energy"),
            "seconds",
            "U / U(start)",
            vec![energy(&by_time)],
        ),
    ];
    if !names.is_empty() {
        charts.push(chart(
            "discrepancies (roots)".into(),
            "step",
            "discrepancy",
            metric(&by_step),
        ));
        charts.push(chart(
            "discrepancies (roots)".into(),
            "seconds",
            "discrepancy",
            metric(&by_time),
        ));
    }
    stillpoint_plot::save_line_chart_grid(output, &charts, 2)?;
    Ok(())
}

/// Draws the start beside the result, with the boundary when the domain has one and s = 2.
pub(crate) fn plot_start_result(
    path: &std::path::Path,
    start: &PointSet,
    result: &PointSet,
    domain: &dyn Domain,
    old: Option<usize>,
) -> Result<()> {
    if start.s() < 2 {
        bail!("invalid --plot: the points have s = 1; plots need s ≥ 2");
    }
    let (lo, hi) = domain.bounding_box();
    let (lo2, hi2) = ([lo[0], lo[1]], [hi[0], hi[1]]);
    let boundary = if start.s() == 2 && domain.level(&[lo[0], lo[1]]).is_some() {
        stillpoint_plot::boundary_polylines(
            &|x: &[f64]| domain.level(x).unwrap_or(f64::NAN),
            lo2,
            hi2,
            300,
        )
    } else {
        Vec::new()
    };
    let panels = [
        stillpoint_plot::Panel {
            title: "start".into(),
            points: start,
            lo: lo2,
            hi: hi2,
            boundary: boundary.clone(),
            split: old,
        },
        stillpoint_plot::Panel {
            title: "result".into(),
            points: result,
            lo: lo2,
            hi: hi2,
            boundary,
            split: old,
        },
    ];
    stillpoint_plot::save_panels(path, &panels, 2)?;
    Ok(())
}
