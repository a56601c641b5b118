//! The draws of a scenario's `[dispersion]` table ([`crate::scenario::dispersion`]) for one
//! Monte Carlo run (`docs/guide/monte-carlo.md`, "Dispersions").
//!
//! Every entry changes what the simulated vehicle and sensors do, never what the flight
//! software is configured with, so a dispersion is a model mismatch the campaign measures.
//! Each entry draws from its own random stream of the run's seed
//! ([`Stream::Dispersion`] with the entry's index in
//! [`ENTRY_KEYS`](crate::scenario::dispersion::ENTRY_KEYS)): a run's draws depend
//! only on its seed and the table, so run k alone reproduces run k of a campaign, and adding
//! or removing one entry leaves the others' draws unchanged.

use nalgebra::Vector3;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution as _, StandardNormal};

use crate::scenario::dispersion::{
    Dispersion, Distribution, GNSS_LATENCY_ENTRY, LAUNCH_LONGITUDE_ENTRY,
    MIN_CORRELATION_TIME_FACTOR,
};
use crate::scenario::Scenario;
use crate::setup::streams::{self, Stream};

/// The values one run draws, in the entries' units (zero for an absent entry).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Draw {
    /// Added initial attitude error (deg).
    pub initial_attitude_deg: [f64; 3],
    /// Added initial position error (m).
    pub initial_position_m: [f64; 3],
    /// Added initial velocity error (m/s).
    pub initial_velocity_mps: [f64; 3],
    /// Gyro noise change (%).
    pub gyro_noise_percent: f64,
    /// Accelerometer noise change (%).
    pub accelerometer_noise_percent: f64,
    /// Star-sensor noise change (%).
    pub star_noise_percent: f64,
    /// GNSS white noise change (%).
    pub gnss_noise_percent: f64,
    /// Added star mounting rotation (deg).
    pub star_mounting_deg: [f64; 3],
    /// GNSS correlated 1σ change (%).
    pub gnss_correlated_sigma_percent: f64,
    /// GNSS correlation time change (%).
    pub gnss_correlation_time_percent: f64,
    /// Added GNSS latency (IMU frames).
    pub gnss_latency_frames: u32,
    /// Added gyro misalignment terms `a01, a02, a10, a12, a20, a21` (rad).
    pub gyro_misalignment_rad: [f64; 6],
    /// Added accelerometer misalignment terms, same order (rad).
    pub accelerometer_misalignment_rad: [f64; 6],
    /// Added gyro g-sensitivity per axis (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: [f64; 3],
    /// Turn of the flight about the Earth's axis (deg, east).
    pub launch_longitude_deg: f64,
}

/// The off-diagonal `(row, column)` pairs of a misalignment matrix, in draw order.
pub const OFF_DIAGONAL: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

fn stream(seed: u64, entry: usize) -> ChaCha8Rng {
    streams::rng(seed, Stream::Dispersion { entry })
}

/// One draw from `distribution`.
fn sample(distribution: &Distribution, rng: &mut ChaCha8Rng) -> f64 {
    match *distribution {
        Distribution::Normal { sigma } => {
            let normal: f64 = StandardNormal.sample(rng);
            normal * sigma
        }
        Distribution::Uniform { half_width } => {
            let unit: f64 = rng.random_range(-1.0..=1.0);
            unit * half_width
        }
    }
}

fn draw3(distribution: Option<&Distribution>, seed: u64, entry: usize) -> [f64; 3] {
    distribution.map_or([0.0; 3], |distribution| {
        let mut rng = stream(seed, entry);
        [0; 3].map(|_| sample(distribution, &mut rng))
    })
}

fn draw6(distribution: Option<&Distribution>, seed: u64, entry: usize) -> [f64; 6] {
    distribution.map_or([0.0; 6], |distribution| {
        let mut rng = stream(seed, entry);
        [0; 6].map(|_| sample(distribution, &mut rng))
    })
}

fn draw1(distribution: Option<&Distribution>, seed: u64, entry: usize) -> f64 {
    distribution.map_or(0.0, |distribution| {
        sample(distribution, &mut stream(seed, entry))
    })
}

