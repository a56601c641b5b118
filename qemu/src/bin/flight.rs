//! The panic-free flight build (`--features panic-never`, release profile).
//!
//! Its panic handler calls a function that exists nowhere, so if the optimiser leaves any
//! panic path reachable from the flight code, the link fails with an undefined reference to
//! `panic_path_reachable_in_flight_build` (the "panic-never" technique). Inputs come through
//! `black_box`, so the optimiser cannot fold the flight code away and hide a panic path.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use nav_qemu::exit_success;

#[entry]
fn main() -> ! {
    let results = black_box(nav_core::selftest::reference_workload());
    for value in results {
        defmt::println!("flight: {=u64:016x}", value.to_bits());
    }
    // The whole filter path (propagation, both updates, resets) must be panic-free too.
    match nav_core::selftest::FilterPathFixture::new().and_then(|mut fixture| {
        black_box(&mut fixture).run_sequence()?;
        Ok(fixture.results())
    }) {
        Ok(results) => {
            for value in results {
                defmt::println!("flight filter path: {=u64:016x}", value.to_bits());
            }
        }
        Err(error) => defmt::error!("flight filter path: {}", error),
    }
    #[cfg(feature = "demo-panic-path")]
    demo_panic_path();
    exit_success()
}

/// A deliberately panicking slice index (enabled only by the `demo-panic-path` feature) that
/// the panic-never build must reject.
#[cfg(feature = "demo-panic-path")]
fn demo_panic_path() {
    let table = [1.0_f64, 2.0, 3.0];
    let index: usize = black_box(7);
    #[allow(clippy::indexing_slicing)]
    let value = table[index];
    defmt::println!("unreachable in a correct flight build: {=f64}", value);
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        /// Deliberately never defined: referencing it makes a reachable panic a link error.
        fn panic_path_reachable_in_flight_build() -> !;
    }
    // SAFETY: never executed; the symbol does not exist, so a build that keeps this call fails
    // to link.
    unsafe { panic_path_reachable_in_flight_build() }
}
