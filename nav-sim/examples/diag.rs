//! Temporary diagnostic.
use nav_sim::flight::{fly_with, fsw_config, FlightOptions};
use nav_sim::scenario::ManoeuvreSegment;
use nav_sim::Scenario;
fn main() {
    let mut scenario = Scenario::default_scenario().unwrap();
    let segment = |label: &str, duration_s: f64, ramp_s: f64, rate: [f64; 3]| ManoeuvreSegment {
        label: label.to_string(), duration_s, ramp_s, body_rate_deg_per_s: rate, specific_force_mps2: [0.0; 3],
    };
    scenario.manoeuvres = vec![
        segment("coast", 10.0, 0.0, [2.4e-4; 3]),
        segment("rotate z", 12.0, 1.0, [0.0, 0.0, 100.0]),
        segment("coast", 20.0, 0.0, [2.4e-4; 3]),
    ];
    if let Some(seed) = std::env::args().nth(2) { scenario.simulation.seed = seed.parse().unwrap(); }
    let delay: u64 = std::env::args().nth(1).map(|a| a.parse().unwrap()).unwrap_or(0);
    let mut held = std::collections::VecDeque::new();
    let r = fly_with(&scenario, fsw_config(&scenario), FlightOptions { record_interval_s: 2.0 }, |_, _| {}, |frame, inputs| {
        for m in inputs.star.0.drain(..) { held.push_back((frame + delay, m)); }
        while held.front().is_some_and(|(d, _)| *d <= frame) { inputs.star.0.extend(held.pop_front().map(|(_, m)| m)); }
    }).unwrap();
    for s in r.samples.iter().rev().take(if std::env::args().nth(2).is_some() {1} else {1000}).rev() {
        let z: Vec<String> = (0..5).map(|b| format!("{:+.1} {:+.1} {:+.1}", (s.estimate[b][0]-s.truth[b][0])/s.sigma[b][0], (s.estimate[b][1]-s.truth[b][1])/s.sigma[b][1], (s.estimate[b][2]-s.truth[b][2])/s.sigma[b][2])).collect();
        println!("{:7.1} {} | att {:+.1} {:+.1} {:+.1}", s.time_s - 600.0, z.join(" | "), s.attitude_error_rad[0]/s.attitude_sigma_rad[0], s.attitude_error_rad[1]/s.attitude_sigma_rad[1], s.attitude_error_rad[2]/s.attitude_sigma_rad[2]);
    }
    println!("{:?}", r.health);
}
