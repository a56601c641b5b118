//! The star tracker's per-axis noise reaches the flight software: a scenario with
//! `cross_boresight_noise_arcsec` / `roll_noise_arcsec` gives `star.noise_rad` (sensor x, y)
//! and `star.roll_noise_rad` (sensor z) those values; one without gives `noise_arcsec` on
//! both, the bits of the isotropic setup before the per-axis R.

use crate::realistic_campaign::scenario;
use nav_sim::scenario::star_sensor::arcsec_to_rad;
use nav_sim::setup::fsw::{fsw_config, replay_setup};
use nav_sim::Scenario;

#[test]
fn a_star_tracker_with_per_axis_noise_gives_the_flight_software_those_values() {
    let roll_noise = scenario("star_tracker_roll_noise");
    let config = fsw_config(&roll_noise).unwrap();
    assert_eq!(
        config.star.noise_rad.to_bits(),
        arcsec_to_rad(5.0).to_bits()
    );
    assert_eq!(
        config.star.roll_noise_rad.to_bits(),
        arcsec_to_rad(35.0).to_bits()
    );
    // The words carry both to the QEMU replay.
    let setup = replay_setup(&roll_noise).unwrap();
    let decoded = nav_fsw::replay::ReplaySetup::from_words(&setup.to_words()).unwrap();
    assert_eq!(decoded.config().star, config.star);
    // Value for value the default scenario but for the star noise.
    let mut default = Scenario::default_scenario().unwrap();
    default.star_sensor.noise_arcsec = 35.0;
    default.star_sensor.cross_boresight_noise_arcsec = Some(5.0);
    default.star_sensor.roll_noise_arcsec = Some(35.0);
    assert_eq!(format!("{default:?}"), format!("{roll_noise:?}"));
}

#[test]
fn a_star_tracker_without_per_axis_noise_gives_the_flight_software_noise_arcsec_on_every_axis() {
    let default = Scenario::default_scenario().unwrap();
    let config = fsw_config(&default).unwrap();
    let isotropic = default.star_sensor.noise_rad().max(1e-12).to_bits();
    assert_eq!(config.star.noise_rad.to_bits(), isotropic);
    assert_eq!(config.star.roll_noise_rad.to_bits(), isotropic);
    assert_eq!(
        config.star.noise_rad.to_bits(),
        arcsec_to_rad(10.0).to_bits()
    );
}
