//! The truth trajectory at IMU frame boundaries, and the two fields sampled along it.
//!
//! Times are kept as whole frame counts `n` from the scenario start (`t_n = t_0 + nT`), so
//! the sample and refresh instants are exact integers, not rounded quotients of times.

use nalgebra::Vector3;

use super::OmissionError;
use crate::scenario::Scenario;
use crate::setup::launch::Launch;
use crate::world::gravity::RotatingRemainder;
use crate::world::truth::TruthSimulator;

/// The truth's positions at every `stride`-th frame boundary, from the scenario start.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Scenario start `t_0` (s).
    start_time_s: f64,
    /// IMU frame period `T` (s).
    frame_period_s: f64,
    /// Frames between two stored positions.
    stride: u64,
    /// Launch-inertial position at boundary `k·stride` (m).
    positions_m: Vec<Vector3<f64>>,
}

impl Trajectory {
    /// Time of frame boundary `n` (s), computed without accumulating rounding, as the truth
    /// computes its frame times.
    fn time_s(&self, boundary: u64) -> f64 {
        // Whole-frame counts below 2^53 are exact in f64.
        self.start_time_s + boundary as f64 * self.frame_period_s
    }

    /// Position at frame boundary `n`, a multiple of the stride within the flight.
    fn position_m(&self, boundary: u64) -> Option<&Vector3<f64>> {
        let index = usize::try_from(boundary / self.stride).ok()?;
        self.positions_m.get(index)
    }

    /// The smallest geocentric radius of the stored positions (m).
    pub fn lowest_radius_m(&self, launch: &Launch) -> f64 {
        self.positions_m
            .iter()
            .map(|position| launch.frame.geocentric_position_launch(position).norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// The geocentric radius at every `sample_frames`-th boundary (m), as the samples of
    /// [`truth_remainder`] are taken.
    pub fn sample_radii_m(&self, sample_frames: u64, launch: &Launch) -> Vec<f64> {
        self.samples(sample_frames)
            .map(|boundary| {
                self.position_m(boundary).map_or(f64::NAN, |position| {
                    launch.frame.geocentric_position_launch(position).norm()
                })
            })
            .collect()
    }

    /// The last frame boundary stored.
    fn last_boundary(&self) -> u64 {
        (self.positions_m.len().saturating_sub(1) as u64) * self.stride
    }

    /// The sampled boundaries `0, s, 2s, …` within the flight.
    fn samples(&self, sample_frames: u64) -> impl Iterator<Item = u64> {
        let last = self.last_boundary();
        (0..=last / sample_frames).map(move |k| k * sample_frames)
    }
}

/// Flies the scenario's truth (its own field, `[gravity]` included) and keeps the position at
/// every `stride`-th frame boundary, the initial state first.
///
/// # Errors
/// [`OmissionError::Truth`] if the truth cannot be set up or flown.
pub fn fly(scenario: &Scenario, launch: &Launch, stride: u64) -> Result<Trajectory, OmissionError> {
    let mut truth = TruthSimulator::from_launch(scenario, launch)?;
    let stride = stride.max(1);
    let capacity = usize::try_from(truth.frame_count() / stride + 1).unwrap_or(0);
    let mut positions_m = Vec::with_capacity(capacity);
    positions_m.push(truth.state().position_m);
    while let Some(frame) = truth.next_frame()? {
        // Frame k ends at boundary k + 1.
        if (frame.frame_index + 1) % stride == 0 {
            positions_m.push(frame.position_m);
        }
    }
    Ok(Trajectory {
        start_time_s: launch.truth_start.time_s,
        frame_period_s: scenario.imu.frame_period_s(),
        stride,
        positions_m,
    })
}

/// `δg_truth(t_n, p_n)` at every `sample_frames`-th boundary, in full (not the truth's
/// Taylor model, whose error is below 1e-9 m/s²); zero without a published model.
///
/// # Errors
/// [`OmissionError::Field`] if an evaluation fails.
pub fn truth_remainder(
    path: &Trajectory,
    sample_frames: u64,
    remainder: Option<&RotatingRemainder>,
) -> Result<Vec<Vector3<f64>>, OmissionError> {
    path.samples(sample_frames)
        .map(|boundary| evaluate(path, remainder, boundary))
        .collect()
}

/// The flight's field as it holds it: evaluated at refresh boundaries, used until the next
/// one, `latency_refreshes` refreshes late.
#[derive(Debug, Clone, Copy)]
pub struct HeldField<'a> {
    /// The flight's remainder, `None` for `J2` alone.
    pub remainder: Option<&'a RotatingRemainder>,
    /// Frames between refreshes `R`.
    pub refresh_frames: u64,
    /// How many refreshes old the value in use is.
    pub latency_refreshes: u64,
}

impl HeldField<'_> {
    /// The refresh boundary whose value is in use at boundary `n`:
    /// `R·max(⌊n/R⌋ − latency, 0)` (before the flight's first refreshes, the value at the
    /// start).
    pub(super) fn source(&self, boundary: u64) -> u64 {
        (boundary / self.refresh_frames).saturating_sub(self.latency_refreshes)
            * self.refresh_frames
    }
}

/// `δg_flight` at every `sample_frames`-th boundary: the held value (module docs of the
/// study), each refresh evaluated once.
///
/// # Errors
/// [`OmissionError::Field`] if an evaluation fails.
pub fn flight_remainder(
    path: &Trajectory,
    sample_frames: u64,
    held: &HeldField<'_>,
) -> Result<Vec<Vector3<f64>>, OmissionError> {
    let mut last: Option<(u64, Vector3<f64>)> = None;
    let mut values = Vec::new();
    for boundary in path.samples(sample_frames) {
        let source = held.source(boundary);
        let value = match last {
            Some((cached, value)) if cached == source => value,
            _ => evaluate(path, held.remainder, source)?,
        };
        last = Some((source, value));
        values.push(value);
    }
    Ok(values)
}

/// `remainder` at frame boundary `n` (zero for `None`).
fn evaluate(
    path: &Trajectory,
    remainder: Option<&RotatingRemainder>,
    boundary: u64,
) -> Result<Vector3<f64>, OmissionError> {
    let time_s = path.time_s(boundary);
    let Some(remainder) = remainder else {
        return Ok(Vector3::zeros());
    };
    let position_m = path
        .position_m(boundary)
        .ok_or_else(|| OmissionError::Field {
            time_s,
            reason: format!("no truth position stored at frame boundary {boundary}"),
        })?;
    remainder
        .acceleration_mps2(time_s, position_m)
        .map_err(|reason| OmissionError::Field { time_s, reason })
}
