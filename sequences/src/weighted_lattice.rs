//! Rank-1 lattices made for one n with a product weight per coordinate: the
//! component-by-component search of [`super::tent_lattice_generator`] where coordinate j
//! enters the criterion as 1 + γ_j ω(x) rather than with one weight for all. A Brownian
//! path built by its principal components or by the bridge puts most of its variance on
//! its leading normals, so a payoff of the path is nearly a function of those few: weights
//! that decay as the construction's variances make the search spend its freedom on the
//! projections of the leading coordinates.

use super::fast_cbc::FastCbc;
use super::lattices::{extend_terms, generators, pick, rough_terms, tent_terms, RoughTieBreak};
use crate::Error;

/// The one-dimensional kernel a weighted lattice is scored with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeKernel {
    /// Σ_{h≠0} e^{2πihx}/h⁴: smoothness 2, the shift-and-tent criterion of
    /// [`super::tent_criterion`].
    Tent,
    /// Σ_{h≠0} e^{2πihx}/h² = 2π²B2(x): smoothness 1, the shifted lattice's criterion
    /// (the kernel of [`super::law_lattice_generator`]'s unbounded coordinates).
    FirstOrder,
}

impl LatticeKernel {
    /// γ·ω(r/n) for r = 0..n−1.
    fn terms(self, n: usize, gamma: f64) -> Vec<f64> {
        match self {
            LatticeKernel::Tent => tent_terms(n, gamma),
            LatticeKernel::FirstOrder => rough_terms(n, gamma),
        }
    }
}

/// The weighted criterion −1 + (1/n) Σ_k Π_j (1 + γ_j ω(frac(k z_j / n))): the squared
/// worst-case error, averaged over the shift, of the shifted lattice (with the tent for
/// [`LatticeKernel::Tent`]) in the weighted space of the kernel.
///
/// Refuses n = 0, an empty z, weights of another length than z, or a weight that is not
/// finite and positive, naming the argument.
pub fn weighted_criterion(
    n: usize,
    z: &[u64],
    weights: &[f64],
    kernel: LatticeKernel,
) -> Result<f64, Error> {
    check(n, z.len(), weights)?;
    let mut q = vec![0.0f64; n];
    for (&zj, &g) in z.iter().zip(weights) {
        extend_terms(&mut q, &kernel.terms(n, g), zj);
    }
    Ok(q.iter().sum::<f64>() / n as f64)
}

/// The generating vector of an n-point rank-1 lattice for product weights γ_j: z_1 = 1,
/// then each z_j the unit 1 ≤ z_j ≤ n/2 that makes [`weighted_criterion`] of
/// (z_1, …, z_j) smallest, by the component-by-component search of the lattice made for
/// the laws (the first-order criterion breaks the smoothness-2 scores' ties).
///
/// Refuses n = 0, no weights, or a weight that is not finite and positive, naming the
/// argument.
pub fn weighted_lattice_generator(
    n: usize,
    weights: &[f64],
    kernel: LatticeKernel,
) -> Result<Vec<u64>, Error> {
    check(n, weights.len(), weights)?;
    let coords: Vec<(LatticeKernel, f64)> = weights.iter().map(|&g| (kernel, g)).collect();
    Ok(cbc_generator(n, &coords))
}

/// The component-by-component search every lattice made for one n shares: coordinate j
/// enters the criterion as 1 + γ_j ω_j(x) with its own kernel and weight
/// (`coords[j]`); z_1 = 1, then each z_j the unit 1 ≤ z_j ≤ n/2 whose criterion is
/// smallest, every candidate scored at once by the fast construction (Nuyens and Cools
/// 2006). Candidates within the transforms' rounding of the best are told apart by the
/// first-order criterion ([`RoughTieBreak`]; the smoothness-2 scores stop resolving them
/// above a few 10⁴ points), then the smallest wins. A weight only scales its
/// coordinate's scores, so one set of transforms per kernel serves every weight: each
/// kernel's is made at the weight of the first coordinate that needs it.
///
/// The caller has checked n ≥ 1, at least one coordinate and positive weights.
pub(super) fn cbc_generator(n: usize, coords: &[(LatticeKernel, f64)]) -> Vec<u64> {
    let n64 = n as u64;
    let candidates = generators(n64);
    if coords.len() == 1 || candidates.len() <= 1 {
        return vec![1 % n64; coords.len()];
    }
    // One planner per kernel the coordinates after the first need (each is O(n) memory
    // and one set of transforms).
    let plan = |kernel: LatticeKernel| {
        coords[1..]
            .iter()
            .find(|c| c.0 == kernel)
            .map(|&(k, g)| FastCbc::new(&k.terms(n, g), &candidates))
    };
    let (tent_plan, first_plan) = (plan(LatticeKernel::Tent), plan(LatticeKernel::FirstOrder));
    let mut terms: Vec<((LatticeKernel, u64), Vec<f64>)> = Vec::new();
    let mut q = vec![0.0f64; n];
    let mut z: Vec<u64> = Vec::with_capacity(coords.len());
    let mut ties: Option<RoughTieBreak> = None;
    for (j, &(kernel, g)) in coords.iter().enumerate() {
        let zj = if j == 0 {
            1
        } else {
            let fast = match kernel {
                LatticeKernel::Tent => &tent_plan,
                LatticeKernel::FirstOrder => &first_plan,
            };
            let (scores, rounding) = fast.as_ref().expect("planned for this kernel").scores(&q);
            let ties = ties.get_or_insert_with(|| RoughTieBreak::new(n, &candidates, &z));
            pick(&candidates, &scores, rounding, || ties.scores())
        };
        let key = (kernel, g.to_bits());
        let at = match terms.iter().position(|(k, _)| *k == key) {
            Some(at) => at,
            None => {
                terms.push((key, kernel.terms(n, g)));
                terms.len() - 1
            }
        };
        extend_terms(&mut q, &terms[at].1, zj);
        if let Some(t) = ties.as_mut() {
            t.extend(zj);
        }
        z.push(zj);
    }
    z
}

