//! The one rule that decides, for a design space, which unit-cube set its points come
//! from and how that set is carried into the space ([`cube_rule`]). The resolution asks
//! it once and keeps the answer in [`super::request::Resolved::rule`]; the pipeline (the
//! set it makes and the map it applies), the run-time estimate (through the job the rule
//! leaves) and the reports (its [`CubeRule::phrase`]) read that answer and never decide
//! again. A rule made for a law (a lattice for the product of the input densities, a
//! scrambled net where it measures better) is one more variant and one more arm of
//! [`cube_rule`].

use super::request::Job;
use crate::config::GenerateConfig;
use crate::design::balance::Finish;
use crate::design::{Design, DesignSpace};
use crate::post::randomize::Randomize;
use crate::sequences::Baseline;
use crate::{Error, PointSet};

/// How the points of a design space are made in the unit cube and carried into the space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CubeRule {
    /// The request's own set (its goal's construction, or the baseline it names), dealt
    /// into the space: levels by rank, pairs of unordered factors balanced, continuous
    /// columns stratified within slices, then each through its quantile function. The
    /// best design for one seed; the dealing ties the points to one another, so the mean
    /// of f over a seed's points is not an unbiased estimate of E f(X).
    Dealt,
    /// The request's set randomised as [`Randomize`] says (`tent`: the lattice made for
    /// it; `cells`, `shift`: the optimised set), then every coordinate through its law's
    /// inverse CDF ([`mapped`]). Each point then follows the space's law, so each seed's
    /// mean of f is an unbiased estimate of E f(X).
    Randomized(Randomize),
    /// The randomised lattice made for the laws ([`crate::sequences::law_lattice`]: the
    /// first-order kernel on unbounded coordinates, odd-sized parts so that the tent
    /// makes no reflected pairs), mapped as [`CubeRule::Randomized`]: unbiased for every
    /// seed.
    LawLattice,
    /// The deterministic set for a space whose every law is unbounded
    /// ([`crate::sequences::law_lattice_picked_or`]): the lattice made for the laws in odd
    /// parts, each shifted by integer offsets drawn from the seed onto the midpoints after
    /// the tent, the best of 16 draws and the cube's default set on three test integrals
    /// of the normal scores; then mapped as [`CubeRule::Randomized`]. The choice among
    /// candidates ties the points to one another, so (as for [`CubeRule::Dealt`]) a
    /// seed's mean is not an unbiased estimate.
    PickedLattice,
    /// Owen-scrambled Sobol' points from the seed ([`crate::sequences::sobol_scrambled`]),
    /// their leading columns dealt to the leading coordinates (the variables that are not
    /// paths, then every path's first step, then every path's second, …), then mapped as
    /// [`CubeRule::Randomized`]: unbiased for every seed.
    ScrambledSobol,
}

