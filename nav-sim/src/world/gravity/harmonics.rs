//! Spherical-harmonic gravitation in Earth-fixed axes, by Cunningham's recursion of the
//! solid harmonics `V_nm`, `W_nm` (Montenbruck & Gill, *Satellite Orbits*, 2000, §3.2.4–3.2.5,
//! eqs. 3.29–3.33), rewritten for fully normalised coefficients.
//!
//! With `ρ = a / r²` and the normalisation `N_nm = √((2 − δ_m0)(2n + 1)(n − m)!/(n + m)!)`
//! (`C_nm = N_nm C̄_nm`), the normalised harmonics `V̄_nm = N_nm V_nm` obey, from
//! `V̄_00 = a / r`, `W̄_00 = 0`:
//!
//! ```text
//! V̄_mm = f_m (x ρ V̄_m−1,m−1 − y ρ W̄_m−1,m−1)     f_1 = √3, f_m = √((2m + 1)/(2m)) (m ≥ 2)
//! W̄_mm = f_m (x ρ W̄_m−1,m−1 + y ρ V̄_m−1,m−1)
//! V̄_nm = α_nm z ρ V̄_n−1,m − β_nm a ρ V̄_n−2,m       (the same for W̄)
//! α_nm = √((2n + 1)(2n − 1) / ((n − m)(n + m)))
//! β_nm = √((2n + 1)(n + m − 1)(n − m − 1) / ((2n − 3)(n + m)(n − m)))
//! ```
//!
//! (M&G eqs. 3.30–3.31 times the ratios of `N_nm`; the same `α`, `β` as the Legendre
//! forward-column recursion of Holmes & Featherstone, *J. Geodesy* 76, 2002, eqs. 11–12).
//! M&G eq. 3.33 becomes, per term, in units of `GM / a²`:
//!
//! ```text
//! m = 0:  ẍ = −C̄ k₀ V̄_n+1,1              ÿ = −C̄ k₀ W̄_n+1,1
//! m > 0:  ẍ = ½ [k₁ (−C̄ V̄_n+1,m+1 − S̄ W̄_n+1,m+1) + k₂ (C̄ V̄_n+1,m−1 + S̄ W̄_n+1,m−1)]
//!         ÿ = ½ [k₁ (−C̄ W̄_n+1,m+1 + S̄ V̄_n+1,m+1) + k₂ (−C̄ W̄_n+1,m−1 + S̄ V̄_n+1,m−1)]
//! all m:  z̈ = k₃ (−C̄ V̄_n+1,m − S̄ W̄_n+1,m)
//! k₀² = (2n + 1)(n + 1)(n + 2) / (2 (2n + 3))      k₁² = (2n + 1)(n + m + 1)(n + m + 2) / (2n + 3)
//! k₂² = (1 + δ_m1)(2n + 1)(n − m + 1)(n − m + 2) / (2n + 3)
//! k₃² = (2n + 1)(n + m + 1)(n − m + 1) / (2n + 3)
//! ```
//!
//! (`k = N_nm / N_n+1,m±1` times M&G's integer factors). The recursion has no pole
//! singularity, and every quantity stays within a few powers of ten of 1 at any degree this
//! crate uses.

use nalgebra::Vector3;

use super::gfc::{triangle_index, GravityCoefficients};

/// A spherical-harmonic field ready to evaluate: the coefficients and the recursion factors.
#[derive(Debug, Clone, PartialEq)]
pub struct SphericalHarmonics {
    coefficients: GravityCoefficients,
    /// `α_nm`, `β_nm` (zonal and tesseral) or `f_m` (sectoral, in `alpha`) for `n ≤ N + 1`.
    alpha: Vec<f64>,
    beta: Vec<f64>,
    /// `[k₀ or k₁, k₂, k₃]` per coefficient `(n, m)`, `n ≤ N`.
    factors: Vec<[f64; 3]>,
}

fn recursion_factors(degree: usize) -> (Vec<f64>, Vec<f64>) {
    let size = triangle_index(degree, degree) + 1;
    let (mut alpha, mut beta) = (vec![0.0; size], vec![0.0; size]);
    for n in 1..=degree {
        let nf = n as f64;
        let sectoral = if n == 1 {
            3.0_f64.sqrt()
        } else {
            ((2.0 * nf + 1.0) / (2.0 * nf)).sqrt()
        };
        alpha[triangle_index(n, n)] = sectoral;
        for m in 0..n {
            let mf = m as f64;
            let at = triangle_index(n, m);
            alpha[at] = ((2.0 * nf + 1.0) * (2.0 * nf - 1.0) / ((nf - mf) * (nf + mf))).sqrt();
            beta[at] = if n >= m + 2 {
                ((2.0 * nf + 1.0) * (nf + mf - 1.0) * (nf - mf - 1.0)
                    / ((2.0 * nf - 3.0) * (nf + mf) * (nf - mf)))
                    .sqrt()
            } else {
                0.0
            };
        }
    }
    (alpha, beta)
}

