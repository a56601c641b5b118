//! The short scheduler scenario the cost checks and the profiler share: 40 frames of 500 Hz
//! IMU data from a coasting state, a star measurement in frame 20 and a 10 ms late GNSS fix
//! (12 m off) in frame 30. Each frame's ports are built here; the caller runs them.

use nalgebra::{Quaternion, Vector3};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;
use nav_fsw::config::FswConfig;
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::FramePorts;
use nav_fsw::scheduler::{FilterArithmetic, NavigationComputer};

/// Frames in the scenario.
pub const FRAMES: u32 = 40;
/// The frame that carries the star measurement.
pub const STAR_FRAME: u32 = 20;
/// The frame that carries the (late) GNSS fix.
pub const GNSS_FRAME: u32 = 30;
/// The frame whose navigation time tags the GNSS fix.
const GNSS_EPOCH_FRAME: u32 = 25;

/// The scenario's navigation computer and the state it needs to build the next frame.
pub struct SchedulerScenario {
    /// The flight software under test.
    pub computer: NavigationComputer,
    frame: u32,
    gnss_time_s: f64,
    gnss_position_m: Vector3<f64>,
}

impl SchedulerScenario {
    /// The paper's default configuration at a fixed launch site, coasting at 7.5 km/s;
    /// `None` if the configuration is rejected.
    pub fn new(arithmetic: FilterArithmetic) -> Option<Self> {
        let site = LaunchSite {
            latitude_rad: 0.715,
            longitude_rad: 1.750,
            height_m: 1000.0,
            azimuth_rad: 3.316,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        };
        let initial = NavigationState {
            attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
            position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
            velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
            time_s: 600.0,
        };
        let mut computer = NavigationComputer::new(
            // PLACEHOLDER ground constants (the check's sensors speak the launch frame): a
            // flight image uses its launch's, from `nav-sim ground-constants --format rust`.
            FswConfig::paper_defaults(site, nav_fsw::sensor_frames::SensorFrames::ALIGNED),
            initial,
        )
        .ok()?;
        computer.set_arithmetic(arithmetic);
        Some(Self {
            computer,
            frame: 0,
            gnss_time_s: 0.0,
            gnss_position_m: Vector3::zeros(),
        })
    }

    /// The next frame's number (1-based) and ports; `None` after [`FRAMES`] frames or if
    /// the GNSS fix cannot be formed.
    pub fn next_frame(&mut self) -> Option<(u32, FramePorts)> {
        if self.frame >= FRAMES {
            return None;
        }
        self.frame += 1;
        let frame = self.frame;
        let time_s = 600.0 + 0.002 * f64::from(frame);
        let mut ports = FramePorts::default();
        ports.imu.0 = Some(ImuSample::new(
            frame,
            time_s,
            [1e-4, -2e-4, 3e-3],
            [0.01, 0.04, -0.02],
        ));
        let navigation = self.computer.navigation();
        if frame == STAR_FRAME {
            let q = navigation.attitude;
            let _ = ports.star.0.push_back(StarMeasurement::new(
                navigation.time_s,
                [q.w, q.i, q.j, q.k],
                0,
            ));
        }
        if frame == GNSS_FRAME {
            // The antenna position of frame 25 (10 ms late), 12 m off.
            let ecef = self
                .computer
                .launch_frame()
                .launch_inertial_to_ecef(
                    &(self.gnss_position_m + Vector3::new(12.0, -5.0, 3.0)),
                    self.gnss_time_s,
                )
                .ok()?;
            // The aligned sensor frames: navigation time is GPS seconds of week 1000.
            let _ = ports.gnss.0.push_back(GnssFix::new(
                1_000,
                self.gnss_time_s,
                [ecef.x, ecef.y, ecef.z],
            ));
        }
        if frame == GNSS_EPOCH_FRAME {
            self.gnss_time_s = navigation.time_s;
            self.gnss_position_m = navigation.position_m;
        }
        Some((frame, ports))
    }
}
