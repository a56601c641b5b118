//! scratch
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap();
    let seed: u64 = std::env::args().nth(2).unwrap().parse()?;
    let scenario = nav_sim::Scenario::load(std::path::Path::new(&path))?;
    let seeded = nav_sim::flight::with_truth_drawn_from_prior(&scenario, seed);
    let truth = nav_sim::dispersion::truth_scenario(&seeded, seed);
    let config = nav_sim::dispersion::flight_config(&seeded, &truth)?;
    let options = if std::env::args().nth(3).is_some() { nav_sim::flight::FlightOptions::default() } else { nav_sim::flight::FlightOptions { record_interval_s: 5.0 } };
    let result = nav_sim::flight::fly_with(&truth, config, options, |_, _| {}, |_, _| {})?;
    println!("health: {:?}", result.health);
    println!("final nees {:?} samples {} last t {:?} err {:?}", result.calibration_nees(), result.samples.len(), result.last().map(|s| s.time_s), result.calibration_error.as_slice());
    for s in result.samples.iter() {
        let n = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let ez = (s.estimate[4][0] - s.truth[4][0]) / s.sigma[4][0];
        println!(
            "t {:7.1} pos_err {:10.3e} pos_sig {:10.3e} vel_err {:9.2e} vel_sig {:9.2e} att_err {:9.2e} att_sig {:9.2e} ksfx_z {:8.2} nees {:?} star_nis {}/{} gnss_nis {}/{}",
            s.time_s, n(s.position_error_m), n(s.position_sigma_m), n(s.velocity_error_mps), n(s.velocity_sigma_mps),
            n(s.attitude_error_rad), n(s.attitude_sigma_rad), ez, s.calibration_nees.map(|x| (x * 10.0).round() / 10.0),
            (s.star_nis.sum * 10.0).round() / 10.0, s.star_nis.updates, (s.gnss_nis.sum * 10.0).round() / 10.0, s.gnss_nis.updates
        );
    }
    Ok(())
}
