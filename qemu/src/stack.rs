//! Stack high-water mark. cortex-m-rt's `paint-stack` feature fills the whole stack region
//! (`_stack_end` up to `_stack_start`, the top of RAM; the stack grows down) with
//! [`cortex_m_rt::STACK_PAINT_VALUE`] before `main`; the deepest word that no longer holds the
//! paint is the lowest address the stack ever reached.

use cortex_m_rt::STACK_PAINT_VALUE;

extern "C" {
    /// Lowest address of the stack region (end of `.bss`/`.uninit`), from cortex-m-rt's `link.x`.
    static mut _stack_end: u32;
    /// Initial stack pointer (top of RAM), from `link.x`.
    static mut _stack_start: u32;
}

/// Stack use so far and the size of the stack region, in bytes.
#[derive(Debug, Clone, Copy, defmt::Format)]
pub struct StackUsage {
    /// Bytes between the top of the stack and the deepest word the program wrote.
    pub high_water_bytes: u32,
    /// Bytes in the stack region (`_stack_start − _stack_end`).
    pub region_bytes: u32,
}

/// Paints the part of the stack region below the current stack pointer again (leaving a
/// 256-byte margin under it for this function's own frame), so that a later [`usage`]
/// measures only what runs after this call: the replay calls it after start-up, before the
/// first frame, to separate the cyclic flight path from one-off initialisation.
#[inline(never)]
pub fn repaint_below_current_stack_pointer() {
    const MARGIN_BYTES: usize = 256;
    let bottom = core::ptr::addr_of!(_stack_end) as usize;
    let stack_pointer = cortex_m::register::msp::read() as usize;
    let limit = stack_pointer.saturating_sub(MARGIN_BYTES) & !3;
    let mut address = bottom;
    while address < limit {
        // SAFETY: `address` is word aligned and inside [_stack_end, SP − 256): stack-region
        // RAM below anything live (the stack grows down and nothing lives below SP).
        unsafe { core::ptr::write_volatile(address as *mut u32, STACK_PAINT_VALUE) };
        address += 4;
    }
}

/// Scans the painted region from its bottom up (bounded: one read per word of the region).
pub fn usage() -> StackUsage {
    // Only the addresses of the linker symbols are taken. The words in between are RAM of
    // the stack region (mapped, 4-byte aligned: link.x asserts `_stack_end % 4 == 0`).
    let (bottom, top) = (
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    );
    let region_bytes = top.saturating_sub(bottom);
    let mut lowest_used = top;
    let mut address = bottom;
    while address < top {
        // SAFETY: `address` stays inside the stack region [bottom, top), which is mapped RAM,
        // and is word aligned; a volatile read of a plain u32 has no other effect.
        let word = unsafe { core::ptr::read_volatile(address as *const u32) };
        if word != STACK_PAINT_VALUE {
            lowest_used = address;
            break;
        }
        address += 4;
    }
    StackUsage {
        high_water_bytes: u32::try_from(top - lowest_used).unwrap_or(u32::MAX),
        region_bytes: u32::try_from(region_bytes).unwrap_or(u32::MAX),
    }
}
