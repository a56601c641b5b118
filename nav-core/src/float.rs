//! The square root of the flight code: IEEE 754 correctly rounded, so every implementation
//! gives the same bits, and the cheapest one the build allows is used.
//!
//! `libm::sqrt` (the default) is correctly rounded in software, dozens of instructions on the
//! Cortex-M7, and a star-update frame takes several square roots (docs/guide/performance.md). With
//! the `hardware-sqrt` feature on 32-bit ARM the FPU's `VSQRT.F64` computes it in one
//! instruction. IEEE 754
//! requires the square root to be correctly rounded, so both give the same bits for every
//! input in the default rounding mode (round to nearest, which the flight code never
//! changes); the host/target bit-for-bit replays check it over every square root of a
//! 300 s flight. `VSQRT.F64` needs a double-precision FPU (Cortex-M7 with FPv5-D16,
//! `-C target-cpu=cortex-m7`): on a core without one the build fails with an assembler
//! error rather than faulting in flight.

/// `√x`, correctly rounded (NaN for `x < 0`, `+∞` for `+∞`, `±0` for `±0`).
///
/// # Examples
/// ```
/// assert_eq!(nav_core::float::sqrt(2.25), 1.5);
/// assert!(nav_core::float::sqrt(-1.0).is_nan());
/// ```
#[cfg(not(all(feature = "hardware-sqrt", target_arch = "arm")))]
#[inline(always)]
pub fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}

/// `√x`, correctly rounded, by the FPU's `VSQRT.F64` (module docs).
#[cfg(all(feature = "hardware-sqrt", target_arch = "arm"))]
#[allow(unsafe_code)]
#[inline(always)]
pub fn sqrt(x: f64) -> f64 {
    let root: f64;
    // SAFETY: VSQRT.F64 reads one D register and writes another: no memory, no stack, no
    // control flow; it sets only FPSCR's cumulative exception bits, which nothing reads.
    unsafe {
        core::arch::asm!(
            "vsqrt.f64 {root}, {x}",
            x = in(dreg_low16) x,
            root = lateout(dreg_low16) root,
            options(pure, nomem, nostack, preserves_flags)
        );
    }
    root
}
