//! The model's dense matrices `F` and `Qd`, for the comparisons with the dense reference
//! (the flight path never forms them): compiled for the `dense-reference` feature and the
//! tests only.

use super::{StructuredModel, ATT, BIAS_A, BIAS_G, POS, SCALE_A, SCALE_G, VEL};
use crate::block::{scale_columns, write, write_diagonal_symmetric, write_symmetric};
use crate::discretise::CovarianceMatrix;

impl StructuredModel {
    /// The dense 24×24 `F` (for tests and reports; the flight path never forms it).
    pub fn transition_matrix(&self) -> CovarianceMatrix {
        let mut f = CovarianceMatrix::identity();
        let t = &self.transition;
        write::<ATT, ATT>(&mut f, &t.attitude_attitude);
        write::<POS, ATT>(&mut f, &t.position_attitude);
        write::<POS, POS>(&mut f, &t.position_position);
        write::<POS, VEL>(&mut f, &t.position_velocity);
        write::<VEL, ATT>(&mut f, &t.velocity_attitude);
        write::<VEL, POS>(&mut f, &t.velocity_position);
        write::<VEL, VEL>(&mut f, &t.velocity_velocity);
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let rate = self.measured_rate_rad_s;
        let force = self.measured_specific_force_mps2;
        write::<ATT, BIAS_G>(&mut f, gyro_attitude);
        write::<POS, BIAS_G>(&mut f, gyro_position);
        write::<VEL, BIAS_G>(&mut f, gyro_velocity);
        write::<ATT, SCALE_G>(&mut f, &scale_columns(gyro_attitude, rate));
        write::<POS, SCALE_G>(&mut f, &scale_columns(gyro_position, rate));
        write::<VEL, SCALE_G>(&mut f, &scale_columns(gyro_velocity, rate));
        write::<POS, BIAS_A>(&mut f, accel_position);
        write::<VEL, BIAS_A>(&mut f, accel_velocity);
        write::<POS, SCALE_A>(&mut f, &scale_columns(accel_position, force));
        write::<VEL, SCALE_A>(&mut f, &scale_columns(accel_velocity, force));
        f
    }

    /// The dense 24×24 `Qd` (for tests and reports).
    pub fn process_noise_matrix(&self) -> CovarianceMatrix {
        let mut q = CovarianceMatrix::zeros();
        let mut unfolded = *self;
        unfolded.unfold_input_noise();
        let n = &unfolded.noise;
        let [aa, ap, av, pp, pv, vv] = &n.dynamic;
        write_diagonal_symmetric::<ATT>(&mut q, aa);
        write_symmetric::<ATT, POS>(&mut q, ap);
        write_symmetric::<ATT, VEL>(&mut q, av);
        write_diagonal_symmetric::<POS>(&mut q, pp);
        write_symmetric::<POS, VEL>(&mut q, pv);
        write_diagonal_symmetric::<VEL>(&mut q, vv);
        let [ga, gp, gv] = &n.dynamic_gyro_bias;
        write_symmetric::<ATT, BIAS_G>(&mut q, ga);
        write_symmetric::<POS, BIAS_G>(&mut q, gp);
        write_symmetric::<VEL, BIAS_G>(&mut q, gv);
        let [ba_attitude, ba_position, ba_velocity] = &n.dynamic_accel_bias;
        write_symmetric::<ATT, BIAS_A>(&mut q, ba_attitude);
        write_symmetric::<POS, BIAS_A>(&mut q, ba_position);
        write_symmetric::<VEL, BIAS_A>(&mut q, ba_velocity);
        write_diagonal_symmetric::<BIAS_G>(&mut q, &n.gyro_bias);
        write_diagonal_symmetric::<BIAS_A>(&mut q, &n.accel_bias);
        q
    }
}
