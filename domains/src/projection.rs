//! Small vector helpers and the Euclidean projection onto an intersection of half-spaces.
//!
//! Shared by [`crate::region`] (which projects onto the linear pieces of an implicit
//! region) and [`crate::shapes`] (the polytope's own projection), so that both depend on
//! this module and neither on the other for it.

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(crate) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Scales v to unit length; false (v untouched) when its length is zero or not finite.
pub(crate) fn normalise(v: &mut [f64]) -> bool {
    let n = norm(v);
    if n > 0.0 && n.is_finite() {
        v.iter_mut().for_each(|x| *x /= n);
        true
    } else {
        false
    }
}

/// Euclidean projection of x onto {y : n_i·y ≤ c_i − δ} (unit normals `normals`, row per
/// constraint, offsets c) by the dual active-set method of Goldfarb and Idnani (1983)
/// with the identity Hessian: start from the unconstrained minimum y = x, add the most
/// violated constraint, and take primal and dual steps that drop constraints whose
/// multiplier would turn negative. It ends in finitely many steps at the exact projection
/// (to rounding), or proves the set empty (`None`). `scale` is the length scale of the
/// set (its box diameter), for tolerances.
pub(crate) fn project_halfspaces(
    normals: &[f64],
    offsets: &[f64],
    x: &[f64],
    delta: f64,
    scale: f64,
) -> Option<Vec<f64>> {
    let s = x.len();
    let m = offsets.len();
    let normal = |i: usize| &normals[i * s..(i + 1) * s];
    let tol = 1e-13 * scale.max(1.0);
    let mut y = x.to_vec();
    let mut active: Vec<usize> = Vec::with_capacity(s);
    let mut mult: Vec<f64> = Vec::with_capacity(s);
    let mut q = vec![0.0; s * s];
    let mut r = vec![0.0; s * s];
    let mut z = vec![0.0; s];
    let mut rv = vec![0.0; s];
    let slack = |y: &[f64], i: usize| offsets[i] - delta - dot(normal(i), y);
    let max_iter = 20 * (m + s) + 100;
    let mut iter = 0;
    loop {
        // Most violated constraint.
        let mut worst = (-tol, usize::MAX);
        for i in 0..m {
            if active.contains(&i) {
                continue;
            }
            let sl = slack(&y, i);
            if sl < worst.0 {
                worst = (sl, i);
            }
        }
        let p = worst.1;
        if p == usize::MAX {
            return Some(y);
        }
        let mut u_p = 0.0;
        loop {
            iter += 1;
            if iter > max_iter {
                // Cycling on a degenerate vertex: keep the point only if it is feasible
                // to well within the scale of the set.
                return (0..m).all(|i| slack(&y, i) >= -1e-9 * scale).then_some(y);
            }
            let qa = active.len();
            qr(normals, s, &active, &mut q, &mut r);
            // GI's constraints are c·y ≥ d with c = −n_p: z is the primal direction (c
            // projected off the active normals), rv the dual one (R⁻¹ Qᵀ c).
            let np = normal(p);
            for k in 0..s {
                z[k] = -np[k];
            }
            for j in 0..qa {
                let col = &q[j * s..(j + 1) * s];
                let c = -dot(col, np);
                rv[j] = c;
                for k in 0..s {
                    z[k] -= c * col[k];
                }
            }
            for j in (0..qa).rev() {
                let mut v = rv[j];
                for l in j + 1..qa {
                    v -= r[j * s + l] * rv[l];
                }
                rv[j] = v / r[j * s + j];
            }
            let mut t1 = f64::INFINITY;
            let mut drop = usize::MAX;
            for j in 0..qa {
                if rv[j] > 0.0 {
                    let t = mult[j] / rv[j];
                    if t < t1 {
                        t1 = t;
                        drop = j;
                    }
                }
            }
            let zz = dot(&z, &z);
            let t2 = if zz > 1e-24 {
                // slack_p(y + t z) = slack_p(y) + t |z|², zero at t2.
                -slack(&y, p) / zz
            } else {
                f64::INFINITY
            };
            if t1.is_infinite() && t2.is_infinite() {
                return None;
            }
            if t2.is_infinite() {
                for j in 0..qa {
                    mult[j] -= t1 * rv[j];
                }
                u_p += t1;
                active.remove(drop);
                mult.remove(drop);
                continue;
            }
            let t = t1.min(t2);
            for k in 0..s {
                y[k] += t * z[k];
            }
            for j in 0..qa {
                mult[j] -= t * rv[j];
            }
            u_p += t;
            if t2 <= t1 {
                active.push(p);
                mult.push(u_p);
                break;
            }
            active.remove(drop);
            mult.remove(drop);
        }
    }
}

/// Modified Gram–Schmidt QR of the active normals, each negated (GI's c = −n): q holds
/// orthonormal columns (row j = column j), r the upper triangle, both s × s.
fn qr(normals: &[f64], s: usize, active: &[usize], q: &mut [f64], r: &mut [f64]) {
    for (j, &i) in active.iter().enumerate() {
        let (done, rest) = q.split_at_mut(j * s);
        let col = &mut rest[..s];
        for (k, v) in col.iter_mut().enumerate() {
            *v = -normals[i * s + k];
        }
        for l in 0..j {
            let ql = &done[l * s..(l + 1) * s];
            let c = dot(ql, col);
            r[l * s + j] = c;
            for k in 0..s {
                col[k] -= c * ql[k];
            }
        }
        let n = dot(col, col).sqrt();
        r[j * s + j] = n;
        if n > 0.0 {
            col.iter_mut().for_each(|v| *v /= n);
        }
    }
}