/// The values the run with `seed` draws from `dispersion`.
pub fn draw(dispersion: &Dispersion, seed: u64) -> Draw {
    Draw {
        initial_attitude_deg: draw3(dispersion.initial_attitude_deg.as_ref(), seed, 0),
        initial_position_m: draw3(dispersion.initial_position_m.as_ref(), seed, 1),
        initial_velocity_mps: draw3(dispersion.initial_velocity_mps.as_ref(), seed, 2),
        gyro_noise_percent: draw1(dispersion.gyro_noise_percent.as_ref(), seed, 3),
        accelerometer_noise_percent: draw1(
            dispersion.accelerometer_noise_percent.as_ref(),
            seed,
            4,
        ),
        star_noise_percent: draw1(dispersion.star_noise_percent.as_ref(), seed, 5),
        gnss_noise_percent: draw1(dispersion.gnss_noise_percent.as_ref(), seed, 6),
        star_mounting_deg: draw3(dispersion.star_mounting_deg.as_ref(), seed, 7),
        gnss_correlated_sigma_percent: draw1(
            dispersion.gnss_correlated_sigma_percent.as_ref(),
            seed,
            8,
        ),
        gnss_correlation_time_percent: draw1(
            dispersion.gnss_correlation_time_percent.as_ref(),
            seed,
            9,
        ),
        gnss_latency_frames: dispersion.gnss_latency_frames.map_or(0, |frames| {
            stream(seed, GNSS_LATENCY_ENTRY).random_range(0..=frames)
        }),
        gyro_misalignment_rad: draw6(dispersion.gyro_misalignment_rad.as_ref(), seed, 11),
        accelerometer_misalignment_rad: draw6(
            dispersion.accelerometer_misalignment_rad.as_ref(),
            seed,
            12,
        ),
        gyro_g_sensitivity_rad_s_per_mps2: draw3(
            dispersion.gyro_g_sensitivity_rad_s_per_mps2.as_ref(),
            seed,
            13,
        ),
        launch_longitude_deg: draw1(
            dispersion.launch_longitude_deg.as_ref(),
            seed,
            LAUNCH_LONGITUDE_ENTRY,
        ),
    }
}

/// The mission of the run with `seed`: `scenario` turned about the Earth's axis by the drawn
/// `launch_longitude_deg` (the site's longitude and the orbit's node, which is measured in the
/// frame that is Earth-fixed at the launch epoch, both move east by it), or `scenario`
/// unchanged without that entry. Both the truth and the flight software's configuration are
/// made from the turned scenario: the flight in the launch frame is the same, its ground track
/// and the gravity field along it another.
pub fn mission_scenario(scenario: &Scenario, seed: u64) -> Scenario {
    let Some(distribution) = scenario
        .dispersion
        .as_ref()
        .and_then(|dispersion| dispersion.launch_longitude_deg.as_ref())
    else {
        return scenario.clone();
    };
    turned(
        scenario,
        draw1(Some(distribution), seed, LAUNCH_LONGITUDE_ENTRY),
    )
}

/// `scenario` turned east about the Earth's axis by `turn_deg`: the launch site's longitude
/// and the orbit's node (measured in the frame that is Earth-fixed at the launch epoch) both
/// move by it, wrapped to `[−180°, 180°)` and `[0°, 360°)`.
pub fn turned(scenario: &Scenario, turn_deg: f64) -> Scenario {
    let mut mission = scenario.clone();
    let site = &mut mission.launch_site;
    site.longitude_deg = (site.longitude_deg + turn_deg + 180.0).rem_euclid(360.0) - 180.0;
    let orbit = &mut mission.initial_orbit;
    orbit.right_ascension_of_node_deg =
        (orbit.right_ascension_of_node_deg + turn_deg).rem_euclid(360.0);
    mission
}

/// `1 + percent / 100`, at least `floor`: a noise level cannot fall below zero.
fn factor(percent: f64, floor: f64) -> f64 {
    (1.0 + percent / 100.0).max(floor)
}

