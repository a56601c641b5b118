//! The MPS2-AN500's serial lines: Arm CMSDK APB UARTs (Cortex-M System Design Kit Technical
//! Reference Manual, ARM DDI0479C, section 4.3), as [`embedded_io`] byte streams. A UART has a
//! one-byte receive and one-byte transmit buffer and no FIFO; reads poll the receive-full flag,
//! writes wait for the transmit buffer to empty. QEMU connects each to a `-serial` chardev in
//! order (UART0 first).
//!
//! Registers (offsets): DATA 0x00, STATE 0x04 (bit 0 TX full, bit 1 RX full), CTRL 0x08
//! (bit 0 TX enable, bit 1 RX enable), BAUDDIV 0x10 (at least 16).

use core::convert::Infallible;
use core::sync::atomic::{AtomicU8, Ordering};

use embedded_io::{ErrorType, Read, ReadReady, Write};

/// Base addresses of UART0..UART4 on the MPS2 (AN385 / AN500 memory map).
pub const UART_BASES: [usize; 5] = [
    0x4000_4000,
    0x4000_5000,
    0x4000_6000,
    0x4000_7000,
    0x4000_9000,
];

const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const BAUDDIV: usize = 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const CTRL_TX_ENABLE: u32 = 1 << 0;
const CTRL_RX_ENABLE: u32 = 1 << 1;
/// The smallest baud divisor the UART accepts; the line rate is irrelevant under QEMU.
const MINIMUM_BAUD_DIVISOR: u32 = 16;

/// UARTs already handed out (bit per UART), so each has one owner.
static TAKEN: AtomicU8 = AtomicU8::new(0);

/// One CMSDK UART, enabled for receive and transmit.
pub struct CmsdkUart {
    base: usize,
}

impl CmsdkUart {
    /// UART `index` (0..=4), enabled; `None` for another index or a UART already taken.
    pub fn take(index: usize) -> Option<Self> {
        let base = *UART_BASES.get(index)?;
        let bit = 1_u8 << index;
        if TAKEN.fetch_or(bit, Ordering::AcqRel) & bit != 0 {
            return None;
        }
        let uart = Self { base };
        uart.write_register(BAUDDIV, MINIMUM_BAUD_DIVISOR);
        uart.write_register(CTRL, CTRL_TX_ENABLE | CTRL_RX_ENABLE);
        Some(uart)
    }

    fn read_register(&self, offset: usize) -> u32 {
        // SAFETY: `base + offset` is a register of a UART this value owns (see `take`);
        // MMIO needs volatile access.
        unsafe { core::ptr::read_volatile((self.base + offset) as *const u32) }
    }

    fn write_register(&self, offset: usize, value: u32) {
        // SAFETY: as in `read_register`.
        unsafe { core::ptr::write_volatile((self.base + offset) as *mut u32, value) }
    }

    fn received(&self) -> bool {
        self.read_register(STATE) & STATE_RX_FULL != 0
    }

    /// The received byte (the caller checked [`Self::received`]).
    fn take_byte(&self) -> u8 {
        self.read_register(DATA).to_le_bytes()[0]
    }
}

impl ErrorType for CmsdkUart {
    type Error = Infallible;
}

impl ReadReady for CmsdkUart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.received())
    }
}

impl Read for CmsdkUart {
    /// Waits for one byte, then takes what else has arrived, up to `buffer.len()`.
    fn read(&mut self, buffer: &mut [u8]) -> Result<usize, Infallible> {
        let Some((first, rest)) = buffer.split_first_mut() else {
            return Ok(0);
        };
        while !self.received() {}
        *first = self.take_byte();
        let mut read = 1;
        for byte in rest {
            if !self.received() {
                break;
            }
            *byte = self.take_byte();
            read += 1;
        }
        Ok(read)
    }
}

impl Write for CmsdkUart {
    fn write(&mut self, buffer: &[u8]) -> Result<usize, Infallible> {
        for &byte in buffer {
            while self.read_register(STATE) & STATE_TX_FULL != 0 {}
            self.write_register(DATA, u32::from(byte));
        }
        Ok(buffer.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        while self.read_register(STATE) & STATE_TX_FULL != 0 {}
        Ok(())
    }
}
