//! The shift criterion of [`super::lattice`] in the frequency domain: computed as a sum
//! of non-negative terms (never negative, accurate to a small relative error at any n),
//! and for every shift of a coordinate at once by one FFT of length n.
//!
//! Why the frequency domain. In the point domain the order-two criterion is a sum of
//! kernel values of order one that cancel down to O(n⁻⁴): at 20 001 points rounding
//! noise was as large as the value, which came out negative. Over the lattice's
//! frequencies every part is a product of positive weights, or bounded by one.
//!
//! The algebra. With y_kj = frac(k z_j/n + q_j/(4n)) and x = φ(y) the tent transform,
//! cos(πh x) = cos(2πh y), so with C_j(h) = (1/n) Σ_k e^{2πih y_kj} the pair sums of
//! ψ(x, x') = Σ_{h≥1} 2 cos(πhx) cos(πhx')/h⁴ are, for F = h z_j mod n:
//!
//! - order one: (1/n²) Σ_{k,k'} ψ = π⁴/(720 n⁴) for every coordinate (only h ≡ 0 mod 2n
//!   survive, each column being the n midpoints);
//! - order two, coordinates j < l: (1/n²) Σ_{k,k'} ψ_j ψ_l = ¼ Σ_F [A_j(F) A_l(F) +
//!   Re(Ŝ_j(F) conj Ŝ_l(F))] + ¼ A(0) B(0)·2, where, with G = F z_j⁻¹ mod n,
//!   A_j(F) = Σ_{h ≡ G (n), h≠0} h⁻⁴ (the differences k − k', positive) and
//!   Ŝ_j(F) = e^{πiG q_j/n} B(G), B(G) = Σ_{h ≡ G (n), h≠0} (−1)^{(h−G)/n} h⁻⁴ (the sums
//!   k + k', shifted). Since |B| ≤ A, every F ≠ 0 gives a non-negative term, and F = 0
//!   with the cross terms gives ¼(A(0) + B(0))².
//!
//! In closed form, with x = G/n: n⁴A = π⁴ csc²(πx)(cot²(πx) + ⅓) and
//! n⁴B = (π⁴/6) csc(πx) cot(πx)(6 cot²(πx) + 5); n⁴A(0) = π⁴/45, n⁴B(0) = −7π⁴/360.
//!
//! The search. A candidate q for coordinate j meets the coordinates chosen before it
//! only through P̂(F) = Σ_{l<j} Ŝ_l(F), so the part of its criterion that depends on q
//! is Re Σ_{G≠0} B(G) conj P̂(G z_j) e^{πiGq/n}: at the odd q = 2p + 1 one DFT of
//! length n over G. Numerators q and q + 2n (the reflection x ↦ 1 − x) score the same.

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

/// The lattice's weights per residue G of the frequency mod n, scaled by n⁴, and the
/// phases e^{πik/n} a shift numerator contributes.
pub(crate) struct Spectrum {
    n: usize,
    /// n⁴ A(G): the differences' weight, positive.
    a: Vec<f64>,
    /// n⁴ B(G): the sums' weight, |B| ≤ A, odd about n/2.
    b: Vec<f64>,
    /// e^{πik/n} for k = 0..2n − 1.
    phase: Vec<Complex64>,
    fft: Arc<dyn Fft<f64>>,
}

impl Spectrum {
    pub(crate) fn new(n: usize) -> Self {
        let pi4 = PI.powi(4);
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        a[0] = pi4 / 45.0;
        b[0] = -7.0 * pi4 / 360.0;
        for g in 1..n {
            // x and 1 − x share csc² and cot²; B changes sign. Folding onto x ≤ ½ keeps
            // sin(πx) accurate to its last bits near x = 1.
            let folded = g.min(n - g);
            let x = PI * folded as f64 / n as f64;
            let (sin, cos) = x.sin_cos();
            let (csc, cot) = (1.0 / sin, cos / sin);
            a[g] = pi4 * csc * csc * (cot * cot + 1.0 / 3.0);
            b[g] = if 2 * g == n {
                0.0
            } else {
                let v = pi4 / 6.0 * csc * cot * (6.0 * cot * cot + 5.0);
                if g == folded {
                    v
                } else {
                    -v
                }
            };
        }
        let phase = (0..2 * n)
            .map(|k| Complex64::from_polar(1.0, PI * k as f64 / n as f64))
            .collect();
        let fft = FftPlanner::new().plan_fft_inverse(n.max(1));
        Spectrum {
            n,
            a,
            b,
            phase,
            fft,
        }
    }

    /// The number of points n.
    pub(crate) fn n(&self) -> usize {
        self.n
    }

    /// e^{πi G q/n}.
    #[cfg(test)]
    fn phase_of(&self, g: usize, q: u64) -> Complex64 {
        self.phase[((g as u64 * (q % (2 * self.n) as u64)) % (2 * self.n) as u64) as usize]
    }
}

