//! Host replay throughput: the first `SECONDS` (default 120) of the default scenario's
//! sensor log, assembled into frames in memory first, then run through the flight software
//! (nav-fsw `NavigationComputer`) on one core with the structured (flight) and the dense
//! (reference) filter arithmetic; prints frames per second of each and their ratio.
//!
//! `cargo run --release -p nav-sim --example replay_throughput [SECONDS] [structured]`
//! (`structured`: the flight arithmetic only, e.g. under a profiler).

use std::time::Instant;

use nav_fsw::replay::{FrameAssembler, FramePorts};
use nav_fsw::scheduler::{FilterArithmetic, NavigationComputer};
use nav_sim::logs::sensor_log;
use nav_sim::{Scenario, Simulation};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seconds: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(120.0);
    let scenario = Scenario::default_scenario()?;
    let setup = nav_sim::setup::fsw::replay_setup(&scenario)?;
    let mut simulation = Simulation::new(&scenario)?;
    let mut assembler = FrameAssembler::new(setup.frame_grid())?;
    let mut frames: Vec<FramePorts> = Vec::new();
    let mut events = Vec::new();
    let wanted = (seconds * 500.0) as usize;
    while frames.len() < wanted && simulation.step(&mut events)?.is_some() {
        // The default scenario has one star-tracker head: every event goes to the assembler.
        for event in events.drain(..) {
            assembler.push(&sensor_log::record_of(&event))?;
            frames.extend(std::iter::from_fn(|| assembler.next_frame()));
        }
    }
    assembler.finish();
    frames.extend(std::iter::from_fn(|| assembler.next_frame()));
    let structured_only = std::env::args().nth(2).as_deref() == Some("structured");
    let mut rates = Vec::new();
    for (label, arithmetic) in [
        ("structured", FilterArithmetic::Structured),
        ("dense", FilterArithmetic::DenseReference),
    ] {
        if structured_only && arithmetic == FilterArithmetic::DenseReference {
            continue;
        }
        let mut computer = NavigationComputer::new(setup.config(), setup.initial)
            .map_err(|error| format!("{error:?}"))?;
        computer.set_arithmetic(arithmetic);
        let mut replay = frames.clone();
        let start = Instant::now();
        let mut checksum = 0.0;
        for ports in &mut replay {
            checksum += run_frame(ports, &mut computer);
        }
        let elapsed = start.elapsed().as_secs_f64();
        let rate = replay.len() as f64 / elapsed;
        println!(
            "{label:>10}: {} frames ({:.0} s of flight) in {elapsed:.3} s = {rate:.0} frames/s \
             (checksum {checksum:.6e})",
            replay.len(),
            replay.len() as f64 / 500.0
        );
        rates.push(rate);
    }
    if let [structured, dense] = rates[..] {
        println!("ratio structured/dense: {:.1}", structured / dense);
    }
    Ok(())
}

/// One frame (not inlined, so a profiler can collect exactly the frames:
/// `valgrind --tool=callgrind --toggle-collect='*replay_throughput*run_frame*'`).
#[inline(never)]
fn run_frame(ports: &mut FramePorts, computer: &mut NavigationComputer) -> f64 {
    ports.run(computer).position_m[0]
}
