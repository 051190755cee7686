//! The space-filling goal in the cube.

use crate::config::GenerateConfig;
use crate::goals::goal_report;
use crate::goals::paper::paper_run;
use crate::report::{Candidate, GenerateReport, Stage};
use crate::Error;
use stillpoint_domains::PointSet;
use stillpoint_quality::metrics::{self};
use stillpoint_sequences as sequences;
use stillpoint_solve::Event;

/// Latin hypercube starts of the space-filling goal's maximin search (each about half a
/// second at most).
const SPACE_FILLING_LHS_STARTS: u64 = 4;

/// Further passes of the search from the best candidate.
const SPACE_FILLING_PASSES: u64 = 3;

/// The space-filling goal in the cube: the paper's run, stratified, and a Latin
/// hypercube, each through the maximin swap search; the larger smallest distance wins.
pub fn space_filling_run(
    cfg: &GenerateConfig,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let mut paper_cfg = cfg.as_paper();
    paper_cfg.randomize = None;
    let paper = paper_run(&paper_cfg, None, &mut *on_event)?;
    on_event(Event::Stage {
        name: "maximin search",
        steps: None,
    });
    let from_dem = crate::goals::integration::stratify(&paper.output.points);
    // Candidates: the DEM's set and several Latin hypercubes, each through the search.
    let mut candidates = vec![(
        "the DEM's result, stratified".to_string(),
        sequences::maximin_search(from_dem.clone(), cfg.seed)?,
    )];
    for k in 0..SPACE_FILLING_LHS_STARTS {
        candidates.push((
            format!("a Latin hypercube (seed {})", cfg.seed.wrapping_add(k)),
            sequences::lhs_maximin(cfg.n, cfg.s, cfg.seed.wrapping_add(k))?,
        ));
    }
    let min_d = |p: &PointSet| metrics::min_distance_euclidean(p);
    // Each candidate's smallest distance once (an O(n² s) pass); the first best is kept.
    let judged: Vec<Candidate> = candidates
        .iter()
        .map(|(l, p)| Candidate {
            label: l.clone(),
            value: min_d(p),
        })
        .collect();
    let kept = judged.iter().enumerate().fold(
        0,
        |b, (i, c)| if judged[b].value >= c.value { b } else { i },
    );
    let mut points = candidates.swap_remove(kept).1;
    // More passes of the search from the best, each with its own random stream: the
    // search never returns a set below its start, so each pass only adds.
    let mut passes = Vec::new();
    for pass in 0..SPACE_FILLING_PASSES {
        let stream = cfg.seed ^ 0x9e37_79b9_7f4a_7c15u64.wrapping_mul(pass + 1);
        points = sequences::maximin_search(points, stream)?;
        passes.push(min_d(&points));
    }
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![
        Stage::Dem {
            energy: paper.energy_name.clone(),
            steps: paper
                .output
                .trajectory
                .iter()
                .map(|r| r.step)
                .max()
                .unwrap_or(0),
            stop: paper.output.stop,
        },
        Stage::Maximin {
            candidates: judged,
            kept,
            passes,
        },
    ];
    let energy = (min_d(&from_dem), min_d(&points));
    goal_report(
        cfg,
        from_dem,
        points,
        energy,
        "minimum distance (Euclidean)".into(),
        stages,
    )
}