/// The truth side of the run with `seed`: `scenario` (already seeded for the run) with the
/// drawn noise levels, star mounting, correlated GNSS error, latency, IMU misalignments and
/// gyro g-sensitivity. The flight software's
/// configuration is made from the undispersed scenario, so these are model mismatches. Without
/// a `[dispersion]` table the scenario is returned unchanged.
pub fn truth_scenario(scenario: &Scenario, seed: u64) -> Scenario {
    let mut truth = scenario.clone();
    let Some(dispersion) = &scenario.dispersion else {
        return truth;
    };
    let draw = draw(dispersion, seed);
    truth.gyro.rate_noise_density_deg_per_h_per_sqrt_hz *= factor(draw.gyro_noise_percent, 0.0);
    truth.accelerometer.noise_per_sample_mps2 *= factor(draw.accelerometer_noise_percent, 0.0);
    truth
        .star_sensor
        .scale_noise(factor(draw.star_noise_percent, 0.0));
    truth.gnss.noise_m *= factor(draw.gnss_noise_percent, 0.0);
    for (mounting, added) in truth
        .star_sensor
        .mounting_rotation_vector_deg
        .iter_mut()
        .zip(draw.star_mounting_deg)
    {
        *mounting += added;
    }
    truth.gnss.correlated_noise_m *= factor(draw.gnss_correlated_sigma_percent, 0.0);
    truth.gnss.correlation_time_s *= factor(
        draw.gnss_correlation_time_percent,
        MIN_CORRELATION_TIME_FACTOR,
    );
    truth.gnss.latency_s += f64::from(draw.gnss_latency_frames) * scenario.imu.frame_period_s();
    for ((row, column), (gyro, accelerometer)) in OFF_DIAGONAL.into_iter().zip(
        draw.gyro_misalignment_rad
            .into_iter()
            .zip(draw.accelerometer_misalignment_rad),
    ) {
        truth.gyro.misalignment_rad[row][column] += gyro;
        truth.accelerometer.misalignment_rad[row][column] += accelerometer;
    }
    for (sensitivity, added) in truth
        .gyro
        .g_sensitivity_rad_s_per_mps2
        .iter_mut()
        .zip(draw.gyro_g_sensitivity_rad_s_per_mps2)
    {
        *sensitivity += added;
    }
    truth
}

