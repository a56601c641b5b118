//! [`FieldRemainder`] with the feature `gravity-field`: the sliced evaluation of the field
//! beyond `J2` and its held result (equations and slices in the parent's docs).

use nalgebra::{Matrix3, Vector3};

use super::egm2008::{self, FLIGHT_MAX_DEGREE, TAIL_MAX_DEGREE};
use super::{
    triangle_index, FieldModel, COEFFICIENT_COUNT, MIN_REFRESH_PERIOD_S, OMITTED_DEGREES_PER_ITEM,
    OMITTED_ONLY_REFRESH_PERIOD_S,
};
use crate::error::NavError;

/// Solid harmonics are needed one degree above the model's.
const SOLID_DEGREE: usize = FLIGHT_MAX_DEGREE + 1;
const SOLID_COUNT: usize = triangle_index(SOLID_DEGREE, SOLID_DEGREE) + 1;

/// Where an evaluation stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cursor {
    /// No evaluation under way: the next item starts one.
    Start,
    /// Next: the solid harmonic `(n, m)`.
    Solid { degree: u8, order: u8 },
    /// Next: the coefficient `(n, m)`'s acceleration.
    Coefficient { degree: u8, order: u8 },
    /// Next: the omitted power of degrees `from ..` (at most [`OMITTED_DEGREES_PER_ITEM`]).
    Omitted { from: u8 },
    /// Next: back to launch-inertial axes, the omitted RMS, and the held value replaced.
    Finish,
}

/// The sliced evaluation and its held result (module docs). Lives in the navigation
/// computer's static memory: [`Self::EMPTY`] is written in place, then [`Self::configure`].
#[derive(Debug, Clone, PartialEq)]
pub struct FieldRemainder {
    model: FieldModel,
    /// `α_nm` (or `f_m` at `n = m`) and `β_nm` per solid harmonic.
    alpha: [f64; SOLID_COUNT],
    beta: [f64; SOLID_COUNT],
    /// `[k₀ or k₁, k₂, k₃]` per coefficient.
    factors: [[f64; 3]; COEFFICIENT_COUNT],
    /// `(n + 1)(2n + 1) Σ_{m omitted} (C̄² + S̄²)` per degree `n ≤ TAIL_MAX_DEGREE`.
    omitted_weight: [f64; TAIL_MAX_DEGREE + 1],
    v: [f64; SOLID_COUNT],
    w: [f64; SOLID_COUNT],
    /// `xρ, yρ, zρ, aρ` of the node.
    scaled_position: [f64; 4],
    /// `r` of the node (m).
    node_radius_m: f64,
    /// Earth-fixed from launch-inertial axes at the node time.
    ecef_from_launch: Matrix3<f64>,
    /// Acceleration summed so far, Earth-fixed, units of `GM / a²`.
    sum: [f64; 3],
    cursor: Cursor,
    held_launch_mps2: Vector3<f64>,
    held_omitted_rms_mps2: f64,
    /// Omitted mean square summed so far, units of `(GM / r²)²`, and `(a/r)^(2n)` of the
    /// next degree `n` to add.
    omitted_sum: f64,
    omitted_scale: f64,
    /// Start time of the evaluation under way or last made (s).
    node_time_s: f64,
    evaluations: u32,
}

impl FieldRemainder {
    /// Nothing configured: point mass + `J2` only, a zero held value.
    pub const EMPTY: Self = Self {
        model: FieldModel::J2_ONLY,
        alpha: [0.0; SOLID_COUNT],
        beta: [0.0; SOLID_COUNT],
        factors: [[0.0; 3]; COEFFICIENT_COUNT],
        omitted_weight: [0.0; TAIL_MAX_DEGREE + 1],
        v: [0.0; SOLID_COUNT],
        w: [0.0; SOLID_COUNT],
        scaled_position: [0.0; 4],
        node_radius_m: 0.0,
        ecef_from_launch: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        sum: [0.0; 3],
        cursor: Cursor::Start,
        held_launch_mps2: Vector3::new(0.0, 0.0, 0.0),
        held_omitted_rms_mps2: 0.0,
        omitted_sum: 0.0,
        omitted_scale: 0.0,
        node_time_s: f64::NEG_INFINITY,
        evaluations: 0,
    };

    /// Sets the model and its tables in place; the held value returns to zero.
    ///
    /// # Errors
    /// As [`FieldModel::validate`]; `self` is unchanged on error.
    pub fn configure(&mut self, model: FieldModel) -> Result<(), NavError> {
        model.validate()?;
        *self = Self::EMPTY;
        self.model = model;
        self.write_recursion_factors();
        self.write_acceleration_factors();
        self.write_omitted_weights();
        Ok(())
    }

    /// The model in use.
    pub fn model(&self) -> &FieldModel {
        &self.model
    }

    /// The held acceleration beyond point mass + `J2` (m/s², launch-inertial axes): zero
    /// until the first evaluation completes, and always for [`FieldModel::J2_ONLY`].
    pub fn acceleration_launch_mps2(&self) -> &Vector3<f64> {
        &self.held_launch_mps2
    }

