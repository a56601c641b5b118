//! Replay: a recorded sensor log fed to the flight software frame by frame, identically on
//! the host and on the target, with a fixed-layout output record per frame so the two can be
//! compared bit for bit.
//!
//! * [`FramePorts`]: the port contents of one frame (the IMU sample and the measurements
//!   delivered with it); the simulator fills them live, the replay from the log.
//! * [`FrameAssembler`]: places the log's records (`crate::log_record`, delivery order) in
//!   frames by their own times on the [`FrameGrid`] the setup defines: an IMU record in the
//!   frame it ends, a measurement in the frame it arrives by. A frame the log has no IMU
//!   record for runs without one (the flight software holds and counts it, as live), a second
//!   IMU record for a frame is dropped and counted, and a log at another IMU rate, on another
//!   time base or with a jump longer than [`FrameGrid::max_gap_s`] is refused.
//! * [`ReplaySetup`]: what a scenario decides about the flight software (launch site, initial
//!   navigation solution, filter, noise, gates), as 8-byte words, so the target builds the
//!   very configuration the host built ([`ReplaySetup::config`]).
//! * [`output_words`]: the frame's output record, [`OUTPUT_WORDS`] little-endian 8-byte
//!   words named by [`OUTPUT_FIELD_NAMES`] (floats as their bit patterns).
//!
//! One file per job: `assembler.rs` (the frame grid and assembler), `setup.rs` (the setup
//! words), `output.rs` (the output record); the ports of one frame are here.

mod assembler;
mod output;
mod setup;

pub use assembler::{
    AssemblyCounts, FrameAssembler, FrameAssemblyError, FrameGrid, DEFAULT_MAX_GAP_S,
    MAX_GAP_FRAMES,
};
pub use output::{
    optional_state_words, output_words, GNSS_ERROR_BLOCK_BIT, IMU_ERROR_BLOCK_BIT,
    OPTIONAL_STATE_WORDS, OUTPUT_FIELD_NAMES, OUTPUT_WORDS,
};
pub use setup::{ReplaySetup, INITIAL_NAVIGATION_WORDS, SETUP_MAGIC, SETUP_WORDS};

use heapless::Deque;

use crate::log_record::LogRecord;
use crate::ports::{GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};
use crate::scheduler::NavigationComputer;
use crate::telemetry::FrameTelemetry;

/// Most star measurements one frame can carry (more are counted as dropped).
pub const FRAME_STAR_CAPACITY: usize = 8;
/// Most GNSS fixes one frame can carry.
pub const FRAME_GNSS_CAPACITY: usize = 4;

/// The IMU port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameImu(pub Option<ImuSample>);

impl ImuPort for FrameImu {
    fn read(&mut self) -> Option<ImuSample> {
        self.0.take()
    }
}

/// The star-sensor port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameStar(pub Deque<StarMeasurement, FRAME_STAR_CAPACITY>);

impl StarSensorPort for FrameStar {
    fn poll(&mut self) -> Option<StarMeasurement> {
        self.0.pop_front()
    }
}

/// The GNSS port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameGnss(pub Deque<GnssFix, FRAME_GNSS_CAPACITY>);

impl GnssPort for FrameGnss {
    fn poll(&mut self) -> Option<GnssFix> {
        self.0.pop_front()
    }
}

/// What the ports hold for one frame.
#[derive(Debug, Clone, Default)]
pub struct FramePorts {
    /// The IMU sample.
    pub imu: FrameImu,
    /// Star measurements delivered in the frame.
    pub star: FrameStar,
    /// GNSS fixes delivered in the frame.
    pub gnss: FrameGnss,
    /// Measurements that did not fit the frame's capacity (lost, counted here).
    pub dropped: u32,
}

impl FramePorts {
    /// Adds a record's content to the frame (an IMU record replaces the sample).
    pub fn add(&mut self, record: &LogRecord) {
        let refused = match record {
            LogRecord::Imu(imu) => {
                self.imu.0 = Some(imu.to_imu_sample());
                false
            }
            LogRecord::Star(star) => self.star.0.push_back(star.to_star_measurement()).is_err(),
            LogRecord::Gnss(gnss) => self.gnss.0.push_back(gnss.to_gnss_fix()).is_err(),
        };
        if refused {
            self.dropped = self.dropped.saturating_add(1);
        }
    }

    /// Star measurements and GNSS fixes the frame's ports hold.
    pub fn measurements(&self) -> u32 {
        let held = self.star.0.len().saturating_add(self.gnss.0.len());
        u32::try_from(held).unwrap_or(u32::MAX)
    }

    /// Runs the frame on `computer`.
    pub fn run(&mut self, computer: &mut NavigationComputer) -> FrameTelemetry {
        computer.run_frame(&mut self.imu, &mut self.star, &mut self.gnss)
    }
}

#[cfg(test)]
mod tests;
