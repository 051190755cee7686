//! The integration goal: stratified sets with a low squared L2 discrepancy
//! ([`integration_set`], with the exchange move of [`exchange`]), one set, an extension of
//! a given one, or a nested sequence, each reported stage by stage.

pub mod blocks;
mod descent;
pub mod exchange;
pub mod lattice;
mod shift_fft;
pub mod tent;

pub use descent::{
    center_columns, center_columns_after, descend_in_cells, descend_in_cells_after,
    exchange_descent, exchange_descent_after, extend_set, integration_set, nested_run, nested_set,
    stratify, Extension, Nested, Outcome, GUARD_SOBOL_SETS, SOBOL_NET_FROM_N,
};

use crate::config::GenerateConfig;
use crate::goals::goal_report;
use crate::report::{GenerateReport, Stage};
use crate::Error;
use stillpoint_domains::PointSet;
use stillpoint_quality::effort::Effort;
use stillpoint_quality::metrics::{Metrics, Sums};
use stillpoint_quality::stratification::is_stratified;
use stillpoint_quality::target::Target;
use stillpoint_solve::Event;

/// The figures of a part of a result, as a report stage.
fn figures(of: String, p: &PointSet, stratified: Option<bool>, sums: Sums) -> Stage {
    let m = Metrics::compute_with(p, sums);
    Stage::Figures {
        of,
        modified_l2: m.modified_l2,
        star_l2: m.star_l2,
        centered_l2: m.centered_l2,
        stratified,
    }
}

/// The start stage of an extension to `n` points.
fn extension_start(ext: &Extension, n: usize) -> Stage {
    Stage::Start {
        n,
        made: format!(
            "the {} new points placed in the free cells of the union's grid, in the order \
             of each candidate",
            n - ext.old
        ),
        candidates: ext.candidates.clone(),
        kept: ext.kept,
    }
}

/// The start stage of a set made for its size.
fn outcome_start(o: &Outcome, n: usize) -> Stage {
    Stage::Start {
        n,
        made: o.made.clone(),
        candidates: o.candidates.clone(),
        kept: o.kept,
    }
}