/// Per frequency F, the sums over the coordinates added: kept together because a
/// coordinate visits the frequencies in the order G z mod n, far apart in memory, and
/// reads and writes both at each.
#[derive(Clone, Copy)]
struct Sums {
    /// Σ_l A_l(F).
    a: f64,
    /// P̂(F) = Σ_l Ŝ_l(F).
    s: Complex64,
}

/// The criterion of the coordinates added so far, and what a next one's search needs.
pub(crate) struct Accumulator<'a> {
    spectrum: &'a Spectrum,
    /// Per F, Σ_l A_l(F) and P̂(F) over the coordinates added.
    sums: Vec<Sums>,
    /// Coordinates added.
    count: usize,
    /// Σ over the pairs added of n⁸ × their order-two term (every part non-negative).
    pairs: f64,
}

impl<'a> Accumulator<'a> {
    pub(crate) fn new(spectrum: &'a Spectrum) -> Self {
        let n = spectrum.n;
        Accumulator {
            spectrum,
            sums: vec![
                Sums {
                    a: 0.0,
                    s: Complex64::new(0.0, 0.0),
                };
                n
            ],
            count: 0,
            pairs: 0.0,
        }
    }

    /// Adds coordinate (z, q): its pair terms with every coordinate added before.
    pub(crate) fn push(&mut self, z: u64, q: u64) {
        let sp = self.spectrum;
        let n = sp.n;
        let step = (z % n as u64) as usize;
        let mut pairs = 0.0;
        let mut f = 0usize;
        // G·q mod 2n, stepped.
        let (turn, mut angle) = ((q % (2 * n as u64)) as usize, 0usize);
        for g in 0..n {
            let s_hat = sp.phase[angle] * sp.b[g];
            angle += turn;
            if angle >= 2 * n {
                angle -= 2 * n;
            }
            let at = &mut self.sums[f];
            if g != 0 {
                let term = sp.a[g] * at.a + (s_hat * at.s.conj()).re;
                // Non-negative in exact arithmetic (|B| ≤ A): what rounding leaves below
                // zero is noise in a term that vanishes.
                pairs += term.max(0.0);
            }
            at.a += sp.a[g];
            at.s += s_hat;
            f += step;
            if f >= n {
                f -= n;
            }
        }
        let zero = sp.a[0] + sp.b[0];
        self.pairs += pairs + self.count as f64 * zero * zero;
        self.count += 1;
    }

    /// e²₂ of the coordinates added, with product weight `gamma`.
    pub(crate) fn value(&self, gamma: f64) -> f64 {
        let n4 = (self.spectrum.n as f64).powi(4);
        let first = gamma * self.count as f64 * PI.powi(4) / 720.0 / n4;
        first + gamma * gamma / 4.0 * (self.pairs / n4) / n4
    }

    /// c_G = B(G) conj P̂(G z) for G = 1..n − 1 (c_0 = 0: the same for every shift).
    fn coefficients(&self, z: u64) -> Vec<Complex64> {
        let sp = self.spectrum;
        let n = sp.n;
        let step = (z % n as u64) as usize;
        let mut c = vec![Complex64::new(0.0, 0.0); n];
        let mut f = 0usize;
        for (g, cg) in c.iter_mut().enumerate().skip(1) {
            f += step;
            if f >= n {
                f -= n;
            }
            *cg = self.sums[f].s.conj() * sp.b[g];
        }
        c
    }

    /// The part of the criterion (× 4n⁸/γ²) that depends on the next coordinate's
    /// shift, for every odd q = 2p + 1, p = 0..n − 1, by one FFT (q + 2n scores as q).
    pub(crate) fn scores(&self, z: u64) -> Vec<f64> {
        let sp = self.spectrum;
        let mut c = self.coefficients(z);
        for (g, cg) in c.iter_mut().enumerate() {
            *cg *= sp.phase[g];
        }
        sp.fft.process(&mut c);
        c.into_iter().map(|v| v.re).collect()
    }

    /// [`Accumulator::scores`] at one numerator q, term by term in O(n): the plain loop
    /// the FFT replaces.
    #[cfg(test)]
    pub(crate) fn score(&self, z: u64, q: u64) -> f64 {
        let sp = self.spectrum;
        self.coefficients(z)
            .iter()
            .enumerate()
            .map(|(g, cg)| (cg * sp.phase_of(g, q)).re)
            .sum()
    }
}

/// e²₂ of the shifted lattice with generator z and shift numerators q (module
/// documentation), with product weight `gamma`.
pub(crate) fn criterion(spectrum: &Spectrum, z: &[u64], q: &[u64], gamma: f64) -> f64 {
    let mut acc = Accumulator::new(spectrum);
    for (&zj, &qj) in z.iter().zip(q) {
        acc.push(zj, qj);
    }
    acc.value(gamma)
}
