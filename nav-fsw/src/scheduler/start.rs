//! Construction of the computer: in place into a caller's slot
//! ([`NavigationComputer::init_in_place`]), so a flight image can keep the large computer in
//! a `static` and start up on a small stack, or by value ([`NavigationComputer::new`]), the
//! same path followed by a move.
//!
//! The crate's only `unsafe` code is here: writing the fields of a `MaybeUninit` slot one by
//! one (the computer's parts, and each part's members) needs raw pointers. Building the whole value first and moving it into the slot needs
//! no `unsafe` but reserves several copies of it on the stack.
#![allow(unsafe_code)]

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use super::*;

/// The checks of the configuration and the initial state that need no member built. Not
/// inlined, like the builders below, so the construction's own frame stays small.
#[inline(never)]
fn check(config: &FswConfig, initial: &NavigationState) -> Result<(), FswError> {
    config.validate()?;
    let attitude_norm = initial.attitude.norm();
    let finite = attitude::all_finite3(&initial.position_m)
        && attitude::all_finite3(&initial.velocity_mps)
        && initial.time_s.is_finite()
        && initial.time_s.abs() <= crate::config::MAX_INITIAL_TIME_S;
    let unit = attitude::is_unit_norm(attitude_norm);
    if finite && attitude_norm.is_finite() && unit {
        Ok(())
    } else {
        Err(FswError::InvalidConfiguration(
            ConfigField::InitialNavigation,
        ))
    }
}

/// Writes the variance bounds of the covariance protection: the diagonals of the initial `P`
/// of the floors' and of the configured 1σ, the latter scaled by the ceiling factor squared.
#[inline(never)]
fn write_variance_bounds(
    floor: &mut MaybeUninit<ErrorState>,
    ceiling: &mut MaybeUninit<ErrorState>,
    config: &FswConfig,
) -> Result<(), NavError> {
    let floor_config = FilterConfig {
        initial: config.covariance.sigma_floor,
        ..config.filter
    };
    floor.write(floor_config.initial_variances()?);
    let ceiling_factor = config.covariance.sigma_ceiling_factor;
    ceiling.write(config.filter.initial_variances()? * (ceiling_factor * ceiling_factor));
    Ok(())
}

/// Builds one member into its field of the slot. Not inlined: the member's temporaries live
/// in this function's frame only, one member at a time. The member is copied from where its
/// constructor built it: moving it out of the `Result` first would add a second copy to the
/// frame.
#[inline(never)]
fn build_into<T: Copy, E: Copy>(
    field: &mut MaybeUninit<T>,
    build: impl FnOnce() -> Result<T, E>,
) -> Result<(), E> {
    let built = build();
    let member = built.as_ref().map_err(|error| *error)?;
    field.write(*member);
    Ok(())
}

impl NavigationComputer {
    /// The flight software at start, by value (see [`Self::init_in_place`] for a `static`).
    ///
    /// # Errors
    /// As [`Self::init_in_place`].
    pub fn new(config: FswConfig, initial: NavigationState) -> Result<Self, FswError> {
        let mut slot = MaybeUninit::uninit();
        Self::init_in_place(&mut slot, config, initial)?;
        // SAFETY: `init_in_place` returned `Ok`, so it wrote every field of `slot`.
        Ok(unsafe { slot.assume_init() })
    }