fn acceleration_factors(degree: usize) -> Vec<[f64; 3]> {
    let mut factors = vec![[0.0; 3]; triangle_index(degree, degree) + 1];
    for n in 0..=degree {
        let nf = n as f64;
        let tail = 2.0 * nf + 3.0;
        for m in 0..=n {
            let mf = m as f64;
            let first = if m == 0 {
                (2.0 * nf + 1.0) * (nf + 1.0) * (nf + 2.0) / (2.0 * tail)
            } else {
                (2.0 * nf + 1.0) * (nf + mf + 1.0) * (nf + mf + 2.0) / tail
            };
            let doubled = if m == 1 { 2.0 } else { 1.0 };
            let second = doubled * (2.0 * nf + 1.0) * (nf - mf + 1.0) * (nf - mf + 2.0) / tail;
            let third = (2.0 * nf + 1.0) * (nf + mf + 1.0) * (nf - mf + 1.0) / tail;
            factors[triangle_index(n, m)] = [first.sqrt(), second.sqrt(), third.sqrt()];
        }
    }
    factors
}

impl SphericalHarmonics {
    /// The field of `coefficients` (all of them, degree 0 included).
    pub fn new(coefficients: GravityCoefficients) -> Self {
        let (alpha, beta) = recursion_factors(coefficients.degree + 1);
        let factors = acceleration_factors(coefficients.degree);
        Self {
            coefficients,
            alpha,
            beta,
            factors,
        }
    }

    /// The coefficients evaluated.
    pub fn coefficients(&self) -> &GravityCoefficients {
        &self.coefficients
    }

    /// `V̄_nm`, `W̄_nm` for `n ≤ N + 1`, `m ≤ min(n, M + 1)` at Earth-fixed `position_m`.
    fn solid_harmonics(&self, position_m: &Vector3<f64>) -> (Vec<f64>, Vec<f64>) {
        let degree = self.coefficients.degree + 1;
        let order = (self.coefficients.order + 1).min(degree);
        let radius_m = self.coefficients.radius_m;
        let size = triangle_index(degree, degree) + 1;
        let (mut v, mut w) = (vec![0.0; size], vec![0.0; size]);
        let r2 = position_m.norm_squared();
        let rho = radius_m / r2;
        let (x, y, z) = (position_m.x * rho, position_m.y * rho, position_m.z * rho);
        let a_rho = radius_m * rho;
        v[0] = radius_m / r2.sqrt();
        for m in 0..=order {
            if m > 0 {
                let (previous, at) = (triangle_index(m - 1, m - 1), triangle_index(m, m));
                let f = self.alpha[at];
                v[at] = f * (x * v[previous] - y * w[previous]);
                w[at] = f * (x * w[previous] + y * v[previous]);
            }
            for n in (m + 1)..=degree {
                let at = triangle_index(n, m);
                let one_below = triangle_index(n - 1, m);
                let (alpha, beta) = (self.alpha[at], self.beta[at]);
                let (mut v_nm, mut w_nm) = (alpha * z * v[one_below], alpha * z * w[one_below]);
                if n >= m + 2 {
                    let two_below = triangle_index(n - 2, m);
                    v_nm -= beta * a_rho * v[two_below];
                    w_nm -= beta * a_rho * w[two_below];
                }
                v[at] = v_nm;
                w[at] = w_nm;
            }
        }
        (v, w)
    }

    /// Gravitational acceleration (m/s²) in Earth-fixed axes at Earth-fixed geocentric
    /// `position_m` (m): the sum of M&G eq. 3.33 over every coefficient (module docs).
    /// Non-finite at the Earth centre or for a non-finite position.
    pub fn acceleration_mps2(&self, position_m: &Vector3<f64>) -> Vector3<f64> {
        let (v, w) = self.solid_harmonics(position_m);
        let coefficients = &self.coefficients;
        let mut sum = Vector3::zeros();
        for n in 0..=coefficients.degree {
            for m in 0..=n.min(coefficients.order) {
                let at = triangle_index(n, m);
                let (c, s) = (coefficients.c[at], coefficients.s[at]);
                if c == 0.0 && s == 0.0 {
                    continue;
                }
                let [first, second, third] = self.factors[at];
                let above = triangle_index(n + 1, m);
                let z = -third * (c * v[above] + s * w[above]);
                let (x, y) = if m == 0 {
                    (-c * first * v[above + 1], -c * first * w[above + 1])
                } else {
                    let (plus, minus) = (above + 1, above - 1);
                    (
                        0.5 * (first * (-c * v[plus] - s * w[plus])
                            + second * (c * v[minus] + s * w[minus])),
                        0.5 * (first * (-c * w[plus] + s * v[plus])
                            + second * (-c * w[minus] + s * v[minus])),
                    )
                };
                sum += Vector3::new(x, y, z);
            }
        }
        sum * (coefficients.gm_m3_s2 / (coefficients.radius_m * coefficients.radius_m))
    }
}
