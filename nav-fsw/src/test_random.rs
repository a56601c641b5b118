//! Deterministic random draws for the unit tests of the statistical monitors (consistency,
//! noise matching): the same seed gives the same draws on every machine.

/// A deterministic pseudo-random N(0, 1) source (xorshift + Box–Muller).
pub(crate) fn normal_source(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 + 1e-18
        };
        let (u, v) = (uniform(), uniform());
        nav_core::float::sqrt(-2.0 * libm::log(u)) * libm::cos(2.0 * core::f64::consts::PI * v)
    }
}