/// The initial navigation error a flight of `scenario` adds to the one drawn from the filter's
/// initial 1σ, drawn with the scenario's seed (a campaign run's seed,
/// [`crate::setup::prior::with_truth_drawn_from_prior`]): (attitude rotation vector rad, position m,
/// velocity m/s), zero without a `[dispersion]` table.
pub fn initial_error_offsets(scenario: &Scenario) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let Some(dispersion) = &scenario.dispersion else {
        return (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
    };
    let draw = draw(dispersion, scenario.simulation.seed);
    (
        Vector3::from(draw.initial_attitude_deg.map(f64::to_radians)),
        Vector3::from(draw.initial_position_m),
        Vector3::from(draw.initial_velocity_mps),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The new IMU entries draw from their own streams: the old entries' draws (the
    /// latency's stream among them) are bit for bit what they are without them.
    #[test]
    fn the_imu_entries_leave_the_other_entries_draws_unchanged() {
        let normal = Some(Distribution::Normal { sigma: 1.0 });
        let old = Dispersion {
            initial_attitude_deg: normal,
            gyro_noise_percent: normal,
            star_mounting_deg: Some(Distribution::Uniform { half_width: 0.1 }),
            gnss_correlation_time_percent: normal,
            gnss_latency_frames: Some(50),
            ..Dispersion::default()
        };
        let with_imu = Dispersion {
            gyro_misalignment_rad: Some(Distribution::Normal { sigma: 2.0e-5 }),
            accelerometer_misalignment_rad: Some(Distribution::Uniform { half_width: 1.0e-4 }),
            gyro_g_sensitivity_rad_s_per_mps2: Some(Distribution::Normal { sigma: 1.0e-6 }),
            ..old.clone()
        };
        let mut scenario = Scenario::default_scenario().unwrap();
        scenario.gyro.misalignment_rad[0][1] = 1.0e-5;
        for seed in [1, 2, 3] {
            let (before, after) = (draw(&old, seed), draw(&with_imu, seed));
            let undispersed_imu = Draw {
                gyro_misalignment_rad: [0.0; 6],
                accelerometer_misalignment_rad: [0.0; 6],
                gyro_g_sensitivity_rad_s_per_mps2: [0.0; 3],
                ..after
            };
            assert_eq!(format!("{before:?}"), format!("{undispersed_imu:?}"));
            assert_eq!(before, undispersed_imu);
            assert!(after.gyro_misalignment_rad.iter().all(|term| *term != 0.0));
            assert!(after
                .accelerometer_misalignment_rad
                .iter()
                .all(|term| term.abs() <= 1.0e-4 && *term != 0.0));
            assert!(before.gyro_misalignment_rad.iter().all(|term| *term == 0.0));

            scenario.dispersion = Some(with_imu.clone());
            let truth = truth_scenario(&scenario, seed);
            for (index, (row, column)) in OFF_DIAGONAL.into_iter().enumerate() {
                let base = if (row, column) == (0, 1) { 1.0e-5 } else { 0.0 };
                assert_eq!(
                    truth.gyro.misalignment_rad[row][column].to_bits(),
                    (base + after.gyro_misalignment_rad[index]).to_bits()
                );
                assert_eq!(
                    truth.accelerometer.misalignment_rad[row][column].to_bits(),
                    after.accelerometer_misalignment_rad[index].to_bits()
                );
            }
            for axis in 0..3 {
                assert_eq!(truth.gyro.misalignment_rad[axis][axis].to_bits(), 0);
                assert_eq!(
                    truth.gyro.g_sensitivity_rad_s_per_mps2[axis].to_bits(),
                    after.gyro_g_sensitivity_rad_s_per_mps2[axis].to_bits()
                );
            }
            // Without the IMU entries the truth's IMU is the scenario's, bit for bit.
            scenario.dispersion = Some(old.clone());
            let truth = truth_scenario(&scenario, seed);
            assert_eq!(truth.gyro.misalignment_rad, scenario.gyro.misalignment_rad);
            assert_eq!(
                truth.gyro.g_sensitivity_rad_s_per_mps2.map(f64::to_bits),
                scenario.gyro.g_sensitivity_rad_s_per_mps2.map(f64::to_bits)
            );
            assert_eq!(
                truth.accelerometer.misalignment_rad,
                scenario.accelerometer.misalignment_rad
            );
        }
    }

    /// A turned mission is the same flight in the launch frame (the initial truth state to
    /// rounding) over another longitude: the site's longitude and the node move together, every
    /// other key and every other entry's draw is unchanged, and without the entry the
    /// scenario is returned bit for bit.
    #[test]
    fn a_turned_mission_is_the_same_flight_over_another_longitude() {
        let scenario = Scenario::default_scenario().unwrap();
        let initial = |scenario: &Scenario| {
            let frame = crate::setup::launch::launch_frame(scenario).unwrap();
            crate::setup::launch::initial_state(scenario, &frame).unwrap()
        };
        let before = initial(&scenario);
        for turn_deg in [-170.0, 45.0, 180.0] {
            let mission = turned(&scenario, turn_deg);
            let moved =
                (mission.launch_site.longitude_deg - scenario.launch_site.longitude_deg - turn_deg)
                    .rem_euclid(360.0);
            assert!(moved.min(360.0 - moved) < 1e-9, "{turn_deg}: {moved}");
            assert!((-180.0..180.0).contains(&mission.launch_site.longitude_deg));
            let node = (mission.initial_orbit.right_ascension_of_node_deg
                - scenario.initial_orbit.right_ascension_of_node_deg
                - turn_deg)
                .rem_euclid(360.0);
            assert!(node.min(360.0 - node) < 1e-9, "{turn_deg}: {node}");
            let after = initial(&mission);
            assert!((after.position_m - before.position_m).norm() < 1e-6);
            assert!((after.velocity_mps - before.velocity_mps).norm() < 1e-9);
            let unturned = Scenario {
                launch_site: scenario.launch_site.clone(),
                initial_orbit: scenario.initial_orbit.clone(),
                ..mission
            };
            assert_eq!(unturned, scenario);
        }

        let with_turn = Dispersion {
            launch_longitude_deg: Some(Distribution::Uniform { half_width: 180.0 }),
            gyro_noise_percent: Some(Distribution::Normal { sigma: 10.0 }),
            ..Dispersion::default()
        };
        let without = Dispersion {
            launch_longitude_deg: None,
            ..with_turn.clone()
        };
        let mut dispersed = scenario.clone();
        dispersed.dispersion = Some(without.clone());
        assert_eq!(mission_scenario(&dispersed, 3), dispersed);
        dispersed.dispersion = Some(with_turn.clone());
        let draws: Vec<f64> = (1..=8)
            .map(|seed| {
                let draw = draw(&with_turn, seed);
                assert_eq!(
                    draw.gyro_noise_percent.to_bits(),
                    super::draw(&without, seed).gyro_noise_percent.to_bits()
                );
                let mission = mission_scenario(&dispersed, seed);
                assert_eq!(mission, turned(&dispersed, draw.launch_longitude_deg));
                draw.launch_longitude_deg
            })
            .collect();
        assert!(draws.iter().all(|turn| turn.abs() <= 180.0));
        assert!(draws
            .windows(2)
            .all(|pair| (pair[0] - pair[1]).abs() > 1e-6));
    }
}
