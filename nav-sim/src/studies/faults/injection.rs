//! How a fault is injected: the frame schedule of the scenario's IMU rate, the injector type
//! and its building blocks (the ports of a frame, star and GNSS measurement counters,
//! rotations), the correlated GNSS drift, and the manoeuvres inserted into a row's flight.

use nalgebra::Vector3;
use nav_core::attitude;
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::FramePorts;

use crate::scenario::{frames_in, ManoeuvreSegment, Scenario};

/// Frames of the scenario's IMU rate: the rows give their injection times in seconds from the
/// fault start, converted here to frame counts (a frame per IMU sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSchedule {
    rate_hz: f64,
    period_s: f64,
}

impl FrameSchedule {
    /// The schedule of `scenario`'s IMU rate (`imu.rate_hz`).
    pub fn of(scenario: &Scenario) -> Self {
        Self {
            rate_hz: scenario.imu.rate_hz,
            period_s: scenario.imu.frame_period_s(),
        }
    }

    /// IMU frames per second (Hz).
    pub fn rate_hz(self) -> f64 {
        self.rate_hz
    }

    /// The frame period (s).
    pub fn period_s(self) -> f64 {
        self.period_s
    }

    /// Frames in `seconds` (rounded to the nearest frame).
    pub fn frames(self, seconds: f64) -> i64 {
        frames_in(seconds, self.period_s) as i64
    }
}

/// The smallest positive subnormal, 4.9e-324.
pub(super) const SUBNORMAL: f64 = 4.9e-324;
/// NaN, +Inf, −Inf: the non-finite values injected in every field.
pub(super) const NON_FINITE: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

/// An injector: `inject(frame − fault_frame, ports)` on every frame.
pub type Injector = Box<dyn FnMut(i64, &mut FramePorts)>;

pub(super) fn imu(ports: &mut FramePorts) -> Option<&mut ImuSample> {
    ports.imu.0.as_mut()
}

/// Calls `corrupt(n, ports)` on each frame from the fault start that carries a star
/// measurement, `n` counting those frames from 0.
pub(super) fn on_star(mut corrupt: impl FnMut(u32, &mut FramePorts) + 'static) -> Injector {
    let mut n = 0;
    Box::new(move |relative, ports| {
        if relative >= 0 && !ports.star.0.is_empty() {
            corrupt(n, ports);
            n += 1;
        }
    })
}

/// As [`on_star`] for GNSS fixes.
pub(super) fn on_gnss(mut corrupt: impl FnMut(u32, &mut FramePorts) + 'static) -> Injector {
    let mut n = 0;
    Box::new(move |relative, ports| {
        if relative >= 0 && !ports.gnss.0.is_empty() {
            corrupt(n, ports);
            n += 1;
        }
    })
}

pub(super) fn star(ports: &mut FramePorts) -> Option<&mut StarMeasurement> {
    ports.star.0.front_mut()
}

pub(super) fn gnss(ports: &mut FramePorts) -> Option<&mut GnssFix> {
    ports.gnss.0.front_mut()
}

pub(super) fn both(mut a: Injector, mut b: Injector) -> Injector {
    Box::new(move |relative, ports| {
        a(relative, ports);
        b(relative, ports);
    })
}

/// The star measurement rotated by `angle_deg` about sensor axis `axis`.
pub(super) fn rotate_star(measurement: &mut StarMeasurement, axis: usize, angle_deg: f64) {
    let q = nav_fsw::ports::quaternion(&measurement.sensor_to_gcrf_wxyz);
    let mut rotation = Vector3::zeros();
    rotation[axis % 3] = angle_deg.to_radians();
    let r = attitude::product(&q, &attitude::exp_rotation_vector(&rotation));
    measurement.sensor_to_gcrf_wxyz = [r.w, r.i, r.j, r.k];
}

