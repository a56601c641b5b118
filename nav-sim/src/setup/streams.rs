//! The registry of random streams: every random draw of a run comes from one ChaCha8 stream of
//! one seed, named here, so that no two draws share a stream and switching a model on or off
//! leaves every other draw unchanged.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A named random stream of a seed (its ChaCha8 stream id is [`Stream::id`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// Gyro angle random walk (white rate noise).
    GyroNoise,
    /// Gyro bias random walk.
    GyroBiasWalk,
    /// Accelerometer white noise.
    AccelNoise,
    /// Accelerometer bias random walk.
    AccelBiasWalk,
    /// Star-sensor white noise.
    Star,
    /// GNSS white position noise.
    Gnss,
    /// The receiver's correlated error (drawn only when that model is switched on, so a
    /// scenario without it gets the very same numbers as before the model existed).
    GnssCorrelated,
    /// GNSS velocity noise (drawn only when the receiver outputs velocity).
    GnssVelocity,
    /// The gyro bias instability (first-order Gauss–Markov bias; drawn only when it is on).
    GyroBiasInstability,
    /// The accelerometer bias instability (drawn only when it is on).
    AccelBiasInstability,
    /// The star tracker's slowly varying Gauss–Markov error (drawn only when it is on).
    StarSlowError,
    /// White noise of the star tracker's additional head `head` (≥ 1; head 0, `[star_sensor]`,
    /// draws from [`Stream::Star`]).
    AdditionalStarHead {
        /// The head's number, 1 for the first `[[star_sensor.additional_heads]]`.
        head: usize,
    },
    /// The slowly varying error of the additional head `head` (≥ 1; drawn only when it is on;
    /// head 0's is [`Stream::StarSlowError`]).
    AdditionalStarHeadSlowError {
        /// The head's number.
        head: usize,
    },
    /// The initial navigation error drawn from the filter's initial 1σ.
    InitialError,
    /// The sensor-error truth drawn from the filter's prior for a Monte Carlo run.
    TruthDraw,
    /// A `[dispersion]` entry, by its index in
    /// [`crate::scenario::dispersion::ENTRY_KEYS`].
    Dispersion {
        /// The entry's index.
        entry: usize,
    },
}

/// First ChaCha8 stream id of the `[dispersion]` entries.
pub const DISPERSION_STREAM_BASE: u64 = 200;
/// ChaCha8 stream id of head 0's white noise plus `head`: the additional heads' white noise
/// (ids 301..=307 for the at most
/// [`crate::scenario::star_sensor::MAX_STAR_HEADS`] heads).
pub const STAR_HEAD_STREAM_BASE: u64 = 300;
/// Likewise for the additional heads' slowly varying errors (ids 321..=327).
pub const STAR_HEAD_SLOW_ERROR_STREAM_BASE: u64 = 320;

impl Stream {
    /// The white-noise stream of star-tracker head `head` (0 = `[star_sensor]`).
    pub fn star_noise(head: usize) -> Self {
        match head {
            0 => Self::Star,
            head => Self::AdditionalStarHead { head },
        }
    }

    /// The slow-error stream of star-tracker head `head` (0 = `[star_sensor]`).
    pub fn star_slow_error(head: usize) -> Self {
        match head {
            0 => Self::StarSlowError,
            head => Self::AdditionalStarHeadSlowError { head },
        }
    }
}

impl Stream {
    /// The ChaCha8 stream id.
    pub fn id(self) -> u64 {
        match self {
            Self::GyroNoise => 1,
            Self::GyroBiasWalk => 2,
            Self::AccelNoise => 3,
            Self::AccelBiasWalk => 4,
            Self::Star => 5,
            Self::Gnss => 6,
            Self::GnssCorrelated => 7,
            Self::GnssVelocity => 8,
            Self::GyroBiasInstability => 9,
            Self::AccelBiasInstability => 10,
            Self::StarSlowError => 11,
            // Head numbers are below MAX_STAR_HEADS (validated), far inside u64.
            Self::AdditionalStarHead { head } => STAR_HEAD_STREAM_BASE + head as u64,
            Self::AdditionalStarHeadSlowError { head } => {
                STAR_HEAD_SLOW_ERROR_STREAM_BASE + head as u64
            }
            Self::InitialError => 100,
            Self::TruthDraw => 101,
            // Entry indices are below ENTRY_KEYS.len(), far inside u64.
            Self::Dispersion { entry } => DISPERSION_STREAM_BASE + entry as u64,
        }
    }
}

/// The generator of `stream` of `seed`.
pub fn rng(seed: u64, stream: Stream) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream.id());
    rng
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::dispersion::ENTRY_KEYS;
    use crate::scenario::star_sensor::MAX_STAR_HEADS;

    #[test]
    fn no_two_streams_share_an_id() {
        let mut streams = vec![
            Stream::GyroNoise,
            Stream::GyroBiasWalk,
            Stream::AccelNoise,
            Stream::AccelBiasWalk,
            Stream::Star,
            Stream::Gnss,
            Stream::GnssCorrelated,
            Stream::GnssVelocity,
            Stream::GyroBiasInstability,
            Stream::AccelBiasInstability,
            Stream::StarSlowError,
            Stream::InitialError,
            Stream::TruthDraw,
        ];
        streams.extend((0..ENTRY_KEYS.len()).map(|entry| Stream::Dispersion { entry }));
        streams.extend((1..MAX_STAR_HEADS).map(Stream::star_noise));
        streams.extend((1..MAX_STAR_HEADS).map(Stream::star_slow_error));
        let mut ids: Vec<u64> = streams.iter().map(|stream| stream.id()).collect();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), streams.len());
    }

    /// Head 0 keeps the streams the single tracker had, so a scenario without additional
    /// heads draws the very same numbers.
    #[test]
    fn head_zero_keeps_the_single_trackers_streams() {
        assert_eq!(Stream::star_noise(0).id(), 5);
        assert_eq!(Stream::star_slow_error(0).id(), 11);
        assert_eq!(Stream::star_noise(1).id(), 301);
        assert_eq!(Stream::star_slow_error(MAX_STAR_HEADS - 1).id(), 327);
        assert!(STAR_HEAD_STREAM_BASE + MAX_STAR_HEADS as u64 <= STAR_HEAD_SLOW_ERROR_STREAM_BASE);
        assert!(DISPERSION_STREAM_BASE + (ENTRY_KEYS.len() as u64) < STAR_HEAD_STREAM_BASE);
    }
}
