//! The work items of one evaluation of [`FieldRemainder`] (equations in the parent's docs).

use nalgebra::Vector3;

use super::{get, set, triangle_index, Cursor, FieldRemainder, OMITTED_DEGREES_PER_ITEM};
use crate::attitude::all_finite3;
use crate::error::NavError;
use crate::frames::LaunchFrame;
use crate::gravity::egm2008::{self, TAIL_MAX_DEGREE};

impl FieldRemainder {
    /// One frame's share of the evaluation: at most `terms_per_frame` work items. The item
    /// that starts an evaluation takes the node, `time_s` (s since the launch epoch) and
    /// `position_launch_m` (m, launch-inertial); the item that finishes it replaces the held
    /// value. Does nothing for [`super::FieldModel::J2_ONLY`].
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite node, [`NavError::NonFiniteState`] for a
    /// non-finite result; the evaluation under way is dropped and the held value kept.
    ///
    /// ```
    /// use nalgebra::Vector3;
    /// use nav_core::frames::{LaunchFrame, LaunchSite, ECEF_Z_AXIS};
    /// use nav_core::gravity::harmonics::{FieldModel, FieldRemainder};
    /// let site = LaunchSite {
    ///     latitude_rad: 0.7, longitude_rad: 1.75, height_m: 0.0,
    ///     azimuth_rad: 0.0, earth_axis_ecef: ECEF_Z_AXIS,
    /// };
    /// let frame = LaunchFrame::new(&site)?;
    /// let mut field = FieldRemainder::EMPTY;
    /// let model = FieldModel { degree: 8, order: 8, terms_per_frame: 4 };
    /// field.configure(model)?;
    /// let orbit = Vector3::new(0.0, 500.0e3, 0.0); // 500 km above the site
    /// for _ in 0..model.frames_per_evaluation() {
    ///     field.advance(&frame, 600.0, &orbit)?;
    /// }
    /// assert_eq!(field.evaluations(), 1);
    /// let beyond_j2 = field.acceleration_launch_mps2().norm();
    /// assert!(beyond_j2 > 1.0e-6 && beyond_j2 < 1.0e-3, "{beyond_j2}");
    /// # Ok::<(), nav_core::error::NavError>(())
    /// ```
    #[inline(never)]
    pub fn advance(
        &mut self,
        frame: &LaunchFrame,
        time_s: f64,
        position_launch_m: &Vector3<f64>,
    ) -> Result<(), NavError> {
        for _ in 0..self.model.terms_per_frame {
            let outcome = match self.cursor {
                Cursor::Start => {
                    if !self.is_due(time_s) {
                        return Ok(());
                    }
                    self.start(frame, time_s, position_launch_m)
                }
                Cursor::Solid { degree, order } => {
                    self.solid(degree, order);
                    Ok(())
                }
                Cursor::Coefficient { degree, order } => {
                    self.coefficient(degree, order);
                    Ok(())
                }
                Cursor::Omitted { from } => {
                    self.omitted(from);
                    Ok(())
                }
                // One evaluation per frame at most: the next starts in a later frame.
                Cursor::Finish => return self.finish(),
            };
            if let Err(error) = outcome {
                self.cursor = Cursor::Start;
                return Err(error);
            }
        }
        Ok(())
    }

    /// The node: `r`, and for a model beyond `J2` the Earth-fixed position
    /// `r_e = R(t) (p − p_centre)`, `ρ = a / r²` and `V̄_00`.
    fn start(
        &mut self,
        frame: &LaunchFrame,
        time_s: f64,
        position_launch_m: &Vector3<f64>,
    ) -> Result<(), NavError> {
        if !(all_finite3(position_launch_m) && time_s.is_finite()) {
            return Err(NavError::NonFiniteInput);
        }
        let geocentric = frame.geocentric_position_launch(position_launch_m);
        let radius_squared = geocentric.dot(&geocentric);
        let radius_m = crate::float::sqrt(radius_squared);
        if !(radius_m.is_finite() && radius_m > 0.0) {
            return Err(NavError::NonFiniteInput);
        }
        self.node_radius_m = radius_m;
        self.node_time_s = time_s;
        self.sum = [0.0; 3];
        self.omitted_sum = 0.0;
        let ratio = egm2008::RADIUS_M / radius_m;
        let ratio_squared = ratio * ratio;
        self.omitted_scale = ratio_squared * ratio_squared; // (a/r)^(2n) at n = 2
        if self.model.is_j2_only() {
            self.cursor = Cursor::Omitted { from: 2 };
            return Ok(());
        }
        let ecef_from_launch = frame.ecef_from_launch_axes(time_s)?;
        let position = ecef_from_launch * geocentric;
        let a = egm2008::RADIUS_M;
        let rho = a / radius_squared;
        self.scaled_position = [
            position.x * rho,
            position.y * rho,
            position.z * rho,
            a * rho,
        ];
        self.ecef_from_launch = ecef_from_launch;
        set(&mut self.v, 0, a / radius_m);
        set(&mut self.w, 0, 0.0);
        self.cursor = Cursor::Solid {
            degree: 1,
            order: 0,
        };
        Ok(())
    }