/// Non-finite values in IMU field `field` (0: Δθ, 1: Δv): NaN, +Inf, −Inf in x, y, z on
/// frames 0..9, then the smallest subnormal in x, y, z on frames 20..23.
pub(super) fn imu_field_injector(field: usize) -> Injector {
    Box::new(move |relative, ports| {
        let Some(sample) = imu(ports) else { return };
        let vector = if field == 0 {
            &mut sample.delta_angle_rad
        } else {
            &mut sample.delta_velocity_mps
        };
        match relative {
            0..9 => vector[(relative % 3) as usize] = NON_FINITE[(relative / 3) as usize],
            20..23 => *vector = [SUBNORMAL; 3],
            _ => {}
        }
    })
}

/// 1σ per axis of the injected GNSS drift (m).
pub(super) const DRIFT_SIGMA_M: f64 = 8.0;
/// Correlation time of the injected GNSS drift (s).
pub(super) const DRIFT_CORRELATION_TIME_S: f64 = 300.0;

/// A first-order Gauss–Markov error per axis, stationary from its first sample, advanced
/// exactly between the time tags it is asked for (seeded: every flight draws the same drift).
pub(super) struct GaussMarkovDrift {
    sigma_m: f64,
    correlation_time_s: f64,
    rng: rand_chacha::ChaCha8Rng,
    last: Option<(f64, [f64; 3])>,
}

impl GaussMarkovDrift {
    pub(super) fn new(sigma_m: f64, correlation_time_s: f64) -> Self {
        use rand::SeedableRng;
        Self {
            sigma_m,
            correlation_time_s,
            rng: rand_chacha::ChaCha8Rng::seed_from_u64(0x6e55),
            last: None,
        }
    }

    fn normal(&mut self) -> f64 {
        use rand_distr::Distribution;
        rand_distr::StandardNormal.sample(&mut self.rng)
    }

    /// The error at `time_s` (not before the previous time asked).
    pub(super) fn at(&mut self, time_s: f64) -> [f64; 3] {
        let error = match self.last {
            None => [0; 3].map(|_| self.sigma_m * self.normal()),
            Some((last_s, last)) => {
                let phi = (-(time_s - last_s).max(0.0) / self.correlation_time_s).exp();
                let walk = self.sigma_m * (1.0 - phi * phi).sqrt();
                last.map(|value| phi * value + walk * self.normal())
            }
        };
        self.last = Some((time_s, error));
        error
    }
}

/// A raised-cosine rotation (0.5 s ramps) at `rate_deg_s` for `duration_s`, no thrust.
pub(super) fn slew(duration_s: f64, rate_deg_s: [f64; 3]) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: "fault: slew".to_string(),
        duration_s,
        ramp_s: 0.5,
        body_rate_deg_per_s: rate_deg_s,
        specific_force_mps2: [0.0; 3],
    }
}

/// A raised-cosine thrust (0.5 s ramps) of `force_mps2` for `duration_s`, no rotation.
pub(super) fn thrust(duration_s: f64, force_mps2: [f64; 3]) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: "fault: thrust".to_string(),
        duration_s,
        ramp_s: 0.5,
        body_rate_deg_per_s: [0.0; 3],
        specific_force_mps2: force_mps2,
    }
}

/// Splits the constant segment running at `at_s` (from the scenario start) and inserts
/// `inserted` there; the flight grows by their length. A ramped segment at `at_s` is left
/// whole and the insertion follows it.
pub(super) fn insert_segments(scenario: &mut Scenario, at_s: f64, inserted: &[ManoeuvreSegment]) {
    let mut elapsed_s = 0.0;
    for index in 0..scenario.manoeuvres.len() {
        let segment = scenario.manoeuvres[index].clone();
        let end_s = elapsed_s + segment.duration_s;
        if end_s > at_s {
            let mut position = index + 1;
            if segment.ramp_s == 0.0 && at_s > elapsed_s {
                let mut first = segment.clone();
                first.duration_s = at_s - elapsed_s;
                let mut rest = segment;
                rest.duration_s = end_s - at_s;
                scenario.manoeuvres[index] = first;
                scenario.manoeuvres.insert(index + 1, rest);
            } else if segment.ramp_s == 0.0 {
                position = index;
            }
            for (offset, new) in inserted.iter().enumerate() {
                scenario.manoeuvres.insert(position + offset, new.clone());
            }
            return;
        }
        elapsed_s = end_s;
    }
    scenario.manoeuvres.extend_from_slice(inserted);
}
