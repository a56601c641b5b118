//! Stack high-water mark. cortex-m-rt's `paint-stack` feature fills the whole stack region
//! (`_stack_end` up to `_stack_start`, the top of RAM; the stack grows down) with
//! [`cortex_m_rt::STACK_PAINT_VALUE`] before `main`; the deepest word that no longer holds the
//! paint is the lowest address the stack ever reached.

use core::sync::atomic::{AtomicUsize, Ordering};

use cortex_m_rt::STACK_PAINT_VALUE;

/// Size of the MPU guard region at the bottom of the stack (bytes, a power of two ≥ 32).
pub const GUARD_BYTES: usize = 256;
/// MPU region number used for the guard (the highest of the Cortex-M7's 8 or 16 regions
/// that every implementation has).
const GUARD_REGION: u32 = 7;

/// End of the guard region (0 while no guard is installed): the painted region starts here.
static GUARD_END: AtomicUsize = AtomicUsize::new(0);

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

/// Installs an MPU guard region: [`GUARD_BYTES`] of no-access memory at the bottom of the
/// stack region (the first aligned block above `_stack_end`), so a stack overflow faults
/// (MemManage, escalated to HardFault, which exits QEMU with failure; if the fault cannot even
/// be stacked the core locks up, which the runner's timeout turns into a failure) instead of
/// silently overwriting the statics below the stack. The MPU's background region keeps the
/// default memory map for everything else (PRIVDEFENA).
///
/// PMSAv7 programming (ARMv7-M ARM B3.5): RNR selects the region; RBAR takes the base,
/// aligned to the region size; RASR = XN | AP=000 (no access) | SIZE = log2(size) − 1 |
/// ENABLE; CTRL = PRIVDEFENA | ENABLE, then DSB and ISB.
pub fn install_guard(mpu: &mut cortex_m::peripheral::MPU) {
    let bottom = core::ptr::addr_of!(_stack_end) as usize;
    let base = (bottom + GUARD_BYTES - 1) & !(GUARD_BYTES - 1);
    let size_field = GUARD_BYTES.trailing_zeros() - 1;
    const EXECUTE_NEVER: u32 = 1 << 28;
    const REGION_ENABLE: u32 = 1;
    const PRIVILEGED_DEFAULT_MAP: u32 = 1 << 2;
    const MPU_ENABLE: u32 = 1;
    // SAFETY: the guard covers stack-region RAM below everything the program has used so
    // far (the stack grows down from the top of RAM); no code or data lives there.
    unsafe {
        mpu.rnr.write(GUARD_REGION);
        mpu.rbar.write(base as u32);
        mpu.rasr
            .write(EXECUTE_NEVER | (size_field << 1) | REGION_ENABLE);
        mpu.ctrl.write(PRIVILEGED_DEFAULT_MAP | MPU_ENABLE);
    }
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
    GUARD_END.store(base + GUARD_BYTES, Ordering::Relaxed);
}

/// First address of the stack region outside the guard.
fn usable_bottom() -> usize {
    let bottom = core::ptr::addr_of!(_stack_end) as usize;
    bottom.max(GUARD_END.load(Ordering::Relaxed))
}

/// Paints the part of the stack region below the current stack pointer again (leaving a
/// 256-byte margin under it for this function's own frame), so that a later [`usage`]
/// measures only what runs after this call: the replay calls it after start-up, before the
/// first frame, to separate the cyclic flight path from one-off initialisation.
#[inline(never)]
pub fn repaint_below_current_stack_pointer() {
    const MARGIN_BYTES: usize = 256;
    let bottom = usable_bottom();
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
    let (bottom, top) = (usable_bottom(), core::ptr::addr_of!(_stack_start) as usize);
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