/// The integration goal: [`crate::goals::integration::integration_set`].
pub fn integration_run(
    cfg: &GenerateConfig,
    target: &Target,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    on_event(Event::Stage {
        name: "stratified descent",
        steps: None,
    });
    let effort = Effort {
        sums: cfg.sums,
        ..Default::default()
    };
    if let Some(old) = &cfg.extend {
        return extension_run(cfg, old, target, &effort);
    }
    if !cfg.nested.is_empty() {
        return nested_report(cfg, target, &effort);
    }
    let (points, outcome) =
        crate::goals::integration::integration_set(cfg.n, cfg.s, target, cfg.seed, &effort)?;
    stillpoint_solve::stop_if_cancelled()?;
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![
        outcome_start(&outcome, cfg.n),
        Stage::Descent(outcome.descent.clone()),
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

/// The default from [`lattice::LATTICE_FROM_N`] points on: [`lattice::lattice_rule`],
/// its criterion as the energy pair (the seed's drawn shift against the one kept).
pub fn lattice_run(
    cfg: &GenerateConfig,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let rule = lattice::lattice_rule_observed(cfg.n, cfg.s, cfg.seed, on_event)?;
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![Stage::LatticeRule {
        generator: rule.generator,
        shift: rule.shift,
        weight: stillpoint_sequences::TENT_WEIGHT,
        candidates: rule.candidates,
        drawn: rule.drawn_criterion,
        criterion: rule.criterion,
        note: lattice::shared_note(cfg.n, cfg.s, &rule.shared),
        shared: rule.shared,
    }];
    let mut report = goal_report(
        cfg,
        rule.points.clone(),
        rule.points,
        (rule.drawn_criterion, rule.criterion),
        "order-2 cosine-space error e²₂ of the shift".into(),
        stages,
    )?;
    let (generator, shift) = rule.seconds;
    report.timings.splice(
        0..0,
        [
            ("generating vector".to_string(), generator),
            ("shift".to_string(), shift),
        ],
    );
    Ok(report)
}

/// The set `--randomize tent` randomises: [`tent::tent_set`] (the lattice made for that
/// randomisation, descended on its criterion where coordinates share generators), in
/// place of the descent.
pub fn tent_lattice_run(cfg: &GenerateConfig, target: &Target) -> Result<GenerateReport, Error> {
    let set = tent::tent_set(cfg.n, cfg.s)?;
    let stages = vec![Stage::Lattice {
        criterion: set.lattice_criterion,
        weight: stillpoint_sequences::TENT_WEIGHT,
        generator: set.generator,
        descent: set.descent,
    }];
    let value = target.value_with(&set.points, cfg.sums);
    goal_report(
        cfg,
        set.points.clone(),
        set.points,
        (value, value),
        target.name(),
        stages,
    )
}

/// `--extend`: the old points first and unchanged, new ones placed and descended.
fn extension_run(
    cfg: &GenerateConfig,
    old: &PointSet,
    target: &Target,
    effort: &Effort,
) -> Result<GenerateReport, Error> {
    // The request's resolution gives the dimension of the kept points and n beyond them.
    debug_assert!(
        old.s() == cfg.s && old.n() <= cfg.n,
        "points to extend that do not fit"
    );
    let ext =
        crate::goals::integration::extend_set(old, cfg.n - old.n(), target, cfg.seed, effort)?;
    let new = PointSet::new(
        cfg.n - ext.old,
        cfg.s,
        ext.points.as_slice()[ext.old * cfg.s..].to_vec(),
    )?;
    let stages = vec![
        extension_start(&ext, cfg.n),
        Stage::Descent(ext.descent.clone()),
        Stage::Extension {
            old: ext.old,
            new: cfg.n - ext.old,
            stratified: ext.stratified,
            collisions: ext.collisions,
        },
        figures("old points".into(), old, None, cfg.sums),
        figures("new points alone".into(), &new, None, cfg.sums),
        figures("union".into(), &ext.points, None, cfg.sums),
    ];
    let (a, b) = (
        target.value_with(&ext.start, cfg.sums),
        target.value_with(&ext.points, cfg.sums),
    );
    goal_report(cfg, ext.start, ext.points, (a, b), target.name(), stages)
}

/// `--nested`: the first stage made for its size, each later one added by extension.
/// The report's start is every stage as placed before its descent ([`Nested::start`]).
fn nested_report(
    cfg: &GenerateConfig,
    target: &Target,
    effort: &Effort,
) -> Result<GenerateReport, Error> {
    // The request's resolution makes n the last size.
    debug_assert_eq!(
        cfg.nested.last(),
        Some(&cfg.n),
        "nested sizes ending below n"
    );
    let nested =
        crate::goals::integration::nested_run(&cfg.nested, cfg.s, target, cfg.seed, effort)?;
    let prefix = |k: usize| -> Result<Stage, Error> {
        let p = PointSet::new(k, cfg.s, nested.points.as_slice()[..k * cfg.s].to_vec())?;
        let stratified = is_stratified(&p);
        Ok(figures(
            format!("first {k}"),
            &p,
            Some(stratified),
            cfg.sums,
        ))
    };
    let first = cfg.nested[0];
    let mut stages = vec![
        outcome_start(&nested.first, first),
        Stage::Descent(nested.first.descent.clone()),
        prefix(first)?,
    ];
    for (ext, &k) in nested.extensions.iter().zip(&cfg.nested[1..]) {
        stages.push(extension_start(ext, k));
        stages.push(Stage::Descent(ext.descent.clone()));
        stages.push(prefix(k)?);
    }
    let (a, b) = (
        target.value_with(&nested.start, cfg.sums),
        target.value_with(&nested.points, cfg.sums),
    );
    goal_report(
        cfg,
        nested.start,
        nested.points,
        (a, b),
        target.name(),
        stages,
    )
}
