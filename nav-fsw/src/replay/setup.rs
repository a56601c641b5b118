//! The replay setup: what a scenario decides about the flight software, as 8-byte words, in
//! the order the parameter table gives ([`Param::word`]).

use nalgebra::{Quaternion, Vector3};
use nav_core::strapdown::NavigationState;

use super::{FrameGrid, DEFAULT_MAX_GAP_S};
use crate::config::{FswConfig, Param};
use crate::error::{ConfigField, FswError};

/// Number of words of a [`ReplaySetup`].
pub const SETUP_WORDS: usize = 79;
/// First word of an encoded setup (`"NAVSETUP"` little-endian).
pub const SETUP_MAGIC: u64 = u64::from_le_bytes(*b"NAVSETUP");

/// Words of the initial navigation solution: attitude `[w, x, y, z]`, position, velocity
/// (launch-inertial, m and m/s) and time (s); every other word after the magic is a
/// parameter's ([`Param::word`], docs/reference/flight-parameters.md).
pub const INITIAL_NAVIGATION_WORDS: core::ops::Range<usize> = 19..30;

/// What a scenario decides about the flight software and its initial navigation solution.
/// Only the parameters with a replay-setup word ([`Param::word`]) travel; every other one is
/// its default ([`FswConfig::paper_defaults`]), so a setup is exactly what its words give.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySetup {
    config: FswConfig,
    /// Initial navigation solution.
    pub initial: NavigationState,
}

impl ReplaySetup {
    /// The setup of `config`'s parameters that have a replay-setup word (every other one
    /// takes its default) and the initial solution `initial`.
    pub fn new(config: &FswConfig, initial: NavigationState) -> Self {
        let mut carried = FswConfig::table_defaults();
        for param in Param::ALL {
            if param.word().is_some() {
                // The value comes from a configuration of the same type: it always decodes.
                let _ = param.set_word(&mut carried, param.to_word(config));
            }
        }
        Self {
            config: carried,
            initial,
        }
    }

    /// The flight software configuration.
    pub fn config(&self) -> FswConfig {
        self.config
    }

    /// The frames a replay with this setup runs: from the initial solution's time at the IMU
    /// period, with the flight software's IMU period tolerance and [`DEFAULT_MAX_GAP_S`].
    pub fn frame_grid(&self) -> FrameGrid {
        FrameGrid {
            start_time_s: self.initial.time_s,
            period_s: self.config.imu.period_s,
            tolerance: self.config.imu.period_tolerance,
            max_gap_s: DEFAULT_MAX_GAP_S,
        }
    }

    /// The initial solution's values in [`INITIAL_NAVIGATION_WORDS`] order.
    fn initial_values(&self) -> [f64; 11] {
        let (q, p, v) = (
            &self.initial.attitude,
            &self.initial.position_m,
            &self.initial.velocity_mps,
        );
        [
            q.w,
            q.i,
            q.j,
            q.k,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            self.initial.time_s,
        ]
    }

    /// The setup as words: [`SETUP_MAGIC`], each parameter in its word ([`Param::word`]; an
    /// `f64` by its bits, a count or a choice by its value) and the initial solution in
    /// [`INITIAL_NAVIGATION_WORDS`]. Without a second head its words are 0.
    pub fn to_words(&self) -> [u64; SETUP_WORDS] {
        let mut words = [0_u64; SETUP_WORDS];
        words[0] = SETUP_MAGIC;
        let initial = words.get_mut(INITIAL_NAVIGATION_WORDS).unwrap_or_default();
        for (slot, value) in initial.iter_mut().zip(self.initial_values()) {
            *slot = value.to_bits();
        }
        for param in Param::ALL {
            if let Some(slot) = param.word().and_then(|index| words.get_mut(index)) {
                *slot = param.to_word(&self.config);
            }
        }
        words
    }

    /// The setup from words.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`]: `Parameter` naming a parameter whose word is no
    /// value of its type (a count beyond it, a flag neither 0 nor 1); `InitialNavigation`
    /// for a bad magic or words that are not the one encoding of their setup (a second
    /// head's word not zero without a second head). The values themselves are checked by
    /// [`crate::scheduler::NavigationComputer::new`].
    pub fn from_words(words: &[u64; SETUP_WORDS]) -> Result<Self, FswError> {
        let bad = FswError::InvalidConfiguration(ConfigField::InitialNavigation);
        if words[0] != SETUP_MAGIC {
            return Err(bad);
        }
        let mut config = FswConfig::table_defaults();
        for param in Param::ALL {
            if let Some(word) = param.word().and_then(|index| words.get(index)) {
                param.set_word(&mut config, *word)?;
            }
        }
        let mut initial = [0.0; 11];
        let initial_words = words.get(INITIAL_NAVIGATION_WORDS).unwrap_or_default();
        for (value, word) in initial.iter_mut().zip(initial_words) {
            *value = f64::from_bits(*word);
        }
        let [qw, qx, qy, qz, px, py, pz, vx, vy, vz, time_s] = initial;
        let setup = Self {
            config,
            initial: NavigationState {
                attitude: Quaternion::new(qw, qx, qy, qz),
                position_m: Vector3::new(px, py, pz),
                velocity_mps: Vector3::new(vx, vy, vz),
                time_s,
            },
        };
        // One setup, one encoding: a second head's words without a second head are refused.
        if setup.to_words() != *words {
            return Err(bad);
        }
        Ok(setup)
    }
}
