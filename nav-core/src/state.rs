//! The 24-state error vector of the paper's eq. (15), as named blocks.
//!
//! One table ([`BLOCKS`]) is the single source of truth for the layout; every index used
//! elsewhere is derived from a [`StateBlock`] constant (PX4 EKF2's `IdxDof` idea), never a
//! magic number.

/// A contiguous block of the error-state vector: first index and dimension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateBlock {
    /// Index of the first state of the block in the 24-vector.
    pub index: usize,
    /// Number of states in the block (3 for every block of this model).
    pub dimension: usize,
    /// Short name (for tables and telemetry).
    pub name: &'static str,
}

/// Number of error states (paper eq. 15).
pub const STATE_DIMENSION: usize = 24;
/// Number of measurement components of a full update (star attitude 3 + GNSS position 3).
pub const MEASUREMENT_DIMENSION: usize = 6;

/// Attitude error `ϑ`: vector part of the body-frame error quaternion (dimensionless, ≈ half
/// the small rotation angle in rad). States 1-3 of the paper.
pub const ATTITUDE: StateBlock = StateBlock {
    index: 0,
    dimension: 3,
    name: "attitude",
};
/// Position error `δp = p − p̂` in the launch-inertial frame (m). States 4-6.
pub const POSITION: StateBlock = StateBlock {
    index: 3,
    dimension: 3,
    name: "position",
};
/// Velocity error `δv = v − v̂` in the launch-inertial frame (m/s). States 7-9.
pub const VELOCITY: StateBlock = StateBlock {
    index: 6,
    dimension: 3,
    name: "velocity",
};
/// Gyro bias error (rad/s), body axes. States 10-12.
pub const GYRO_BIAS: StateBlock = StateBlock {
    index: 9,
    dimension: 3,
    name: "gyro_bias",
};
/// Accelerometer bias error (m/s²), body axes. States 13-15.
pub const ACCEL_BIAS: StateBlock = StateBlock {
    index: 12,
    dimension: 3,
    name: "accel_bias",
};
/// Star-sensor installation error: vector part of `q_ψ` (≈ half-angle, rad). States 16-18.
pub const STAR_INSTALLATION: StateBlock = StateBlock {
    index: 15,
    dimension: 3,
    name: "star_installation",
};
/// Gyro scale-factor errors (dimensionless), diagonal of `Λg`. States 19-21.
pub const GYRO_SCALE_FACTOR: StateBlock = StateBlock {
    index: 18,
    dimension: 3,
    name: "gyro_scale_factor",
};
/// Accelerometer scale-factor errors (dimensionless), diagonal of `Λa`. States 22-24.
pub const ACCEL_SCALE_FACTOR: StateBlock = StateBlock {
    index: 21,
    dimension: 3,
    name: "accel_scale_factor",
};

/// All blocks in the paper's order (eq. 15). Contiguous and covering 0..24 (checked by test).
pub const BLOCKS: [StateBlock; 8] = [
    ATTITUDE,
    POSITION,
    VELOCITY,
    GYRO_BIAS,
    ACCEL_BIAS,
    STAR_INSTALLATION,
    GYRO_SCALE_FACTOR,
    ACCEL_SCALE_FACTOR,
];

/// The 15 calibration states (biases, installation error, scale factors): states 10-24, five
/// 3-state blocks.
pub const CALIBRATION_BLOCKS: [StateBlock; 5] = [
    GYRO_BIAS,
    ACCEL_BIAS,
    STAR_INSTALLATION,
    GYRO_SCALE_FACTOR,
    ACCEL_SCALE_FACTOR,
];

/// A set of state blocks (e.g. the blocks frozen by the calibration manager), one bit per
/// block of [`BLOCKS`] in their order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BlockMask {
    bits: u8,
}

impl BlockMask {
    /// The empty set.
    pub const NONE: BlockMask = BlockMask { bits: 0 };

    /// Position of `block` in [`BLOCKS`] (its index / 3); blocks are 3 states each.
    #[inline]
    fn bit(block: StateBlock) -> u8 {
        let position = block.index / 3;
        u8::try_from(position).map_or(0, |p| 1u8.checked_shl(u32::from(p)).unwrap_or(0))
    }

    /// Whether the state with index `state_index` (0..24) belongs to a block in the set.
    #[inline]
    pub fn contains_state(&self, state_index: usize) -> bool {
        let position = state_index / 3;
        u32::try_from(position)
            .ok()
            .and_then(|p| 1u8.checked_shl(p))
            .is_some_and(|bit| self.bits & bit != 0)
    }

    /// Whether `block` is in the set.
    #[inline]
    pub fn contains(&self, block: StateBlock) -> bool {
        self.bits & Self::bit(block) != 0
    }

    /// Adds `block` to the set.
    #[inline]
    pub fn insert(&mut self, block: StateBlock) {
        self.bits |= Self::bit(block);
    }

    /// Removes `block` from the set.
    #[inline]
    pub fn remove(&mut self, block: StateBlock) {
        self.bits &= !Self::bit(block);
    }

    /// True for the empty set.
    pub fn is_empty(&self) -> bool {
        self.bits == 0
    }

    /// The raw bits (bit k = `BLOCKS[k]`), for telemetry.
    pub fn bits(&self) -> u8 {
        self.bits
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_mask_holds_exactly_the_inserted_blocks() {
        let mut mask = BlockMask::NONE;
        assert!(mask.is_empty());
        mask.insert(GYRO_SCALE_FACTOR);
        mask.insert(ATTITUDE);
        for block in BLOCKS {
            assert_eq!(
                mask.contains(block),
                block == GYRO_SCALE_FACTOR || block == ATTITUDE,
                "{}",
                block.name
            );
        }
        assert_eq!(mask.bits(), 0b0100_0001);
        mask.remove(ATTITUDE);
        assert_eq!(mask.bits(), 0b0100_0000);
    }

    #[test]
    fn blocks_are_contiguous_and_cover_the_state() {
        let mut next = 0;
        for block in BLOCKS {
            assert_eq!(block.index, next, "{}", block.name);
            assert_eq!(block.dimension, 3);
            next += block.dimension;
        }
        assert_eq!(next, STATE_DIMENSION);
        assert_eq!(CALIBRATION_BLOCKS[0].index, 9);
    }
}
