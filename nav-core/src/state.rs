//! The state layout: every block of the error state, the paper's 24 states (eq. 15) and the
//! optional blocks a mission may fly, declared once in one table (`state_layout!` below, PX4
//! EKF2's generated `state.h` idea). Every index, name, unit, dimension, freeze permission
//! and carrying cargo feature used elsewhere comes from it, never a magic number.
//!
//! The core blocks ([`StateBlock`]) are always there, in the paper's order. The optional
//! blocks ([`OptionalBlock`]) follow them in the layout, each carried by a cargo feature of
//! nav-core; a build without the feature holds neither the block's memory nor its code.

/// Declares the state layout. Each line: the block, its short name (tables, telemetry
/// columns), its unit, its number of states, whether the calibration manager may freeze it,
/// and for an optional block the cargo feature that carries it. Generates [`StateBlock`],
/// [`OptionalBlock`] and their accessors; the blocks' indices are the running sums of the
/// dimensions in table order.
macro_rules! state_layout {
    (
        core {
            $( $(#[$core_doc:meta])* $core:ident =
                ($core_name:literal, $core_unit:literal, $core_dimension:literal, $core_freeze:literal); )*
        }
        optional {
            $( $(#[$optional_doc:meta])* $optional:ident =
                ($optional_name:literal, $optional_unit:literal, $optional_dimension:literal,
                 $optional_freeze:literal, $feature:literal); )*
        }
    ) => {
        /// A core block of the error-state vector (paper eq. 15). A closed set: only the
        /// eight blocks of the model exist, so an index or a name is never out of range.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub enum StateBlock {
            $( $(#[$core_doc])* $core, )*
        }

        /// An optional block of the error state, after the core blocks in the layout; each is
        /// carried by a cargo feature ([`OptionalBlock::feature`]).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub enum OptionalBlock {
            $( $(#[$optional_doc])* $optional, )*
        }

        /// Number of core error states (paper eq. 15): the core blocks' dimensions summed.
        pub const STATE_DIMENSION: usize = 0 $(+ $core_dimension)*;
        /// Number of states of the layout with every optional block.
        pub const LAYOUT_DIMENSION: usize = STATE_DIMENSION $(+ $optional_dimension)*;
        /// Number of states of the optional blocks together (the layout's after the core's).
        pub const OPTIONAL_DIMENSION: usize = LAYOUT_DIMENSION - STATE_DIMENSION;

        /// The first state of each block, by the blocks' names (running sums of the table's
        /// dimensions, evaluated at compile time).
        #[allow(non_upper_case_globals, clippy::indexing_slicing, clippy::as_conversions)]
        mod first_state {
            use super::{OptionalBlock, StateBlock};
            const CORE: [usize; StateBlock::ALL.len()] =
                super::running_sums(0, [$($core_dimension),*]);
            const OPTIONAL: [usize; OptionalBlock::ALL.len()] =
                super::running_sums(super::STATE_DIMENSION, [$($optional_dimension),*]);
            $( pub(super) const $core: usize = CORE[StateBlock::$core as usize]; )*
            $( pub(super) const $optional: usize = OPTIONAL[OptionalBlock::$optional as usize]; )*
        }

        impl StateBlock {
            /// All core blocks in the paper's order (eq. 15); contiguous and covering 0..24
            /// (tested).
            pub const ALL: [StateBlock; [$(stringify!($core)),*].len()] = [$(Self::$core),*];

            /// Index of the first state of the block in the 24-vector.
            pub const fn index(self) -> usize {
                match self { $(Self::$core => first_state::$core,)* }
            }

            /// Number of states in the block (3 for every core block of this model).
            pub const fn dimension(self) -> usize {
                match self { $(Self::$core => $core_dimension,)* }
            }

            /// Short name (for tables and telemetry).
            pub const fn name(self) -> &'static str {
                match self { $(Self::$core => $core_name,)* }
            }

            /// Unit of the block's states.
            pub const fn unit(self) -> &'static str {
                match self { $(Self::$core => $core_unit,)* }
            }

            /// Whether the calibration manager may freeze the block (a calibration block).
            pub const fn may_freeze(self) -> bool {
                match self { $(Self::$core => $core_freeze,)* }
            }
        }

        impl OptionalBlock {
            /// All optional blocks in layout order, compiled in or not.
            pub const ALL: [OptionalBlock; [$(stringify!($optional)),*].len()] =
                [$(Self::$optional),*];

            /// Index of the block's first state in the layout with every block (after the
            /// 24 core states).
            pub const fn index(self) -> usize {
                match self { $(Self::$optional => first_state::$optional,)* }
            }

            /// Number of states in the block.
            pub const fn dimension(self) -> usize {
                match self { $(Self::$optional => $optional_dimension,)* }
            }

            /// Short name (for tables and telemetry).
            pub const fn name(self) -> &'static str {
                match self { $(Self::$optional => $optional_name,)* }
            }

            /// Unit of the block's states.
            pub const fn unit(self) -> &'static str {
                match self { $(Self::$optional => $optional_unit,)* }
            }

            /// Whether the calibration manager may freeze the block.
            pub const fn may_freeze(self) -> bool {
                match self { $(Self::$optional => $optional_freeze,)* }
            }

            /// The nav-core cargo feature that carries the block.
            pub const fn feature(self) -> &'static str {
                match self { $(Self::$optional => $feature,)* }
            }

            /// Whether this build carries the block (its feature is on).
            pub const fn is_compiled(self) -> bool {
                match self { $(Self::$optional => cfg!(feature = $feature),)* }
            }
        }
    };
}