/// The rule for a space and the run the request resolved to (its randomisation, and
/// whether its set is the default one).
///
/// The rule, by law: `--randomize` (tent) under a space that holds a Brownian path takes
/// Owen-scrambled Sobol' points ([`CubeRule::ScrambledSobol`]); under a space whose every
/// coordinate has an unbounded law (normal, lognormal, Student; no bounded or discrete
/// variable) the lattice made for the laws ([`CubeRule::LawLattice`]); every other
/// space, and the other randomisations, the request's own set ([`CubeRule::Randomized`]).
/// Without a randomisation, the default set under two or more variables whose every law
/// is unbounded, with no path and no correlation, is the lattice made for the laws with
/// its offsets picked ([`CubeRule::PickedLattice`]); every other space, and a set the
/// request chose itself (a method, goal, target or run option), is dealt
/// ([`CubeRule::Dealt`]).
/// Why a path takes the scrambled net: a path's leading coordinates (the bridge's end
/// point, the first principal components) carry most of its variance, and a payoff on it
/// (an Asian call) is nearly a function of those few, with a kink; the digital net's
/// projections on its first coordinates are finer than the lattice's made for equal
/// weights, and the lattice made for the laws lost to scrambled Sobol' on the arithmetic
/// Asian and basket calls (bridge paths 1.21×, PCA paths 1.56×, geometric means over the
/// mid grid of results/uq-models) where Owen's scrambling is level with it or better on
/// every construction (results/law-lattice/paths.md).
/// Why, measured on the models with input laws (results/uq-models, n = 1 024 and 4 096,
/// ratio to scrambled Sobol', geometric means): where every law is unbounded, an even
/// lattice's tent pairs every point with its reflection, (Z, −Z) through a symmetric
/// law, and the odd parts of the lattice made for the laws win Keister's family (0.72×
/// against 1.87×) and the lognormal product (1.08× against 1.40×); where bounded laws
/// take part (the engineering models, Ishigami, Morokoff–Caflisch, Sobol' G) the cube's
/// even tent lattice wins all but Sobol' G (0.04–1.25× against 1.11–2.96×): 0.76× over those
/// cells against 0.86× for the cube's lattice everywhere and 0.86× for the lattice made
/// for the laws wherever one law is unbounded (results/law-lattice/rules-by-law.md).
/// Why the default picks drawn offsets where every law is unbounded: the cube's default
/// (its shift searched on the cosine-space error) lost Keister's radial family to
/// scrambled Sobol' (1.34×), and no searched shift measured kept it below 1.5×; drawn
/// offsets, the best of 16 on three normal-score integrals, put every family of those
/// laws at or below scrambled Sobol' (results/law-lattice/deterministic.md); the cube's
/// set judged beside them by the same integrals, kept where it scores best, wins back
/// part of its margin on the ridge-like families (0.65× → 0.64× over all cells, a
/// digital option at 4 096 points 0.99× → 0.19×; results/law-lattice/cube-candidate.md). One
/// variable keeps the dealt set: there every lattice column is a midpoint rule, which
/// the cube's stratified default already is at the full n. A correlated space keeps it
/// too: the test integrals judge the independent scores, not the correlated inputs a
/// model sees, and on four families of correlated normals the picked lattice was no
/// better than the dealt set in any (0.93× scrambled Sobol's error against 0.88×;
/// results/law-lattice/correlated.md).
pub fn cube_rule(space: &DesignSpace, job: &Job) -> CubeRule {
    let randomize = match job {
        Job::Run(cfg) => cfg.randomize,
        Job::Baseline { .. } | Job::Law { .. } => None,
    };
    rule_by_law(space, randomize, is_default_set(job))
}

/// [`cube_rule`] given the randomisation and whether the request's set is the default.
fn rule_by_law(space: &DesignSpace, randomize: Option<Randomize>, default_set: bool) -> CubeRule {
    let unbounded = space.unbounded();
    let every_law_unbounded = !unbounded.is_empty() && unbounded.iter().all(|&u| u);
    let holds_a_path = !space.paths().is_empty();
    let picked = every_law_unbounded
        && !holds_a_path
        && space.copula.is_none()
        && space.dim() >= 2
        && default_set;
    match randomize {
        None if picked => CubeRule::PickedLattice,
        None => CubeRule::Dealt,
        Some(Randomize::Tent) if holds_a_path => CubeRule::ScrambledSobol,
        Some(Randomize::Tent) if every_law_unbounded => CubeRule::LawLattice,
        Some(kind) => CubeRule::Randomized(kind),
    }
}

/// Whether `job` runs the set a request with no option but n, s and the seed runs (the
/// default; `exact` changes only the report): a set the request chose is its own.
fn is_default_set(job: &Job) -> bool {
    let Job::Run(cfg) = job else {
        return false;
    };
    match Job::default_config(cfg.n, cfg.s, cfg.seed) {
        Some(default) => {
            GenerateConfig {
                sums: cfg.sums,
                ..*default
            } == **cfg
        }
        None => false,
    }
}

impl CubeRule {
    /// Every rule, for tests and tables.
    pub const ALL: [CubeRule; 7] = [
        CubeRule::Dealt,
        CubeRule::Randomized(Randomize::Tent),
        CubeRule::Randomized(Randomize::Cells),
        CubeRule::Randomized(Randomize::Shift),
        CubeRule::LawLattice,
        CubeRule::PickedLattice,
        CubeRule::ScrambledSobol,
    ];

