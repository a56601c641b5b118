//! The flight harness: a scenario flown through the flight software ([`flight`]; its
//! optional state blocks' final errors in [`optional_blocks`]), a recorded
//! sensor log replayed through it ([`log_replay`]), and the same flight replayed on the
//! Cortex-M7 firmware under QEMU ([`target_replay`]) and over its serial lines
//! ([`uart_replay`]), compared bit for bit with the host.

pub mod filter_gauge;
pub mod flight;
pub mod log_replay;
pub mod optional_blocks;
pub mod target_replay;
pub mod uart_replay;