    /// RMS over the sphere at the last node's radius of the field the model leaves out, up to
    /// degree [`TAIL_MAX_DEGREE`] (m/s²); zero before the first evaluation.
    pub fn omitted_rms_mps2(&self) -> f64 {
        self.held_omitted_rms_mps2
    }

    /// Evaluations completed (wrapping).
    pub fn evaluations(&self) -> u32 {
        self.evaluations
    }

    /// Whether [`Self::advance`] has work at navigation time `time_s` (s): an evaluation is
    /// under way, or the refresh period since the last one has elapsed. A caller that skips
    /// `advance` otherwise pays nothing in the frames between evaluations.
    #[inline]
    pub fn is_due(&self, time_s: f64) -> bool {
        let period_s = if self.model.is_j2_only() {
            OMITTED_ONLY_REFRESH_PERIOD_S
        } else {
            MIN_REFRESH_PERIOD_S
        };
        // A billionth of the period absorbs the rounding of frame times.
        self.cursor != Cursor::Start || time_s - self.node_time_s >= period_s * (1.0 - 1.0e-9)
    }

    fn write_recursion_factors(&mut self) {
        for n in 1..=SOLID_DEGREE {
            let nf = small_f64(n);
            let sectoral = if n == 1 {
                crate::float::sqrt(3.0)
            } else {
                crate::float::sqrt((2.0 * nf + 1.0) / (2.0 * nf))
            };
            set(&mut self.alpha, triangle_index(n, n), sectoral);
            for m in 0..n {
                let mf = small_f64(m);
                let at = triangle_index(n, m);
                let alpha = (2.0 * nf + 1.0) * (2.0 * nf - 1.0) / ((nf - mf) * (nf + mf));
                set(&mut self.alpha, at, crate::float::sqrt(alpha));
                if n >= m + 2 {
                    let beta = (2.0 * nf + 1.0) * (nf + mf - 1.0) * (nf - mf - 1.0)
                        / ((2.0 * nf - 3.0) * (nf + mf) * (nf - mf));
                    set(&mut self.beta, at, crate::float::sqrt(beta));
                }
            }
        }
    }

    fn write_acceleration_factors(&mut self) {
        for n in 0..=FLIGHT_MAX_DEGREE {
            let nf = small_f64(n);
            let tail = 2.0 * nf + 3.0;
            for m in 0..=n {
                let mf = small_f64(m);
                let first = if m == 0 {
                    (2.0 * nf + 1.0) * (nf + 1.0) * (nf + 2.0) / (2.0 * tail)
                } else {
                    (2.0 * nf + 1.0) * (nf + mf + 1.0) * (nf + mf + 2.0) / tail
                };
                let doubled = if m == 1 { 2.0 } else { 1.0 };
                let second = doubled * (2.0 * nf + 1.0) * (nf - mf + 1.0) * (nf - mf + 2.0) / tail;
                let third = (2.0 * nf + 1.0) * (nf + mf + 1.0) * (nf - mf + 1.0) / tail;
                if let Some(slot) = self.factors.get_mut(triangle_index(n, m)) {
                    *slot = [first, second, third].map(crate::float::sqrt);
                }
            }
        }
    }

    /// `(n + 1)(2n + 1)` times the power the model omits at degree `n`: the orders above `M`
    /// up to `N` (never `C̄_20`, which `J2` carries), every order above `N`, the file's tail
    /// beyond [`FLIGHT_MAX_DEGREE`].
    fn write_omitted_weights(&mut self) {
        let (degree, order) = (
            usize::from(self.model.degree),
            usize::from(self.model.order),
        );
        for n in 2..=TAIL_MAX_DEGREE {
            let power = if n > FLIGHT_MAX_DEGREE {
                egm2008::TAIL_DEGREE_POWER
                    .get(n - FLIGHT_MAX_DEGREE - 1)
                    .copied()
                    .unwrap_or(0.0)
            } else {
                let first_omitted = if n > degree { 0 } else { order + 1 };
                (first_omitted.max(usize::from(n == 2))..=n)
                    .map(|m| {
                        let at = triangle_index(n, m);
                        let c = egm2008::C.get(at).copied().unwrap_or(0.0);
                        let s = egm2008::S.get(at).copied().unwrap_or(0.0);
                        c * c + s * s
                    })
                    .sum()
            };
            let nf = small_f64(n);
            set(
                &mut self.omitted_weight,
                n,
                (nf + 1.0) * (2.0 * nf + 1.0) * power,
            );
        }
    }
}

/// `value` as f64 for the small loop counters of this module (≤ 61, exact).
fn small_f64(value: usize) -> f64 {
    f64::from(u32::try_from(value).unwrap_or(u32::MAX))
}

/// `table[index] = value` when `index` is in range (it is by construction).
fn set<const LENGTH: usize>(table: &mut [f64; LENGTH], index: usize, value: f64) {
    if let Some(slot) = table.get_mut(index) {
        *slot = value;
    }
}

fn get<const LENGTH: usize>(table: &[f64; LENGTH], index: usize) -> f64 {
    table.get(index).copied().unwrap_or(0.0)
}

#[path = "harmonics_step.rs"]
mod step;