    /// The rule in one short phrase, as the report and the file header state it.
    pub fn phrase(self) -> &'static str {
        match self {
            CubeRule::Dealt => "one design: levels dealt by rank, slices balanced",
            CubeRule::Randomized(Randomize::Tent) => {
                "tent-randomised lattice through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
            }
            CubeRule::Randomized(Randomize::Cells) => {
                "set randomised by cells through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
            }
            CubeRule::Randomized(Randomize::Shift) => {
                "set shifted modulo 1 through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
            }
            CubeRule::LawLattice => {
                "lattice made for the laws, shifted and tent-transformed, through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
            }
            CubeRule::PickedLattice => {
                "lattice made for the laws, offsets drawn from the seed onto the midpoints, the best of 16 draws and the cube's default set kept on three normal-score test integrals, through each law's inverse CDF"
            }
            CubeRule::ScrambledSobol => {
                "Owen-scrambled Sobol' through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
            }
        }
    }

    /// Whether each seed's mean of f over the points is an unbiased estimate of E f(X)
    /// under the space's law.
    pub fn unbiased(self) -> bool {
        !matches!(self, CubeRule::Dealt | CubeRule::PickedLattice)
    }

    /// The construction that makes the unit-cube set in place of the request's own run,
    /// if the rule has one.
    pub fn construction(self) -> Option<Baseline> {
        match self {
            CubeRule::ScrambledSobol => Some(Baseline::Sobol),
            _ => None,
        }
    }

    /// The design of `points` (the unit-cube set the rule made, one coordinate per
    /// variable): dealt ([`Design::build`] with `seed` and `finish`) or mapped
    /// ([`mapped`]).
    pub fn design(
        self,
        space: &DesignSpace,
        points: &PointSet,
        seed: u64,
        finish: Finish,
    ) -> Result<Design, Error> {
        match self {
            CubeRule::Dealt => Design::build(space, points, seed, finish),
            CubeRule::ScrambledSobol => mapped(space, &leading_first(space, points)?),
            _ => mapped(space, points),
        }
    }
}

/// The net's columns dealt to the space's coordinates in the order they matter
/// ([`leading_order`]): the net's unit-cube column i goes to coordinate `order[i]`.
fn leading_first(space: &DesignSpace, points: &PointSet) -> Result<PointSet, Error> {
    let s = points.s();
    let order = leading_order(space);
    let mut data = vec![0.0f64; points.n() * s];
    for (out, row) in data.chunks_exact_mut(s).zip(points.rows()) {
        for (&coordinate, &u) in order.iter().zip(row) {
            out[coordinate] = u;
        }
    }
    PointSet::new(points.n(), s, data)
}

/// The space's coordinates in the order a digital net's columns are dealt to them: every
/// variable that is not a path first, then each path's first step (the bridge's end
/// point, the first principal component), then each path's second, and so on. A digital
/// net's leading columns are its finest; with two or more paths, giving one path all the
/// leading columns left the other paths' leading steps to the net's late ones (four
/// paths of 8 to 64 PCA steps: 1.3–6.5× scrambled Sobol' given the steps interleaved).
/// With one path and nothing else the order is the set's own.
pub fn leading_order(space: &DesignSpace) -> Vec<usize> {
    let s = space.dim();
    let mut step = vec![0usize; s];
    for (first, path) in space.paths() {
        for (k, rank) in step.iter_mut().skip(first).take(path.m).enumerate() {
            *rank = k + 1;
        }
    }
    let mut order: Vec<usize> = (0..s).collect();
    order.sort_by_key(|&j| step[j]);
    order
}

/// The rule of a randomised *sequence* for a space (points drawn in rounds that continue
/// one another, as `Engine(d, space=…)` draws them), where [`cube_rule`] decides for a set
/// made for its n, and the order its columns are dealt in ([`leading_order`], for any
/// sequence whose leading columns are its finest): Owen-scrambled Sobol' where the space
/// holds a Brownian path (the rule [`cube_rule`] takes there, for its reason), otherwise
/// the lattice sequence of the first-order table, which is built for the kernel of
/// unbounded laws and measured the better of the two tables over bounded laws as well
/// (results/law-lattice/engine-table.md). On the paths of the models users bring the net
/// and that lattice, both dealt path-first, measured level (results/law-lattice/engine-space.md).
pub fn sequence_rule(space: &DesignSpace) -> (SequenceRule, Vec<usize>) {
    let rule = if space.paths().is_empty() {
        SequenceRule::FirstOrderLattice
    } else {
        SequenceRule::Sobol
    };
    (rule, leading_order(space))
}

/// A randomised sequence's rule ([`sequence_rule`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SequenceRule {
    /// The extensible lattice of the first-order table, one shift, the tent.
    FirstOrderLattice,
    /// Owen-scrambled Sobol' points in natural order.
    Sobol,
}

