//! Which calibration blocks each class of motion makes observable: the [`MotionSignature`]
//! of the current motion and the [`MotionObservabilityTable`] the calibration manager looks
//! it up in. The table is configuration (data) in flight; `MotionObservabilityTable::compute`
//! recomputes it with nav-core's ground analysis (feature `ground-analysis`, never in a
//! flight build), and the tests prove the two agree.

use nalgebra::Vector3;
#[cfg(any(test, feature = "ground-analysis"))]
use nalgebra::{Matrix3, Quaternion};
#[cfg(any(test, feature = "ground-analysis"))]
use nav_core::observability::{
    constant_motion, full_update_measurement_matrix, motion_observability_analysis, RankTolerance,
};
#[cfg(any(test, feature = "ground-analysis"))]
use nav_core::state::StateBlock;
use nav_core::state::{
    BlockMask, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR, POSITION,
    STAR_INSTALLATION, VELOCITY,
};

#[cfg(any(test, feature = "ground-analysis"))]
use crate::error::FswError;

/// The structure of the current motion: which body axes rotate faster than
/// `CalibrationManagerConfig::motion_rate_threshold_rad_s` (bits 0-2, x y z) and which
/// carry a specific force above `CalibrationManagerConfig::motion_force_threshold_mps2`
/// (bits 3-5). Structural observability depends on this pattern only (not on the magnitudes,
/// for generic values), which is why 64 entries describe every motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotionSignature {
    bits: u8,
}

impl MotionSignature {
    /// Number of distinct signatures (6 bits).
    pub const COUNT: usize = 64;

    /// Classifies a body rate (rad/s) and specific force (m/s²) against the thresholds
    /// (absolute value per axis; NaN counts as "not moving").
    pub fn classify(
        body_rate_rad_s: &Vector3<f64>,
        specific_force_mps2: &Vector3<f64>,
        rate_threshold_rad_s: f64,
        force_threshold_mps2: f64,
    ) -> Self {
        let mut bits = 0u8;
        for (bit, rate) in [1u8, 2, 4].iter().zip(body_rate_rad_s.iter()) {
            if rate.abs() > rate_threshold_rad_s {
                bits |= bit;
            }
        }
        for (bit, force) in [8u8, 16, 32].iter().zip(specific_force_mps2.iter()) {
            if force.abs() > force_threshold_mps2 {
                bits |= bit;
            }
        }
        Self { bits }
    }

    /// From its 6 bits (higher bits ignored).
    pub fn from_bits(bits: u8) -> Self {
        Self { bits: bits & 0x3f }
    }

    /// The 6 bits (0-2 rotating axes, 3-5 specific-force axes).
    pub fn bits(&self) -> u8 {
        self.bits
    }

    /// A representative constant motion of this signature for the analysis: 10, 12 and
    /// 14 °/s about the flagged axes and 20, 22 and 24 m/s² along the flagged axes (the
    /// paper's state II and III magnitudes, made distinct so that no accidental symmetry
    /// between axes enters the structural test).
    #[cfg(any(test, feature = "ground-analysis"))]
    fn representative_motion(&self) -> (Vector3<f64>, Vector3<f64>) {
        const RADIANS_PER_DEGREE: f64 = core::f64::consts::PI / 180.0;
        let flag = |bit: u8, value: f64| if self.bits & bit != 0 { value } else { 0.0 };
        let rate = Vector3::new(
            flag(1, 10.0 * RADIANS_PER_DEGREE),
            flag(2, 12.0 * RADIANS_PER_DEGREE),
            flag(4, 14.0 * RADIANS_PER_DEGREE),
        );
        let force = Vector3::new(flag(8, 20.0), flag(16, 22.0), flag(32, 24.0));
        (rate, force)
    }
}

/// For each [`MotionSignature`], the calibration blocks in which that motion makes at least
/// one direction observable (`nav_core::observability::ObservabilityAnalysis::observable_directions`).
///
/// The table is configuration, not computed in flight: the analysis needs nalgebra's SVD and
/// symmetric eigen-decomposition, which contain panic paths (the panic-never flight build
/// refuses to link them), so `Self::compute` runs on the ground (nav-sim, or the QEMU
/// checks where the singular values are compared bit for bit with the host) and the flight
/// software only looks entries up. The default is [`Self::structural`], the pattern the
/// analysis gives for any mounting (proven by this module's tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotionObservabilityTable {
    estimable: [BlockMask; MotionSignature::COUNT],
}

impl Default for MotionObservabilityTable {
    fn default() -> Self {
        Self::structural()
    }
}

impl MotionObservabilityTable {
    /// Rank and null space as [`RankTolerance::DEFAULT`], but a direction inside a block
    /// counts as estimable when at most 10 % of it (scaled coordinates, projection 0.1) lies
    /// in the unobservable subspace. The structural 1e-6 would be right for axis-aligned
    /// motions, whose null vectors are exact, but under an oblique rotation the unobservable
    /// scale-factor combinations (perpendicular to the rotation axis: their drift only tilts
    /// the body-frame attitude by a constant) carry installation components of order 1e-3,
    /// which would hide the two installation directions that the rotation does reveal.
    #[cfg(any(test, feature = "ground-analysis"))]
    pub const ESTIMABLE: RankTolerance = RankTolerance {
        projection: 0.1,
        ..RankTolerance::DEFAULT
    };

