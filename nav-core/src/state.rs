//! The 24-state error vector of the paper's eq. (15), as named blocks.
//!
//! One closed type ([`StateBlock`]) is the single source of truth for the layout; every index used
//! elsewhere is derived from a [`StateBlock`] constant (PX4 EKF2's `IdxDof` idea), never a
//! magic number.

/// A block of the error-state vector (paper eq. 15). A closed set: only the eight blocks of
/// the model exist, so an index or a name is never out of range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StateBlock {
    /// Attitude error `ϑ`: vector part of the body-frame error quaternion (dimensionless, ≈
    /// half the small rotation angle in rad). States 1-3 of the paper.
    Attitude,
    /// Position error `δp = p − p̂` in the launch-inertial frame (m). States 4-6.
    Position,
    /// Velocity error `δv = v − v̂` in the launch-inertial frame (m/s). States 7-9.
    Velocity,
    /// Gyro bias error (rad/s), body axes. States 10-12.
    GyroBias,
    /// Accelerometer bias error (m/s²), body axes. States 13-15.
    AccelBias,
    /// Star-sensor installation error: vector part of `q_ψ` (≈ half-angle, rad). States 16-18.
    StarInstallation,
    /// Gyro scale-factor errors (dimensionless), diagonal of `Λg`. States 19-21.
    GyroScaleFactor,
    /// Accelerometer scale-factor errors (dimensionless), diagonal of `Λa`. States 22-24.
    AccelScaleFactor,
}

impl StateBlock {
    /// All blocks in the paper's order (eq. 15); contiguous and covering 0..24 (tested).
    pub const ALL: [StateBlock; 8] = [
        Self::Attitude,
        Self::Position,
        Self::Velocity,
        Self::GyroBias,
        Self::AccelBias,
        Self::StarInstallation,
        Self::GyroScaleFactor,
        Self::AccelScaleFactor,
    ];

    /// The 15 calibration states (biases, installation error, scale factors): states 10-24,
    /// five 3-state blocks.
    pub const CALIBRATION: [StateBlock; 5] = [
        Self::GyroBias,
        Self::AccelBias,
        Self::StarInstallation,
        Self::GyroScaleFactor,
        Self::AccelScaleFactor,
    ];

    /// The navigation blocks (attitude, position, velocity).
    pub const NAVIGATION: [StateBlock; 3] = [Self::Attitude, Self::Position, Self::Velocity];

    /// Position of the block in [`StateBlock::ALL`].
    pub const fn position(self) -> usize {
        match self {
            Self::Attitude => 0,
            Self::Position => 1,
            Self::Velocity => 2,
            Self::GyroBias => 3,
            Self::AccelBias => 4,
            Self::StarInstallation => 5,
            Self::GyroScaleFactor => 6,
            Self::AccelScaleFactor => 7,
        }
    }

    /// Index of the first state of the block in the 24-vector.
    pub const fn index(self) -> usize {
        self.position() * BLOCK_DIMENSION
    }

    /// Number of states in the block (3 for every block of this model).
    pub const fn dimension(self) -> usize {
        BLOCK_DIMENSION
    }

    /// Short name (for tables and telemetry).
    pub const fn name(self) -> &'static str {
        match self {
            Self::Attitude => "attitude",
            Self::Position => "position",
            Self::Velocity => "velocity",
            Self::GyroBias => "gyro_bias",
            Self::AccelBias => "accel_bias",
            Self::StarInstallation => "star_installation",
            Self::GyroScaleFactor => "gyro_scale_factor",
            Self::AccelScaleFactor => "accel_scale_factor",
        }
    }

    /// Whether the block is one of [`StateBlock::CALIBRATION`].
    pub const fn is_calibration(self) -> bool {
        !matches!(self, Self::Attitude | Self::Position | Self::Velocity)
    }
}

/// Number of states in every block.
pub const BLOCK_DIMENSION: usize = 3;

/// Number of error states (paper eq. 15).
pub const STATE_DIMENSION: usize = 24;
/// Number of dynamic states: the blocks of [`StateBlock::NAVIGATION`] (attitude, position,
/// velocity), first in the vector; the only rows of the system matrix that are not zero.
pub const DYNAMIC_DIMENSION: usize = StateBlock::NAVIGATION.len() * BLOCK_DIMENSION;
/// Number of calibration states: the blocks of [`StateBlock::CALIBRATION`], after the dynamic
/// states.
pub const CALIBRATION_DIMENSION: usize = StateBlock::CALIBRATION.len() * BLOCK_DIMENSION;
const _: () = assert!(DYNAMIC_DIMENSION + CALIBRATION_DIMENSION == STATE_DIMENSION);
/// Number of measurement components of a full update (star attitude 3 + GNSS position 3).
pub const MEASUREMENT_DIMENSION: usize = 6;

/// [`StateBlock::Attitude`].
pub const ATTITUDE: StateBlock = StateBlock::Attitude;
/// [`StateBlock::Position`].
pub const POSITION: StateBlock = StateBlock::Position;
/// [`StateBlock::Velocity`].
pub const VELOCITY: StateBlock = StateBlock::Velocity;
/// [`StateBlock::GyroBias`].
pub const GYRO_BIAS: StateBlock = StateBlock::GyroBias;
/// [`StateBlock::AccelBias`].
pub const ACCEL_BIAS: StateBlock = StateBlock::AccelBias;
/// [`StateBlock::StarInstallation`].
pub const STAR_INSTALLATION: StateBlock = StateBlock::StarInstallation;
/// [`StateBlock::GyroScaleFactor`].
pub const GYRO_SCALE_FACTOR: StateBlock = StateBlock::GyroScaleFactor;
/// [`StateBlock::AccelScaleFactor`].
pub const ACCEL_SCALE_FACTOR: StateBlock = StateBlock::AccelScaleFactor;

/// A set of state blocks (e.g. the blocks frozen by the calibration manager), one bit per
/// block of [`StateBlock::ALL`] in their order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BlockMask {
    bits: u8,
}

impl BlockMask {
    /// The empty set.
    pub const NONE: BlockMask = BlockMask { bits: 0 };

    /// The bit of `block` (its position in [`StateBlock::ALL`]; eight blocks, eight bits).
    #[inline]
    fn bit(block: StateBlock) -> u8 {
        u32::try_from(block.position())
            .ok()
            .and_then(|position| 1u8.checked_shl(position))
            .unwrap_or(0)
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

    /// The raw bits (bit k = `StateBlock::ALL[k]`), for telemetry.
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
        for block in StateBlock::ALL {
            assert_eq!(
                mask.contains(block),
                block == GYRO_SCALE_FACTOR || block == ATTITUDE,
                "{}",
                block.name()
            );
        }
        assert_eq!(mask.bits(), 0b0100_0001);
        mask.remove(ATTITUDE);
        assert_eq!(mask.bits(), 0b0100_0000);
    }

    #[test]
    fn blocks_are_contiguous_and_cover_the_state() {
        let mut next = 0;
        for block in StateBlock::ALL {
            assert_eq!(StateBlock::ALL[block.position()], block);
            assert_eq!(block.index(), next, "{}", block.name());
            assert_eq!(block.dimension(), 3);
            assert_eq!(
                block.is_calibration(),
                StateBlock::CALIBRATION.contains(&block)
            );
            next += block.dimension();
        }
        assert_eq!(next, STATE_DIMENSION);
        assert_eq!(StateBlock::CALIBRATION[0].index(), 9);
    }
}
