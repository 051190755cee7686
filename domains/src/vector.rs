//! Which vector instructions the integer and quantile kernels with vector builds use
//! (the scramble of the Sobol' points, Φ⁻¹ of a column), decided once per process. Every
//! build gives the same bits; the environment variable `STILLPOINT_PORTABLE=1` asks for
//! the portable one, so the builds can be compared and timed on one machine.

use std::sync::OnceLock;

/// A kernel build: the widest the processor runs, or the portable one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VectorBuild {
    /// AVX-512 F and DQ (eight 64-bit lanes, 64-bit lane multiplies).
    Avx512,
    /// AVX2 (four 64-bit lanes, 64-bit multiplies built from 32-bit ones).
    Avx2,
    /// No vector instructions asked of the compiler.
    Portable,
}

/// The build the kernels run: [`VectorBuild::Portable`] when `STILLPOINT_PORTABLE` is
/// set to anything but empty or 0 (read once) or the processor is not x86-64, else the
/// widest of AVX-512 (F and DQ) and AVX2 it has.
pub fn vector_build() -> VectorBuild {
    static BUILD: OnceLock<VectorBuild> = OnceLock::new();
    *BUILD.get_or_init(|| {
        let portable =
            std::env::var("STILLPOINT_PORTABLE").is_ok_and(|v| !v.is_empty() && v != "0");
        #[cfg(target_arch = "x86_64")]
        {
            if portable {
                VectorBuild::Portable
            } else if is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512dq") {
                VectorBuild::Avx512
            } else if is_x86_feature_detected!("avx2") {
                VectorBuild::Avx2
            } else {
                VectorBuild::Portable
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = portable;
            VectorBuild::Portable
        }
    })
}