    /// The analysis' result in closed form: the biases in every motion; a rotation adds the
    /// installation error and the gyro scale factor, a specific force adds the installation
    /// error and the accelerometer scale factor. Why (module tests prove that
    /// `Self::compute` gives exactly this): after the reference coast a constant rotation
    /// separates the scale-factor drift along its axis from the bias, and the turning body
    /// separates the installation directions perpendicular to it from the attitude error;
    /// a specific force reveals the accelerometer scale factor along it and the attitude
    /// about the perpendicular axes through the velocity, hence installation directions.
    pub fn structural() -> Self {
        let mut estimable = [BlockMask::NONE; MotionSignature::COUNT];
        for (bits, mask) in (0u8..).zip(estimable.iter_mut()) {
            mask.insert(GYRO_BIAS);
            mask.insert(ACCEL_BIAS);
            if bits & 0b00_0111 != 0 {
                mask.insert(STAR_INSTALLATION);
                mask.insert(GYRO_SCALE_FACTOR);
            }
            if bits & 0b11_1000 != 0 {
                mask.insert(STAR_INSTALLATION);
                mask.insert(ACCEL_SCALE_FACTOR);
            }
        }
        Self { estimable }
    }

    /// A table from explicit entries (index = [`MotionSignature::bits`]), e.g. one computed
    /// on the ground for another model. Checked by `CalibrationManagerConfig::validate`.
    pub fn from_entries(estimable: [BlockMask; MotionSignature::COUNT]) -> Self {
        Self { estimable }
    }

    /// Only calibration blocks in every entry.
    pub(crate) fn is_valid(&self) -> bool {
        self.estimable.iter().all(|mask| {
            !(mask.contains(ATTITUDE) || mask.contains(POSITION) || mask.contains(VELOCITY))
        })
    }

    /// Runs the structural analysis for the 64 signatures (ground work: 64 × two
    /// 144-row Givens segments and one 24×24 SVD; not for the flight image, see the type's
    /// docs).
    ///
    /// The attitude is the identity: a rotation of the launch-inertial frame maps the
    /// stripped observability matrix of body-frame states onto one with the same row space
    /// (position and velocity rows rotate, `H` of the star sensor is `C_sb` in body axes), so
    /// the answer does not depend on it. The star-sensor mounting `q_bs` does enter `H` and is
    /// the configured one.
    ///
    /// # Errors
    /// [`FswError::Navigation`] if the analysis fails (a non-finite mounting, or an SVD that
    /// does not converge).
    #[cfg(any(test, feature = "ground-analysis"))]
    pub fn compute(star_mounting: &Quaternion<f64>) -> Result<Self, FswError> {
        let h = full_update_measurement_matrix(&Quaternion::identity(), star_mounting)?;
        let mut estimable = [BlockMask::NONE; MotionSignature::COUNT];
        for (bits, mask) in (0u8..).zip(estimable.iter_mut()) {
            let (rate, force) = MotionSignature::from_bits(bits).representative_motion();
            let point = constant_motion(&rate, &force, &Matrix3::identity());
            let analysis = motion_observability_analysis(&point, &h, &RankTolerance::DEFAULT)?;
            for block in StateBlock::CALIBRATION {
                if analysis.observable_directions(block, &Self::ESTIMABLE)? > 0 {
                    mask.insert(block);
                }
            }
        }
        Ok(Self { estimable })
    }

    /// The calibration blocks `signature` makes observable.
    pub fn estimable(&self, signature: MotionSignature) -> BlockMask {
        self.estimable
            .get(usize::from(signature.bits))
            .copied()
            .unwrap_or(BlockMask::NONE)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use nav_core::state::StateBlock;

    /// The bits of the set of `blocks`.
    pub(crate) fn mask(blocks: &[StateBlock]) -> u8 {
        let mut mask = BlockMask::NONE;
        for block in blocks {
            mask.insert(*block);
        }
        mask.bits()
    }

    #[test]
    fn the_observability_table_matches_the_analytical_pattern() {
        // A generic mounting, so that sensor axes and body axes do not coincide.
        let mounting = nav_core::attitude::exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.5));
        let table = MotionObservabilityTable::compute(&mounting).unwrap();
        assert_eq!(table, MotionObservabilityTable::structural());
        assert_eq!(
            MotionObservabilityTable::compute(&Quaternion::identity()).unwrap(),
            table
        );
        for bits in 0..64u8 {
            let rotating = bits & 0b00_0111 != 0;
            let thrusting = bits & 0b11_1000 != 0;
            // Coast after coast: the biases show in the star attitude and the GNSS position;
            // the installation error is not separable from the attitude error, and the scale
            // factors multiply a zero rate and specific force.
            let mut expected = vec![GYRO_BIAS, ACCEL_BIAS];
            // Rotating (after the reference coast): the scale-factor drift along the rotation
            // axis separates from the bias, and the turning body separates the installation
            // directions perpendicular to the axis from the attitude error.
            if rotating {
                expected.extend([STAR_INSTALLATION, GYRO_SCALE_FACTOR]);
            }
            // Thrusting: the accelerometer scale factor along the thrust, and the attitude
            // about axes perpendicular to it (through the velocity), hence installation.
            if thrusting {
                expected.extend([STAR_INSTALLATION, ACCEL_SCALE_FACTOR]);
            }
            assert_eq!(
                table.estimable(MotionSignature::from_bits(bits)).bits(),
                mask(&expected),
                "signature {bits:06b}"
            );
        }
    }
}
