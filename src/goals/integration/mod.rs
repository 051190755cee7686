//! INTEGRATION

pub mod descent;
pub mod exchange;

pub use descent::*;

use crate::energies::PointSet;
use crate::goals::goal_report;
use crate::plan::*;
use crate::quality::metrics::Metrics;
use crate::quality::stratification::is_stratified;
use crate::quality::target::Target;
use crate::solve::Event;
use crate::Error;

/// The integration goal: [`crate::goals::integration::integration_set`].
pub(crate) fn integration_run(
    cfg: &GenerateConfig,
    target: &Target,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    on_event(Event::Stage {
        name: "stratified descent",
        steps: None,
    });
    let effort = crate::goals::integration::Effort::default();
    if let Some(old) = &cfg.extend {
        if old.s() != cfg.s || old.n() > cfg.n {
            return Err(Error::invalid(
                "extend",
                format!("{} points in {} dimensions", old.n(), old.s()),
                format!("at most n = {} points in s = {} dimensions", cfg.n, cfg.s),
            ));
        }
        let ext =
            crate::goals::integration::extend_set(old, cfg.n - old.n(), target, cfg.seed, &effort)?;
        let new = PointSet::new(
            cfg.n - ext.old,
            cfg.s,
            ext.points.as_slice()[ext.old * cfg.s..].to_vec(),
        )?;
        let figures = |p: &PointSet| {
            let m = Metrics::compute(p);
            format!(
                "D_MD {:.6}, D_L2* {:.6}, CD {:.6}",
                m.modified_l2, m.star_l2, m.centered_l2
            )
        };
        let stages = vec![
            format!(
                "extended {} old points (first, unchanged) by {} new ones, placed from {} \
                 in the free cells of the union's grid, then exchanges and in-cell L-BFGS \
                 moving the new points only",
                ext.old,
                cfg.n - ext.old,
                ext.start_label
            ),
            format!(
                "union stratified on its {} cells per coordinate: {}",
                cfg.n,
                if ext.stratified {
                    "yes".to_string()
                } else {
                    format!(
                        "no ({} old points share a cell of the union's grid with another, \
                         so as many cells stay empty)",
                        ext.collisions
                    )
                }
            ),
            format!("old points: {}", figures(old)),
            format!("new points alone: {}", figures(&new)),
            format!("union: {}", figures(&ext.points)),
        ];
        let (a, b) = (target.value(&ext.start), target.value(&ext.points));
        return goal_report(cfg, ext.start, ext.points, (a, b), target.name(), stages);
    }
    if !cfg.nested.is_empty() {
        if cfg.nested.last() != Some(&cfg.n) {
            return Err(Error::invalid(
                "nested",
                format!("{:?}", cfg.nested),
                format!("stages ending at n = {}", cfg.n),
            ));
        }
        let points =
            crate::goals::integration::nested_set(&cfg.nested, cfg.s, target, cfg.seed, &effort)?;
        let mut stages = vec![format!(
            "nested: the first {} points made for their size, each later stage added by \
             extension; every prefix below",
            cfg.nested[0]
        )];
        for &k in &cfg.nested {
            let prefix = PointSet::new(k, cfg.s, points.as_slice()[..k * cfg.s].to_vec())?;
            let m = Metrics::compute(&prefix);
            stages.push(format!(
                "first {k}: D_MD {:.6}, D_L2* {:.6}, CD {:.6}, stratified: {}",
                m.modified_l2,
                m.star_l2,
                m.centered_l2,
                if crate::goals::integration::is_stratified(&prefix) {
                    "yes"
                } else {
                    "no"
                }
            ));
        }
        let v = target.value(&points);
        return goal_report(cfg, points.clone(), points, (v, v), target.name(), stages);
    }
    let (points, outcome) =
        crate::goals::integration::integration_set(cfg.n, cfg.s, target, cfg.seed, &effort)?;
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![
        format!(
            "start: the best of {} stratified scrambled Sobol' sets and a scrambled Halton \
             set by the target: {}",
            effort.starts, outcome.start
        ),
        format!(
            "descent: {} rounds of coordinate exchanges and in-cell L-BFGS; every coordinate \
             stratified (one point in each [k/n, (k+1)/n))",
            effort.rounds
        ),
    ];
    goal_report(
        cfg,
        outcome.start_points,
        points,
        (outcome.before, outcome.after),
        target.name(),
        stages,
    )
}