    /// `V̄_nm`, `W̄_nm`, then the cursor to the next harmonic (down the column, then the next
    /// column's sectoral term, then the first coefficient).
    fn solid(&mut self, degree: u8, order: u8) {
        let (n, m) = (usize::from(degree), usize::from(order));
        let [x, y, z, a_rho] = self.scaled_position;
        let at = triangle_index(n, m);
        let (v, w) = if n == m {
            let previous = triangle_index(n - 1, n - 1);
            let (v_p, w_p) = (get(&self.v, previous), get(&self.w, previous));
            let f = get(&self.alpha, at);
            (f * (x * v_p - y * w_p), f * (x * w_p + y * v_p))
        } else {
            let below = triangle_index(n - 1, m);
            let alpha = get(&self.alpha, at);
            let (mut v, mut w) = (
                alpha * z * get(&self.v, below),
                alpha * z * get(&self.w, below),
            );
            if n >= m + 2 {
                let two_below = triangle_index(n - 2, m);
                let beta = get(&self.beta, at) * a_rho;
                v -= beta * get(&self.v, two_below);
                w -= beta * get(&self.w, two_below);
            }
            (v, w)
        };
        set(&mut self.v, at, v);
        set(&mut self.w, at, w);
        let last_degree = self.model.degree.saturating_add(1);
        self.cursor = if degree < last_degree {
            Cursor::Solid {
                degree: degree + 1,
                order,
            }
        } else if order < self.model.solid_order() {
            Cursor::Solid {
                degree: order + 1,
                order: order + 1,
            }
        } else {
            Cursor::Coefficient {
                degree: 2,
                order: 0,
            }
        };
    }

    /// Coefficient `(n, m)`'s acceleration added to the sum (`C̄_20` is `J2`'s: left out),
    /// then the cursor to the next coefficient or the finish.
    fn coefficient(&mut self, degree: u8, order: u8) {
        let (n, m) = (usize::from(degree), usize::from(order));
        let at = triangle_index(n, m);
        let c = if (n, m) == (2, 0) {
            0.0
        } else {
            egm2008::C.get(at).copied().unwrap_or(0.0)
        };
        let s = egm2008::S.get(at).copied().unwrap_or(0.0);
        let [first, second, third] = self.factors.get(at).copied().unwrap_or([0.0; 3]);
        let above = triangle_index(n + 1, m);
        let (v, w) = (&self.v, &self.w);
        let z = -third * (c * get(v, above) + s * get(w, above));
        let (x, y) = if m == 0 {
            let next = above + 1;
            (-c * first * get(v, next), -c * first * get(w, next))
        } else {
            let (plus, minus) = (above + 1, above - 1);
            (
                0.5 * (first * (-c * get(v, plus) - s * get(w, plus))
                    + second * (c * get(v, minus) + s * get(w, minus))),
                0.5 * (first * (-c * get(w, plus) + s * get(v, plus))
                    + second * (-c * get(w, minus) + s * get(v, minus))),
            )
        };
        let [sum_x, sum_y, sum_z] = self.sum;
        self.sum = [sum_x + x, sum_y + y, sum_z + z];
        self.cursor = if order < degree.min(self.model.order) {
            Cursor::Coefficient {
                degree,
                order: order + 1,
            }
        } else if degree < self.model.degree {
            Cursor::Coefficient {
                degree: degree + 1,
                order: 0,
            }
        } else {
            Cursor::Omitted { from: 2 }
        };
    }

    /// The omitted power of degrees `from` to `from + OMITTED_DEGREES_PER_ITEM − 1` (at most
    /// [`TAIL_MAX_DEGREE`]) added: `Σ weight_n (a/r)^(2n)` (parent docs).
    fn omitted(&mut self, from: u8) {
        let first = usize::from(from);
        let last = (first + OMITTED_DEGREES_PER_ITEM - 1).min(TAIL_MAX_DEGREE);
        let ratio = egm2008::RADIUS_M / self.node_radius_m;
        let ratio_squared = ratio * ratio;
        let (mut sum, mut scale) = (self.omitted_sum, self.omitted_scale);
        for n in first..=last {
            sum += get(&self.omitted_weight, n) * scale;
            scale *= ratio_squared;
        }
        (self.omitted_sum, self.omitted_scale) = (sum, scale);
        self.cursor = match u8::try_from(last + 1) {
            Ok(next) if last < TAIL_MAX_DEGREE => Cursor::Omitted { from: next },
            _ => Cursor::Finish,
        };
    }

    /// The sum in launch-inertial axes (`R(t_n)ᵀ`, m/s²) held; the omitted RMS at the node's
    /// radius (parent docs).
    fn finish(&mut self) -> Result<(), NavError> {
        self.cursor = Cursor::Start;
        let a = egm2008::RADIUS_M;
        let unit = egm2008::GM_M3_S2 / (a * a);
        let [x, y, z] = self.sum;
        let acceleration = if self.model.is_j2_only() {
            Vector3::zeros()
        } else {
            self.ecef_from_launch.transpose() * Vector3::new(x, y, z) * unit
        };
        let radius = self.node_radius_m;
        let omitted_rms =
            egm2008::GM_M3_S2 / (radius * radius) * crate::float::sqrt(self.omitted_sum);
        if !(all_finite3(&acceleration) && omitted_rms.is_finite()) {
            return Err(NavError::NonFiniteState);
        }
        self.held_launch_mps2 = acceleration;
        self.held_omitted_rms_mps2 = omitted_rms;
        self.evaluations = self.evaluations.wrapping_add(1);
        Ok(())
    }
}
