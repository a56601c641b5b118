//! Truth and sensors together: the scenario's sensor-event stream, frame by frame.

use crate::scenario::Scenario;
use crate::sensors::{SensorError, SensorErrorTruth, SensorEvent, SensorSimulator};
use crate::truth::{FlightGravity, TruthError, TruthFrame, TruthSimulator};

/// Why a simulation could not be set up or advanced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulationError {
    /// The truth failed.
    #[error(transparent)]
    Truth(#[from] TruthError),
    /// The sensors failed.
    #[error(transparent)]
    Sensor(#[from] SensorError),
}

/// The scenario's truth trajectory and sensor models, advanced one IMU frame at a time.
pub struct Simulation {
    truth: TruthSimulator<FlightGravity>,
    sensors: SensorSimulator,
}

impl Simulation {
    /// Sets up truth and sensors for a (validated) scenario.
    ///
    /// # Errors
    /// [`SimulationError`] if nav-core refuses the launch site or the initial state.
    pub fn new(scenario: &Scenario) -> Result<Self, SimulationError> {
        Ok(Self {
            truth: TruthSimulator::from_scenario(scenario)?,
            sensors: SensorSimulator::new(scenario)?,
        })
    }

    /// The truth simulator (current state, profile, frame count).
    pub fn truth(&self) -> &TruthSimulator<FlightGravity> {
        &self.truth
    }

    /// The true sensor errors now.
    pub fn error_truth(&self) -> SensorErrorTruth {
        self.sensors.error_truth()
    }

    /// Advances one frame: returns its truth and appends the frame's sensor events to `events`
    /// (not cleared first). `Ok(None)` at the end of the scenario.
    ///
    /// # Errors
    /// [`SimulationError`] from the truth or the sensors.
    pub fn step(
        &mut self,
        events: &mut Vec<SensorEvent>,
    ) -> Result<Option<TruthFrame>, SimulationError> {
        let Some(frame) = self.truth.next_frame()? else {
            return Ok(None);
        };
        self.sensors.process_frame(&frame, events)?;
        Ok(Some(frame))
    }

    /// Runs to the end and returns every sensor event in delivery order.
    ///
    /// # Errors
    /// As [`Simulation::step`].
    pub fn event_stream(mut self) -> Result<Vec<SensorEvent>, SimulationError> {
        let mut events = Vec::new();
        while self.step(&mut events)?.is_some() {}
        Ok(events)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_scenario_stream_has_the_expected_counts_and_order() {
        let scenario = Scenario::default_scenario().unwrap();
        let events = Simulation::new(&scenario).unwrap().event_stream().unwrap();
        let count = |wanted: fn(&SensorEvent) -> bool| events.iter().filter(|e| wanted(e)).count();
        // 226 s: 113,000 IMU frames, 904 star samples (4 Hz), 226 GNSS fixes (1 Hz).
        assert_eq!(count(|e| matches!(e, SensorEvent::Imu { .. })), 113_000);
        assert_eq!(count(|e| matches!(e, SensorEvent::Star { .. })), 904);
        assert_eq!(count(|e| matches!(e, SensorEvent::Gnss { .. })), 226);
        assert!(events
            .windows(2)
            .all(|pair| pair[0].delivery_time_s() <= pair[1].delivery_time_s()));
        let last_time_s = events.last().unwrap().delivery_time_s();
        assert!(
            (last_time_s - (600.0 + 226.0)).abs() < 1e-9,
            "{last_time_s}"
        );
    }
}