/// `start` plus the running sums of `dimensions`: each block's first state. Evaluated only
/// in constants (the layout's), so its indexing is checked at compile time.
#[allow(clippy::indexing_slicing)]
const fn running_sums<const N: usize>(start: usize, dimensions: [usize; N]) -> [usize; N] {
    let mut first = [0; N];
    let mut next = start;
    let mut k = 0;
    while k < N {
        first[k] = next;
        next += dimensions[k];
        k += 1;
    }
    first
}

state_layout! {
    core {
        /// Attitude error `ϑ`: vector part of the body-frame error quaternion (dimensionless,
        /// ≈ half the small rotation angle in rad). States 1-3 of the paper.
        Attitude = ("attitude", "rad/2", 3, false);
        /// Position error `δp = p − p̂` in the launch-inertial frame (m). States 4-6.
        Position = ("position", "m", 3, false);
        /// Velocity error `δv = v − v̂` in the launch-inertial frame (m/s). States 7-9.
        Velocity = ("velocity", "m/s", 3, false);
        /// Gyro bias error (rad/s), body axes. States 10-12.
        GyroBias = ("gyro_bias", "rad/s", 3, true);
        /// Accelerometer bias error (m/s²), body axes. States 13-15.
        AccelBias = ("accel_bias", "m/s^2", 3, true);
        /// Star-sensor installation error: vector part of `q_ψ` (≈ half-angle, rad). States
        /// 16-18.
        StarInstallation = ("star_installation", "rad/2", 3, true);
        /// Gyro scale-factor errors (dimensionless), diagonal of `Λg`. States 19-21.
        GyroScaleFactor = ("gyro_scale_factor", "1", 3, true);
        /// Accelerometer scale-factor errors (dimensionless), diagonal of `Λa`. States 22-24.
        AccelScaleFactor = ("accel_scale_factor", "1", 3, true);
    }
    optional {
        /// The receiver's correlated position error `ε` (m, launch-inertial axes):
        /// [`crate::gnss_error`].
        GnssError = ("gnss_error", "m", 3, true, "gnss-error-states");
        /// Gyro non-orthogonality (rad): [`crate::imu_error_states`].
        GyroNonOrthogonality = ("gyro_non_orthogonality", "rad", 3, true, "imu-error-states");
        /// Accelerometer misalignment (rad): [`crate::imu_error_states`].
        AccelMisalignment = ("accel_misalignment", "rad", 6, true, "imu-error-states");
        /// Gyro g-sensitivity (rad/s per m/s²): [`crate::imu_error_states`].
        GyroGSensitivity = ("gyro_g_sensitivity", "rad/s/(m/s^2)", 3, true, "imu-error-states");
    }
}

impl StateBlock {
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

    /// Position of the block in [`StateBlock::ALL`] (its declaration order).
    #[allow(clippy::as_conversions)] // a fieldless enum's discriminant: lossless
    pub const fn position(self) -> usize {
        self as usize
    }

    /// Whether the block is one of [`StateBlock::CALIBRATION`].
    pub const fn is_calibration(self) -> bool {
        !matches!(self, Self::Attitude | Self::Position | Self::Velocity)
    }
}

/// Number of states in every block.
pub const BLOCK_DIMENSION: usize = 3;

