/* Reset and exceptions of the C firmware on the Cortex-M7: the vector table, .data copied
 * and .bss zeroed, the stack painted (so the replay can report its high-water mark), the FPU
 * enabled (the library's double arithmetic runs on it), then main(). */
#include <stdint.h>

#include "semihosting.h"
#include "startup.h"

/* The linker script's symbols, as arrays: only their addresses are meant. */
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _stack_bottom[], _stack_top[];
int main(void);

void Reset_Handler(void);
void SysTick_Handler(void);
static void fault_handler(void);

typedef void (*vector)(void);

/* Initial stack pointer, then the exception handlers (ARMv7-M B1.5.3). */
__attribute__((section(".vectors"), used)) static const vector vectors[16] = {
    (vector)(uintptr_t)_stack_top, Reset_Handler, fault_handler, fault_handler,
    fault_handler,                  fault_handler, fault_handler, 0,
    0,                              0,             0,             fault_handler,
    fault_handler,                  0,             fault_handler, SysTick_Handler};

/* A fault ends the run with a failure. */
static void fault_handler(void) {
  host_print("HardFault\n");
  host_exit(0);
}

void paint_stack(uint32_t *from, uint32_t *below) {
  for (uint32_t *word = from; word < below; word++) *word = STACK_PAINT;
}

void Reset_Handler(void) {
  uint32_t *source = _sidata;
  for (uint32_t *word = _sdata; word < _edata; word++) *word = *source++;
  for (uint32_t *word = _sbss; word < _ebss; word++) *word = 0;
  /* Below this function's own frame (a margin of 256 bytes). */
  paint_stack(_stack_bottom, (uint32_t *)((uintptr_t)_stack_top - 256));
  /* CPACR: full access to CP10 and CP11, the FPU. */
  *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  host_exit(main() == 0);
}

StackUsage stack_usage(void) {
  StackUsage usage;
  uint32_t *word = _stack_bottom;
  while (word < _stack_top && *word == STACK_PAINT) word++;
  usage.high_water_bytes = (uint32_t)((uintptr_t)_stack_top - (uintptr_t)word);
  usage.region_bytes = (uint32_t)((uintptr_t)_stack_top - (uintptr_t)_stack_bottom);
  return usage;
}

void repaint_below_stack_pointer(void) {
  uint32_t *stack_pointer;
  __asm__ volatile("mov %0, sp" : "=r"(stack_pointer));
  /* A margin of 256 bytes below the stack pointer: this function's callees. */
  paint_stack(_stack_bottom, stack_pointer - 64);
}