    /// The flight software at start, built in `slot`: the given navigation solution, `x = 0`,
    /// `P` from the configured initial 1σ, no calibration (zero corrections). Each part of
    /// the computer is written into its field of the slot by the part's own initialiser,
    /// member by member, so the large members (filter, history, queues, model) are never
    /// built on the stack and start-up needs only a small stack whatever the computer's size;
    /// a flight image passes a slot in a `static`.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] for a bad configuration (named field) or a
    /// non-finite / non-unit initial navigation state. On an error the slot is still
    /// uninitialised (some members may have been written; nothing reads them).
    ///
    /// # Examples
    /// A computer in a `static` slot, run for one frame (a `Mutex` on the host; a flight
    /// image takes its slot from `cortex_m::singleton!`, see `qemu/src/bin/replay.rs`):
    /// ```
    /// use core::mem::MaybeUninit;
    /// use nav_fsw::nalgebra::{Quaternion, Vector3};
    /// use nav_fsw::nav_core::frames::LaunchSite;
    /// use nav_fsw::nav_core::strapdown::NavigationState;
    /// use nav_fsw::sensor_frames::SensorFrames;
    /// use nav_fsw::{FrameGnss, FrameImu, FrameStar, FswConfig, ImuSample, NavigationComputer};
    ///
    /// static SLOT: std::sync::Mutex<MaybeUninit<NavigationComputer>> =
    ///     std::sync::Mutex::new(MaybeUninit::uninit());
    /// let site = LaunchSite {
    ///     latitude_rad: 40.958_f64.to_radians(),
    ///     longitude_rad: 100.291_f64.to_radians(),
    ///     height_m: 1000.0,
    ///     azimuth_rad: 190.0_f64.to_radians(),
    ///     earth_axis_ecef: [0.0, 0.0, 1.0],
    /// };
    /// let initial = NavigationState {
    ///     attitude: Quaternion::identity(),
    ///     position_m: Vector3::new(0.0, 500e3, 0.0),
    ///     velocity_mps: Vector3::new(7600.0, 0.0, 0.0),
    ///     time_s: 600.0,
    /// };
    /// let mut slot = SLOT.lock().unwrap();
    /// // PLACEHOLDER ground constants: a flight image uses its launch's (`nav-sim ground-constants`).
    /// let computer =
    ///     NavigationComputer::init_in_place(&mut slot, FswConfig::paper_defaults(site, SensorFrames::ALIGNED), initial)?;
    /// let mut imu = FrameImu(Some(ImuSample::new(1, 600.002, [0.0; 3], [0.0; 3])));
    /// let telemetry =
    ///     computer.run_frame(&mut imu, &mut FrameStar::default(), &mut FrameGnss::default());
    /// assert_eq!(telemetry.frame, 1);
    /// assert!((telemetry.time_s - 600.002).abs() < 1e-9);
    /// # Ok::<(), nav_fsw::FswError>(())
    /// ```
    #[inline(never)]
    pub fn init_in_place(
        slot: &mut MaybeUninit<Self>,
        config: FswConfig,
        initial: NavigationState,
    ) -> Result<&mut Self, FswError> {
        check(&config, &initial)?;
        let computer = slot.as_mut_ptr();
        // SAFETY: `computer` comes from a `&mut MaybeUninit<Self>`, so it is aligned, valid
        // for writes of `Self` and not aliased. Each field is written once, through
        // `addr_of_mut!` and `write` (which create no reference to uninitialised memory and
        // drop nothing) or through a `&mut MaybeUninit` of the field (which has no validity
        // requirement), a part by its own `init_in_place`, which writes every field of the
        // part when it returns `Ok`. A refusal returns before the reference below is made;
        // the writes name every field of `Self` (the test `init_in_place_writes_every_field`
        // fails for one left out), so the slot is initialised when it is made.
        unsafe {
            Covariance::init_in_place(
                &mut *addr_of_mut!((*computer).covariance).cast(),
                &config,
                initial.time_s,
            )?;
            build_into(&mut *addr_of_mut!((*computer).launch_frame).cast(), || {
                LaunchFrame::new(&config.launch_site)
                    .map_err(|_| FswError::InvalidConfiguration(ConfigField::LaunchSite))
            })?;
            Calibration::init_in_place(
                &mut *addr_of_mut!((*computer).calibration).cast(),
                &config,
            )?;
            Navigation::init_in_place(
                &mut *addr_of_mut!((*computer).navigation).cast(),
                &config,
                initial,
            )?;
            Aids::init_in_place(&mut *addr_of_mut!((*computer).aids).cast());
            let heads = StarHeads::new(&config.star)
                .map_err(|_| FswError::InvalidConfiguration(ConfigField::StarSecondHead))?;
            addr_of_mut!((*computer).heads).write(heads);
            addr_of_mut!((*computer).star_aberration)
                .write(crate::aberration_monitor::AberrationMonitor::default());
            addr_of_mut!((*computer).optional_variance_bounds).write(OptionalVarianceBounds::new(
                &config.covariance.optional_sigma_floor.by_block(),
                config.covariance.sigma_ceiling_factor,
                &config.filter,
            )?);
            Health::init_in_place(&mut *addr_of_mut!((*computer).health).cast());
            addr_of_mut!((*computer).operations).write(Operations {
                disabled: [false; 2],
                commands: CommandCounters::default(),
            });
            addr_of_mut!((*computer).config).write(config);
            addr_of_mut!((*computer).frame).write(0);
            addr_of_mut!((*computer).arithmetic).write(FilterArithmetic::Structured);
        }
        // SAFETY: every field was written above.
        let computer = unsafe { slot.assume_init_mut() };
        computer.record_snapshot();
        Ok(computer)
    }
}

// Each part is written member by member into its field of the slot, like the computer: its
// large members (the filter, the model, the history, the queues) are never built on the
// stack and moved. Not inlined, so each part's temporaries live in its own frame only. On an
// error some members may have been written; nothing reads them.