// Every core block has three states (the structured kernels work on 3×3 blocks).
#[allow(clippy::indexing_slicing)] // evaluated at compile time
const _: () = {
    let mut k = 0;
    while k < StateBlock::ALL.len() {
        assert!(StateBlock::ALL[k].dimension() == BLOCK_DIMENSION);
        k += 1;
    }
};
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

impl OptionalBlock {
    /// Position of the block in [`OptionalBlock::ALL`] (its declaration order).
    #[allow(clippy::as_conversions)] // a fieldless enum's discriminant: lossless
    pub const fn position(self) -> usize {
        self as usize
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
    fn the_layout_numbers_every_state_once() {
        let mut next = STATE_DIMENSION;
        for block in OptionalBlock::ALL {
            assert_eq!(OptionalBlock::ALL[block.position()], block);
            assert_eq!(block.index(), next, "{}", block.name());
            assert!(block.may_freeze());
            next += block.dimension();
        }
        assert_eq!(next, LAYOUT_DIMENSION);
        assert_eq!(LAYOUT_DIMENSION, 39);
        assert_eq!(OptionalBlock::AccelMisalignment.dimension(), 6);
        assert_eq!(OptionalBlock::GnssError.feature(), "gnss-error-states");
        assert_eq!(
            OptionalBlock::GyroGSensitivity.is_compiled(),
            cfg!(feature = "imu-error-states")
        );
        assert_eq!(GYRO_BIAS.unit(), "rad/s");
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
            assert_eq!(block.may_freeze(), block.is_calibration());
            next += block.dimension();
        }
        assert_eq!(next, STATE_DIMENSION);
        assert_eq!(StateBlock::CALIBRATION[0].index(), 9);
    }

    /// Each optional block's own files (under `nav-core/src`) and the words that name it: its
    /// module, types, configuration field and cargo feature.
    const OPTIONAL_BLOCK_NAMES: [(&str, &[&str], &[&str]); 2] = [
        (
            "gnss-error-states",
            &["gnss_error/"],
            &["gnss_error", "GnssError", "gnss-error-states"],
        ),
        (
            "imu-error-states",
            &["imu_error_states/", "imu_error.rs", "imu_error_tests.rs"],
            &[
                "imu_error",
                "ImuError",
                "imu-error-states",
                "GyroNonOrthogonality",
                "AccelMisalignment",
                "GyroGSensitivity",
            ],
        ),
    ];

    /// Every `.rs` file under `root`, as paths relative to it with `/` separators.
    fn source_files(root: &std::path::Path) -> Vec<String> {
        let mut files = Vec::new();
        let mut directories = vec![root.to_path_buf()];
        while let Some(directory) = directories.pop() {
            for entry in std::fs::read_dir(directory).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    directories.push(path);
                } else if path.extension().is_some_and(|extension| extension == "rs") {
                    let relative = path.strip_prefix(root).unwrap();
                    files.push(relative.to_string_lossy().replace('\\', "/"));
                }
            }
        }
        files.sort();
        files
    }

    /// The next optional block is its own module plus a line in the layout: outside its own
    /// files, nav-core's flight source (tests excluded) names each optional block in at most
    /// three files (the layout here, the registration in `filter/blocks.rs`, the `mod` line
    /// in `lib.rs`); everything else reaches it through `crate::block_interface`.
    #[test]
    fn each_optional_block_is_named_in_at_most_three_files_outside_its_own() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let files = source_files(&root);
        let is_test = |file: &str| file.ends_with("/tests.rs") || file.ends_with("_tests.rs");
        assert!(files.len() > 40, "{files:?}");
        let features: Vec<&str> = OptionalBlock::ALL.iter().map(|b| b.feature()).collect();
        for (feature, own, words) in OPTIONAL_BLOCK_NAMES {
            assert!(features.contains(&feature), "{feature}");
            let naming: Vec<&String> = files
                .iter()
                .filter(|file| !is_test(file) && !own.iter().any(|own| file.starts_with(own)))
                .filter(|file| {
                    let text = std::fs::read_to_string(root.join(file)).unwrap();
                    words.iter().any(|word| text.contains(word))
                })
                .collect();
            println!("{feature}: named outside its own files in {naming:?}");
            assert!(naming.len() <= 3, "{feature} is named in {naming:?}");
        }
        // Every optional block of the layout is in the table.
        for feature in features {
            assert!(OPTIONAL_BLOCK_NAMES.iter().any(|(f, _, _)| *f == feature));
        }
    }
}
