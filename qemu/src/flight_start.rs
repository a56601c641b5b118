//! The flight software's start in the replay firmwares: the computer built in place in a
//! static slot (`NavigationComputer::init_in_place`), so start-up's stack holds only the
//! construction's small parts, never the large computer.

use core::mem::MaybeUninit;

use nav_fsw::replay::ReplaySetup;
use nav_fsw::scheduler::NavigationComputer;

/// The computer of `setup` in its static slot; `None` (logged) if the configuration is
/// refused or the slot was taken already (a second call).
pub fn start_flight_software(setup: &ReplaySetup) -> Option<&'static mut NavigationComputer> {
    let slot = cortex_m::singleton!(: MaybeUninit<NavigationComputer> = MaybeUninit::uninit())?;
    let started = NavigationComputer::init_in_place(slot, setup.config(), setup.initial);
    if started.is_err() {
        defmt::error!("flight software: configuration refused");
    }
    started.ok()
}
