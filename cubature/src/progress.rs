//! The progress line every front end prints after a round of an integration or a
//! sensitivity analysis (the command line's `stillpoint:` lines, Python's `progress=True`),
//! written once: evaluations so far, where the widest interval stands against its target,
//! and the seconds since the start, numbers as C's `%e` writes them.

use super::Cubature;

impl Cubature {
    /// `{prefix}: n=4096  estimate=1.23457e+00  half-width=3.1e-04 (target 1.2e-04)  2.3 s`:
    /// the target is max(abs_tol, rel_tol·|estimate|); with several outputs, the one
    /// furthest from its target, named `(output j)`.
    pub fn progress_line(&self, prefix: &str, seconds: f64) -> String {
        let (estimate, half_width, targets) = (self.estimate(), self.half_width(), self.targets());
        let behind = |j: usize| match (targets[j] > 0.0, half_width[j] > 0.0) {
            (true, _) => half_width[j] / targets[j],
            (false, true) => f64::INFINITY,
            (false, false) => 0.0,
        };
        // The first of the furthest behind.
        let Some(j) = (0..estimate.len()).reduce(|a, b| if behind(b) > behind(a) { b } else { a })
        else {
            // Before the rule's first round (after a face test): the rule it chose.
            return format!(
                "{prefix}: n={}  rule: {}",
                self.n(),
                self.options.rule.as_str()
            );
        };
        let which = if estimate.len() > 1 {
            format!("  (output {j})")
        } else {
            String::new()
        };
        format!(
            "{prefix}: n={}  estimate={}  half-width={} (target {}){which}  {seconds:.1} s",
            self.n(),
            sci(estimate[j], 5),
            sci(half_width[j], 1),
            sci(targets[j], 1)
        )
    }
}

/// `x` in scientific notation with `digits` decimals and a signed two-digit exponent, as
/// C's `%e` writes it (`1.23457e+00`, `3.1e-04`).
pub(crate) fn sci(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$e}");
    match s.split_once('e') {
        Some((mantissa, exp)) if x.is_finite() => {
            let exp: i32 = exp.parse().unwrap_or(0);
            let sign = if exp < 0 { '-' } else { '+' };
            format!("{mantissa}e{sign}{:02}", exp.abs())
        }
        _ => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sci_writes_as_c_does() {
        assert_eq!(sci(1.234567, 5), "1.23457e+00");
        assert_eq!(sci(3.14e-4, 1), "3.1e-04");
        assert_eq!(sci(-2.5e12, 1), "-2.5e+12");
        assert_eq!(sci(0.0, 1), "0.0e+00");
        assert_eq!(sci(1e-300, 1), "1.0e-300");
    }

    #[test]
    fn the_line_names_the_output_furthest_from_its_target() {
        let mut c = Cubature::new(1, super::super::QuadOptions::default()).unwrap();
        let p = c.next_points().unwrap();
        // Output 0 constant (met), output 1 varying: output 1 is named.
        let v: Vec<f64> = p.rows().flat_map(|x| [1.0, x[0]]).collect();
        c.feed(&p, &v).unwrap();
        let line = c.progress_line("quad", 1.25);
        assert!(line.starts_with("quad: n=256  estimate=5."), "{line}");
        assert!(line.ends_with("  (output 1)  1.2 s"), "{line}");
    }
}
