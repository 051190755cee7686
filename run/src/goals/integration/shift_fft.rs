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

use rayon::prelude::*;
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

/// Frequencies per task of the passes over them that run on all threads: each pass visits
/// the sums at F = G z mod n, scattered over n·32 bytes (6.4 MB at 2·10⁵ points), so it
/// waits on memory, and two threads wait on it together; a chunk starts at its own G
/// (one multiplication) and steps from there like the whole pass.
const CHUNK: usize = 1 << 13;

/// g·step mod m without overflow.
fn mul_mod(g: usize, step: usize, m: usize) -> usize {
    (g as u128 * step as u128 % m as u128) as usize
}

/// The frequencies F = G z mod n for G = `from`, `from` + 1, …: a step and a subtraction
/// each, no division.
fn frequencies(from: usize, step: usize, n: usize) -> impl Iterator<Item = usize> {
    std::iter::successors(Some(mul_mod(from, step, n)), move |&f| {
        let next = f + step;
        Some(if next >= n { next - n } else { next })
    })
}

/// The sums of an [`Accumulator`], written through a pointer by the chunks of
/// [`Accumulator::push`], each at frequencies no other chunk visits.
struct Scatter(*mut Sums);

// SAFETY: shared only by `push`, whose chunks write disjoint elements (see there).
unsafe impl Sync for Scatter {}

impl Scatter {
    /// The sums at frequency f.
    ///
    /// SAFETY: f < n, and no other reference to element f is alive while this one is.
    #[allow(clippy::mut_from_ref)]
    unsafe fn at(&self, f: usize) -> &mut Sums {
        &mut *self.0.add(f)
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
    ///
    /// Where z is prime to n, G ↦ G z mod n visits every F once, so the chunks of G write
    /// disjoint sums and run on all threads; each term is kept and they are added in the
    /// order of G, as [`Accumulator::push_in_order`] adds them: the same bits.
    pub(crate) fn push(&mut self, z: u64, q: u64) {
        let sp = self.spectrum;
        let n = sp.n;
        let step = (z % n as u64) as usize;
        if n <= CHUNK || gcd(step, n) != 1 {
            return self.push_in_order(z, q);
        }
        let turn = (q % (2 * n as u64)) as usize;
        let mut terms = vec![0.0; n];
        let sums = Scatter(self.sums.as_mut_ptr());
        terms
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, chunk)| {
                let from = c * CHUNK;
                let angles = std::iter::successors(Some(mul_mod(from, turn, 2 * n)), |&a| {
                    let next = a + turn;
                    Some(if next >= 2 * n { next - 2 * n } else { next })
                });
                let at = frequencies(from, step, n).zip(angles);
                for ((t, g), (f, angle)) in chunk.iter_mut().zip(from..).zip(at) {
                    let s_hat = sp.phase[angle] * sp.b[g];
                    // SAFETY: f < n, and G ↦ G z mod n is one to one (z prime to n), so
                    // no other G of this or another chunk reaches f.
                    let at = unsafe { sums.at(f) };
                    if g != 0 {
                        *t = (sp.a[g] * at.a + (s_hat * at.s.conj()).re).max(0.0);
                    }
                    at.a += sp.a[g];
                    at.s += s_hat;
                }
            });
        let pairs = terms[1..].iter().fold(0.0, |sum, &t| sum + t);
        let zero = sp.a[0] + sp.b[0];
        self.pairs += pairs + self.count as f64 * zero * zero;
        self.count += 1;
    }

    /// [`Accumulator::push`] on one thread, G by G.
    fn push_in_order(&mut self, z: u64, q: u64) {
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

    /// c_G = B(G) conj P̂(G z) for G = 1..n − 1 (c_0 = 0: the same for every shift),
    /// each times e^{πiG/n} where `phased`; chunks of G on all threads.
    fn coefficients(&self, z: u64, phased: bool) -> Vec<Complex64> {
        let sp = self.spectrum;
        let n = sp.n;
        let step = (z % n as u64) as usize;
        let mut c = vec![Complex64::new(0.0, 0.0); n];
        c.par_chunks_mut(CHUNK).enumerate().for_each(|(k, chunk)| {
            let from = k * CHUNK;
            for ((cg, g), f) in chunk.iter_mut().zip(from..).zip(frequencies(from, step, n)) {
                if g != 0 {
                    *cg = self.sums[f].s.conj() * sp.b[g];
                    if phased {
                        *cg *= sp.phase[g];
                    }
                }
            }
        });
        c
    }

    /// The part of the criterion (× 4n⁸/γ²) that depends on the next coordinate's
    /// shift, for every odd q = 2p + 1, p = 0..n − 1, by one FFT (q + 2n scores as q).
    pub(crate) fn scores(&self, z: u64) -> Vec<f64> {
        let sp = self.spectrum;
        let mut c = self.coefficients(z, true);
        sp.fft.process(&mut c);
        c.into_iter().map(|v| v.re).collect()
    }

    /// [`Accumulator::scores`] at one numerator q, term by term in O(n): the plain loop
    /// the FFT replaces.
    #[cfg(test)]
    pub(crate) fn score(&self, z: u64, q: u64) -> f64 {
        let sp = self.spectrum;
        self.coefficients(z, false)
            .iter()
            .enumerate()
            .map(|(g, cg)| (cg * sp.phase_of(g, q)).re)
            .sum()
    }
}

/// The greatest common divisor.
fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_passes_on_all_threads_are_the_one_thread_passes_to_the_bit() {
        // Sizes of one chunk and a bit, several chunks and a ragged end (each composite);
        // generators prime to n (the chunks' path) and one sharing a factor with it (one
        // thread, G by G).
        for n in [CHUNK + 1, 3 * CHUNK + 18, 40_000] {
            let spectrum = Spectrum::new(n);
            let (mut chunked, mut in_order) =
                (Accumulator::new(&spectrum), Accumulator::new(&spectrum));
            let mut zs: Vec<u64> = [1u64, 7919, 104_729, 3 * CHUNK as u64 + 1]
                .into_iter()
                .filter(|&z| gcd(z as usize % n, n) == 1)
                .collect();
            let shared = (2..n).find(|&d| n.is_multiple_of(d)).unwrap() as u64;
            zs.push(shared);
            for (j, &z) in zs.iter().enumerate() {
                if j > 0 {
                    // The coefficients, chunk by chunk, against G·z mod n formed directly.
                    let c = chunked.coefficients(z, false);
                    for (g, cg) in c.iter().enumerate().skip(1) {
                        let f = (g as u64 * z % n as u64) as usize;
                        let want = chunked.sums[f].s.conj() * spectrum.b[g];
                        assert_eq!(
                            (cg.re.to_bits(), cg.im.to_bits()),
                            (want.re.to_bits(), want.im.to_bits())
                        );
                    }
                }
                let q = 2 * (z * 31 % (2 * n as u64)) + 1;
                chunked.push(z, q);
                in_order.push_in_order(z, q);
                assert_eq!(
                    chunked.pairs.to_bits(),
                    in_order.pairs.to_bits(),
                    "n = {n}, z = {z}"
                );
                for (x, y) in chunked.sums.iter().zip(&in_order.sums) {
                    assert_eq!(
                        [x.a, x.s.re, x.s.im].map(f64::to_bits),
                        [y.a, y.s.re, y.s.im].map(f64::to_bits)
                    );
                }
            }
            assert!(chunked.pairs > 0.0);
        }
    }
}