impl SequenceRule {
    /// The rule as front ends name it (as `quad`'s results name the same rules).
    pub fn as_str(self) -> &'static str {
        match self {
            SequenceRule::FirstOrderLattice => "first-order lattice",
            SequenceRule::Sobol => "sobol",
        }
    }
}

/// The unit-cube set carried into a design space by each law's own map (the rule of a
/// randomised set), kept here under its former path.
pub use crate::design::mapped;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cubature::Rule;

    fn space(items: &[&str]) -> DesignSpace {
        DesignSpace::parse("--var", items).unwrap()
    }

    #[test]
    fn the_rule_follows_the_randomisation_asked_for() {
        let s = space(&["x=normal(0,1)", "k=int(1,3)"]);
        assert_eq!(rule_by_law(&s, None, true), CubeRule::Dealt);
        for kind in [Randomize::Cells, Randomize::Shift] {
            let rule = rule_by_law(&s, Some(kind), true);
            assert_eq!(rule, CubeRule::Randomized(kind));
            assert!(rule.unbiased() && rule.construction().is_none());
        }
        // The recommended randomisation: the lattice made for the laws where every law
        // is unbounded, the cube's tent lattice where one variable is bounded or discrete.
        assert_eq!(
            rule_by_law(&s, Some(Randomize::Tent), true),
            CubeRule::Randomized(Randomize::Tent)
        );
        for laws in [
            &["x=normal(0,1)", "y=lognormal(0,0.5)"][..],
            &["z=normal(2,3)"][..],
        ] {
            let unbounded = space(laws);
            assert_eq!(
                rule_by_law(&unbounded, Some(Randomize::Tent), true),
                CubeRule::LawLattice
            );
            // Without a randomisation: the picked lattice for the default set of two or
            // more variables, the dealt set for one variable or a set the request chose.
            let picked = if laws.len() >= 2 {
                CubeRule::PickedLattice
            } else {
                CubeRule::Dealt
            };
            assert_eq!(rule_by_law(&unbounded, None, true), picked);
            assert_eq!(rule_by_law(&unbounded, None, false), CubeRule::Dealt);
            assert_eq!(
                rule_by_law(&unbounded, Some(Randomize::Shift), true),
                CubeRule::Randomized(Randomize::Shift)
            );
        }
        // A Brownian path, of any construction and beside any other law, takes the
        // scrambled net under the tent randomisation (and only under it).
        for laws in [
            &["W=brownian(1,8,pca)"][..],
            &["W=brownian(1,8,bridge)"][..],
            &["W=brownian(2,4,standard)", "u=uniform(0,1)", "k=int(1,3)"][..],
        ] {
            let path = space(laws);
            assert_eq!(
                rule_by_law(&path, Some(Randomize::Tent), true),
                CubeRule::ScrambledSobol,
                "{laws:?}"
            );
            assert_eq!(rule_by_law(&path, None, true), CubeRule::Dealt);
            assert_eq!(
                rule_by_law(&path, Some(Randomize::Cells), true),
                CubeRule::Randomized(Randomize::Cells)
            );
        }
        let mixed = space(&["x=normal(0,1)", "u=uniform(0,1)"]);
        assert_eq!(
            rule_by_law(&mixed, Some(Randomize::Tent), true),
            CubeRule::Randomized(Randomize::Tent)
        );
        let bounded = space(&["x=uniform(0,2)", "b=beta(2,3)", "k=int(1,3)"]);
        assert_eq!(
            rule_by_law(&bounded, Some(Randomize::Tent), true),
            CubeRule::Randomized(Randomize::Tent)
        );
        assert_eq!(rule_by_law(&bounded, None, true), CubeRule::Dealt);
        assert_eq!(s.unbounded(), vec![true, false]);
        assert!(CubeRule::LawLattice.unbiased() && CubeRule::LawLattice.construction().is_none());
        assert!(!CubeRule::Dealt.unbiased() && !CubeRule::PickedLattice.unbiased());
        let mut correlated = space(&["x=normal(0,1)", "y=normal(0,1)"]);
        assert_eq!(
            rule_by_law(&correlated, None, true),
            CubeRule::PickedLattice
        );
        correlated
            .correlate("--correlation", "1,0.5;0.5,1", vec![1.0, 0.5, 0.5, 1.0])
            .unwrap();
        assert_eq!(rule_by_law(&correlated, None, true), CubeRule::Dealt);
        assert_eq!(
            CubeRule::ScrambledSobol.construction(),
            Some(Baseline::Sobol)
        );
        let phrases: std::collections::HashSet<_> =
            CubeRule::ALL.iter().map(|r| r.phrase()).collect();
        assert_eq!(phrases.len(), CubeRule::ALL.len());
        assert!(CubeRule::ALL.iter().all(|r| !r.phrase().contains('\n')));
    }

    /// Two paths of three steps beside a normal: the net's columns go to x, then each
    /// path's first step, then each one's second and third.
    #[test]
    fn the_net_deals_its_leading_columns_to_the_paths_leading_steps() {
        let s = space(&[
            "A=brownian(1,3,pca)",
            "x=normal(0,1)",
            "B=brownian(1,3,bridge)",
        ]);
        let row: Vec<f64> = (0..7).map(|i| (i as f64 + 0.5) / 8.0).collect();
        let unit = PointSet::new(1, 7, row.clone()).unwrap();
        let dealt = leading_first(&s, &unit).unwrap();
        // Coordinates: A_1 A_2 A_3 x B_1 B_2 B_3; the order x, A_1, B_1, A_2, B_2, A_3, B_3.
        let want = [row[1], row[3], row[5], row[0], row[2], row[4], row[6]];
        assert_eq!(dealt.point(0), &want[..]);
        let d = CubeRule::ScrambledSobol
            .design(&s, &unit, 0, Finish::Nothing)
            .unwrap();
        assert_eq!(d.unit, dealt);
        let one = space(&["W=brownian(1,4,pca)"]);
        let u4 = PointSet::new(1, 4, row[..4].to_vec()).unwrap();
        assert_eq!(leading_first(&one, &u4).unwrap(), u4);
    }

    /// A sequence under a space: Owen's net dealt as the set's rule deals it where a path
    /// is held, the first-order lattice in the space's own order elsewhere.
    #[test]
    fn a_sequence_takes_the_net_under_a_path_and_the_first_order_lattice_elsewhere() {
        let two = space(&[
            "A=brownian(1,3,pca)",
            "x=normal(0,1)",
            "B=brownian(1,3,bridge)",
        ]);
        let (rule, order) = sequence_rule(&two);
        assert_eq!(rule, SequenceRule::Sobol);
        assert_eq!(order, leading_order(&two));
        assert_eq!(order, vec![3, 0, 4, 1, 5, 2, 6]);
        for laws in [
            &["x=normal(0,1)", "u=uniform(0,1)", "k=int(1,3)"][..],
            &["x=normal(0,1)", "y=lognormal(0,1)"][..],
        ] {
            let (rule, order) = sequence_rule(&space(laws));
            assert_eq!(rule, SequenceRule::FirstOrderLattice);
            assert_eq!(order, (0..laws.len()).collect::<Vec<_>>());
        }
        assert_eq!(SequenceRule::Sobol.as_str(), Rule::Sobol.as_str());
        assert_eq!(
            SequenceRule::FirstOrderLattice.as_str(),
            Rule::FirstOrderLattice.as_str()
        );
    }

    #[test]
    fn levels_are_the_floor_of_u_times_l_and_values_the_quantiles() {
        let s = space(&["x=normal(2,3)", "k=int(-1,2)", "c={a,b,c}"]);
        let u = [
            0.0,
            0.0,
            0.0,
            0.3,
            0.25,
            0.34,
            0.9,
            0.99,
            2.0 / 3.0,
            0.5,
            1.0,
            1.0,
        ];
        let unit = PointSet::new(4, 3, u.to_vec()).unwrap();
        let d = mapped(&s, &unit).unwrap();
        // ⌊u·L⌋ with L = 4 and 3, a coordinate of 1 in the last level.
        assert_eq!(d.levels[1], vec![0, 1, 3, 3]);
        assert_eq!(d.levels[2], vec![0, 1, 2, 2]);
        let x = crate::design::Marginal::Normal {
            mu: 2.0,
            sigma: 3.0,
        };
        match &d.columns()[0] {
            crate::design::Column::Real(v) => {
                for (i, &xi) in v.iter().enumerate() {
                    assert_eq!(xi.to_bits(), x.ppf(u[3 * i]).to_bits());
                }
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(d.unit, unit);
        let e = mapped(&s, &PointSet::new(1, 2, vec![0.1, 0.2]).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("2-dimensional"), "{e}");
    }
}
