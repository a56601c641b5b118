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

/// What a scenario decides about the flight software and its initial navigation solution, as
/// its words. Only the parameters with a replay-setup word ([`Param::word`]) travel; every
/// other one is its default ([`FswConfig::paper_defaults`]), so a setup is exactly what its
/// words give. The setup keeps the checked words and decodes the configuration when asked
/// ([`Self::config`]), so reading a setup on the target holds no configuration on the stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySetup {
    words: [u64; SETUP_WORDS],
    /// Initial navigation solution.
    pub initial: NavigationState,
}

impl ReplaySetup {
    /// The setup of `config`'s parameters that have a replay-setup word (every other one
    /// takes its default) and the initial solution `initial`.
    pub fn new(config: &FswConfig, initial: NavigationState) -> Self {
        let mut words = [0_u64; SETUP_WORDS];
        words[0] = SETUP_MAGIC;
        let (q, p, v) = (
            &initial.attitude,
            &initial.position_m,
            &initial.velocity_mps,
        );
        let values = [
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
            initial.time_s,
        ];
        let slots = words.get_mut(INITIAL_NAVIGATION_WORDS).unwrap_or_default();
        for (slot, value) in slots.iter_mut().zip(values) {
            *slot = value.to_bits();
        }
        for param in Param::ALL {
            if let Some(slot) = param.word().and_then(|index| words.get_mut(index)) {
                *slot = param.to_word(config);
            }
        }
        Self { words, initial }
    }

    /// The flight software configuration: the defaults with every carried parameter. Not
    /// inlined: the decoding's temporaries leave start-up's stack before the computer is
    /// built.
    #[inline(never)]
    pub fn config(&self) -> FswConfig {
        let frames = crate::sensor_frames::SensorFrames::ALIGNED;
        let mut config = FswConfig::paper_defaults(crate::config::ZERO_SITE, frames);
        for param in Param::ALL {
            if let Some(word) = self.word(*param) {
                // Every word decodes: `from_words` and `new` made it so.
                let _ = param.set_word(&mut config, word);
            }
        }
        config
    }

    /// The parameter's word, `None` for a parameter not carried.
    fn word(&self, param: Param) -> Option<u64> {
        param
            .word()
            .and_then(|index| self.words.get(index))
            .copied()
    }

    /// The parameter's value: its word's, else its default (NaN for a value the mission
    /// gives, which every such parameter carries).
    fn number(&self, param: Param) -> f64 {
        self.word(param).map_or_else(
            || param.default_value().unwrap_or(f64::NAN),
            |word| param.word_number(word).unwrap_or(f64::NAN),
        )
    }

    /// The frames a replay with this setup runs: from the initial solution's time at the IMU
    /// period, with the flight software's IMU period tolerance and [`DEFAULT_MAX_GAP_S`].
    pub fn frame_grid(&self) -> FrameGrid {
        FrameGrid {
            start_time_s: self.initial.time_s,
            period_s: self.number(Param::ImuPeriod),
            tolerance: self.number(Param::ImuPeriodTolerance),
            max_gap_s: DEFAULT_MAX_GAP_S,
        }
    }

    /// The setup as words: [`SETUP_MAGIC`], each carried parameter in its word
    /// ([`Param::word`]; an `f64` by its bits, a count or a choice by its value) and the
    /// initial solution in [`INITIAL_NAVIGATION_WORDS`]. Without a second head its words
    /// are 0.
    pub fn to_words(&self) -> [u64; SETUP_WORDS] {
        self.words
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
        let word_of = |param: Param| param.word().and_then(|index| words.get(index)).copied();
        for param in Param::ALL {
            let Some(word) = word_of(*param) else {
                continue;
            };
            if !param.decodes(word) {
                return Err(FswError::InvalidConfiguration(ConfigField::Parameter(
                    *param,
                )));
            }
            // One setup, one encoding: a parameter that does not apply (a second head's
            // without a second head) has the word 0.
            let off = param
                .condition()
                .is_some_and(|flag| word_of(flag) == Some(0));
            if off && word != 0 {
                return Err(bad);
            }
        }
        let mut initial = [0.0; 11];
        let initial_words = words.get(INITIAL_NAVIGATION_WORDS).unwrap_or_default();
        for (value, word) in initial.iter_mut().zip(initial_words) {
            *value = f64::from_bits(*word);
        }
        let [qw, qx, qy, qz, px, py, pz, vx, vy, vz, time_s] = initial;
        Ok(Self {
            words: *words,
            initial: NavigationState {
                attitude: Quaternion::new(qw, qx, qy, qz),
                position_m: Vector3::new(px, py, pz),
                velocity_mps: Vector3::new(vx, vy, vz),
                time_s,
            },
        })
    }
}
