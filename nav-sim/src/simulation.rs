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

    /// Cross-check of truth, sensor model and flight code: with the noise off, the flight
    /// strapdown fed the measured increments and the exact sensor-error corrections must fly
    /// the truth trajectory; only its own algorithm error (two-sample coning/sculling,
    /// trapezoidal position, midpoint gravity) remains. Proves the increment conventions
    /// (Δθ = ∫ω_b, Δv = ∫f_b, time tags at frame ends) and the error-model inverse agree.
    #[test]
    fn flight_strapdown_on_noise_free_measurements_follows_the_truth() {
        use nav_core::strapdown::{
            ImuIncrement, NavigationState, SensorCorrections, Strapdown, StrapdownConfig,
        };
        let mut scenario = Scenario::default_scenario().unwrap();
        scenario.gyro.rate_noise_density_deg_per_h_per_sqrt_hz = 0.0;
        scenario.accelerometer.noise_per_sample_mps2 = 0.0;
        let mut simulation = Simulation::new(&scenario).unwrap();
        let frame = crate::truth::launch_frame(&scenario).unwrap();
        let initial = *simulation.truth().state();
        let errors = simulation.error_truth();
        let corrections = SensorCorrections {
            gyro_bias_rad_s: errors.gyro_bias_rad_per_s,
            accel_bias_mps2: errors.accel_bias_mps2,
            gyro_scale_factor: errors.gyro_scale_factor,
            accel_scale_factor: errors.accel_scale_factor,
        };
        let mut navigation = NavigationState {
            attitude: initial.attitude_q_ib,
            position_m: initial.position_m,
            velocity_mps: initial.velocity_mps,
            time_s: initial.time_s,
        };
        let mut strapdown = Strapdown::new(StrapdownConfig::default());
        let mut events = Vec::new();
        let (mut worst_attitude_rad, mut worst_position_m, mut worst_velocity_mps) =
            (0.0_f64, 0.0_f64, 0.0_f64);
        let mut worst_time_s = 0.0_f64;
        while let Some(truth) = simulation.step(&mut events).unwrap() {
            for event in events.drain(..) {
                if let SensorEvent::Imu {
                    delta_angle_rad,
                    delta_velocity_mps,
                    interval_s,
                    ..
                } = event
                {
                    let increment = ImuIncrement {
                        delta_angle_rad,
                        delta_velocity_mps,
                        interval_s,
                    };
                    strapdown
                        .step(&mut navigation, &increment, &corrections, &frame)
                        .unwrap();
                }
            }
            let attitude_error = nav_core::attitude::canonical(
                &(truth.attitude_q_ib.conjugate() * navigation.attitude),
            );
            worst_attitude_rad = worst_attitude_rad.max(2.0 * attitude_error.imag().norm());
            worst_position_m =
                worst_position_m.max((navigation.position_m - truth.position_m).norm());
            worst_velocity_mps =
                worst_velocity_mps.max((navigation.velocity_mps - truth.velocity_mps).norm());
            worst_time_s = worst_time_s.max((navigation.time_s - truth.time_s).abs());
        }
        println!(
            "strapdown vs truth over 226 s: attitude {worst_attitude_rad:.3e} rad, \
             position {worst_position_m:.3e} m, velocity {worst_velocity_mps:.3e} m/s, \
             time tag {worst_time_s:.3e} s"
        );
        // Measured: attitude 3.2e-13 rad, position 1.7e-5 m, velocity 2.0e-9 m/s; the time tag
        // differs by 5.3e-9 s because the strapdown sums T while the truth computes t0 + kT.
        // (Without the bias correction the position error would be ~ ½ |b_a| t² = 96 m.)
        assert!(worst_attitude_rad < 1e-11);
        assert!(worst_position_m < 1e-3);
        assert!(worst_velocity_mps < 1e-7);
        assert!(worst_time_s < 1e-7);
    }
}