impl Covariance {
    /// The covariance at start in `slot`: `x = 0`, `P` from the configured initial 1σ at
    /// `time_s`, the protection's bounds, no motion summed and no growth.
    #[inline(never)]
    fn init_in_place(
        slot: &mut MaybeUninit<Self>,
        config: &FswConfig,
        time_s: f64,
    ) -> Result<(), FswError> {
        let part = slot.as_mut_ptr();
        // SAFETY: as for the computer (`NavigationComputer::init_in_place`): `part` is valid
        // for writes of `Self`, and each field is written once without reading it.
        unsafe {
            write_variance_bounds(
                &mut *addr_of_mut!((*part).variance_floor).cast(),
                &mut *addr_of_mut!((*part).variance_ceiling).cast(),
                config,
            )?;
            ErrorStateFilter::init_in_place(
                &mut *addr_of_mut!((*part).filter).cast(),
                &config.filter,
            )?;
            addr_of_mut!((*part).process_noise).write(super::gravity::process_noise(config));
            addr_of_mut!((*part).installation_walk_rad2_per_s).write(
                config
                    .star
                    .has_slow_error()
                    .then(|| config.star.installation_walk_rad2_per_s()),
            );
            addr_of_mut!((*part).time_s).write(time_s);
            addr_of_mut!((*part).sums).write(PropagationSums::EMPTY);
            addr_of_mut!((*part).last_point).write(None);
            addr_of_mut!((*part).model).write(StructuredModel::EMPTY);
            addr_of_mut!((*part).held_attitude).write(CoherentGrowth::default());
            addr_of_mut!((*part).held_velocity).write(CoherentGrowth::default());
            addr_of_mut!((*part).second_order_attitude).write(CoherentGrowth::default());
            addr_of_mut!((*part).second_order_rate_rad_s).write(Vector3::zeros());
            addr_of_mut!((*part).second_order_pending_s).write(0.0);
        }
        Ok(())
    }
}

impl Calibration {
    /// No calibration (zero corrections) and the manager of the configured policy, in `slot`.
    #[inline(never)]
    fn init_in_place(slot: &mut MaybeUninit<Self>, config: &FswConfig) -> Result<(), FswError> {
        let part = slot.as_mut_ptr();
        // SAFETY: as for the covariance.
        unsafe {
            build_into(&mut *addr_of_mut!((*part).manager).cast(), || {
                CalibrationManager::new(config.calibration)
            })?;
            addr_of_mut!((*part).estimate).write(CalibrationEstimate::default());
            addr_of_mut!((*part).imu_errors).write(ImuErrorEstimate::default());
        }
        Ok(())
    }
}

impl Navigation {
    /// The navigation solution `initial` in `slot`, with the IMU checker of the configured
    /// limits, no increment held and an empty history.
    #[inline(never)]
    fn init_in_place(
        slot: &mut MaybeUninit<Self>,
        config: &FswConfig,
        initial: NavigationState,
    ) -> Result<(), FswError> {
        let part = slot.as_mut_ptr();
        // SAFETY: as for the covariance.
        unsafe {
            build_into(&mut *addr_of_mut!((*part).imu_checker).cast(), || {
                ImuChecker::new(config.imu)
            })?;
            addr_of_mut!((*part).strapdown).write(Strapdown::new(config.strapdown));
            addr_of_mut!((*part).solution).write(initial);
            addr_of_mut!((*part).last_increment).write(None);
            addr_of_mut!((*part).frames_without_sample).write(0);
            addr_of_mut!((*part).history).write(History::new());
            addr_of_mut!((*part).gravity_field)
                .write(nav_core::gravity::harmonics::FieldRemainder::EMPTY);
            addr_of_mut!((*part).gravity_allowance_short).write(false);
            (*part)
                .gravity_field
                .configure(config.gravity.field)
                .map_err(|_| FswError::InvalidConfiguration(ConfigField::Gravity))?;
        }
        Ok(())
    }
}

impl Aids {
    /// Empty queues, no aid acquired or faulty, no outage and white innovations, in `slot`.
    #[inline(never)]
    fn init_in_place(slot: &mut MaybeUninit<Self>) {
        let part = slot.as_mut_ptr();
        // SAFETY: as for the covariance.
        unsafe {
            addr_of_mut!((*part).last_star).write([None; MAX_STAR_HEADS]);
            addr_of_mut!((*part).star_queue).write(MeasurementBuffer::new());
            addr_of_mut!((*part).gnss_queue).write(MeasurementBuffer::new());
            addr_of_mut!((*part).pending_gnss_position).write(None);
            addr_of_mut!((*part).star).write(AidingSensor::default());
            addr_of_mut!((*part).gnss).write(AidingSensor::default());
            addr_of_mut!((*part).gnss_velocity).write(AidingSensor::default());
            addr_of_mut!((*part).star_outage).write(OutageMonitor::default());
            addr_of_mut!((*part).gnss_outage).write(OutageMonitor::default());
            addr_of_mut!((*part).gnss_whiteness).write(WhitenessMonitor::default());
            addr_of_mut!((*part).star_consistency).write(ConsistencyMonitor::default());
            addr_of_mut!((*part).star_noise).write(NoiseMatching::default());
            addr_of_mut!((*part).gnss_consistency).write(ConsistencyMonitor::default());
            addr_of_mut!((*part).gnss_velocity_consistency).write(ConsistencyMonitor::default());
        }
    }
}

impl Health {
    /// Every counter at zero and no frame cost reported (no budget), in `slot`.
    #[inline(never)]
    fn init_in_place(slot: &mut MaybeUninit<Self>) {
        let part = slot.as_mut_ptr();
        // SAFETY: as for the covariance.
        unsafe {
            addr_of_mut!((*part).counters).write(HealthCounters::default());
            addr_of_mut!((*part).cost).write(FrameCostMonitor::new(u32::MAX));
        }
    }
}