fn check(n: usize, s: usize, weights: &[f64]) -> Result<(), Error> {
    super::check_shape(n, s)?;
    if weights.len() != s {
        return Err(Error::invalid(
            "weights",
            weights.len(),
            format!("one weight per coordinate ({s})"),
        ));
    }
    if let Some(g) = weights.iter().find(|g| !(g.is_finite() && **g > 0.0)) {
        return Err(Error::invalid("weights", g, "finite and positive weights"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The criterion by its definition: the mean over the points of
    /// Π_j (1 + γ_j ω(frac(k z_j / n))) − 1, with ω from the Bernoulli polynomials.
    fn direct(n: usize, z: &[u64], w: &[f64], kernel: LatticeKernel) -> f64 {
        let pi = std::f64::consts::PI;
        let omega = |x: f64| match kernel {
            LatticeKernel::Tent => {
                -(2.0 * pi).powi(4) / 24.0 * (x.powi(4) - 2.0 * x.powi(3) + x * x - 1.0 / 30.0)
            }
            LatticeKernel::FirstOrder => 2.0 * pi * pi * (x * x - x + 1.0 / 6.0),
        };
        let mut sum = 0.0;
        for k in 0..n {
            let mut p = 1.0;
            for (&zj, &g) in z.iter().zip(w) {
                p *= 1.0 + g * omega(((k as u64 * zj) % n as u64) as f64 / n as f64);
            }
            sum += p;
        }
        sum / n as f64 - 1.0
    }

    #[test]
    fn criterion_is_the_direct_formula() {
        let (z, w) = ([1u64, 7, 11, 5], [1.0, 0.5, 0.1, 0.02]);
        for kernel in [LatticeKernel::Tent, LatticeKernel::FirstOrder] {
            let got = weighted_criterion(31, &z, &w, kernel).unwrap();
            let want = direct(31, &z, &w, kernel);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs(),
                "{kernel:?}: {got} {want}"
            );
        }
    }

    #[test]
    fn each_coordinate_is_the_best_given_the_earlier_ones() {
        // The fast scores pick what trying every unit one by one picks, at an odd
        // non-prime and a power of two.
        let w = [1.0, 0.6, 0.3, 0.15, 0.08];
        for n in [45usize, 64] {
            for kernel in [LatticeKernel::Tent, LatticeKernel::FirstOrder] {
                let z = weighted_lattice_generator(n, &w, kernel).unwrap();
                assert_eq!(z[0], 1);
                for j in 1..w.len() {
                    let crit = |c: u64| {
                        let mut t = z[..j].to_vec();
                        t.push(c);
                        direct(n, &t, &w[..=j], kernel)
                    };
                    let best = generators(n as u64)
                        .into_iter()
                        .map(crit)
                        .fold(f64::INFINITY, f64::min);
                    assert!(crit(z[j]) <= best * (1.0 + 1e-9), "n {n} {kernel:?} j {j}");
                }
            }
        }
    }

    #[test]
    fn weights_steer_the_search() {
        // With the weight on the first two coordinates, their pair is the best pair
        // there is; with the weight on the third instead, the pair (1, z_3) is.
        let n = 101;
        let front = weighted_lattice_generator(n, &[1.0, 1.0, 1e-6], LatticeKernel::Tent).unwrap();
        let back = weighted_lattice_generator(n, &[1.0, 1e-6, 1.0], LatticeKernel::Tent).unwrap();
        let pair = |a: u64| direct(n, &[1, a], &[1.0, 1.0], LatticeKernel::Tent);
        let best = generators(n as u64)
            .into_iter()
            .map(pair)
            .fold(f64::INFINITY, f64::min);
        assert!(pair(front[1]) <= best * (1.0 + 1e-9));
        assert!(pair(back[2]) <= best * (1.0 + 1e-9));
    }

    #[test]
    fn refuses_bad_weights_naming_them() {
        for w in [vec![1.0, 0.0], vec![1.0, f64::NAN], vec![1.0, -1.0]] {
            match weighted_lattice_generator(16, &w, LatticeKernel::Tent) {
                Err(Error::InvalidArgument { name, .. }) => assert_eq!(name, "weights"),
                other => panic!("expected an error naming the weights, got {other:?}"),
            }
        }
        match weighted_criterion(16, &[1, 3], &[1.0], LatticeKernel::Tent) {
            Err(Error::InvalidArgument { name, .. }) => assert_eq!(name, "weights"),
            other => panic!("expected an error naming the weights, got {other:?}"),
        }
        assert!(weighted_lattice_generator(0, &[1.0], LatticeKernel::Tent).is_err());
    }
}
