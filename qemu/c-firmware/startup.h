/* The stack's measurement (startup.c paints the stack region at reset). */
#ifndef NAV_STARTUP_H
#define NAV_STARTUP_H

#include <stdint.h>

/* The value of a stack word never written. */
#define STACK_PAINT 0xCCCCCCCCu

typedef struct {
  /* Bytes between the top of the stack and the deepest word written. */
  uint32_t high_water_bytes;
  /* Bytes of the stack region. */
  uint32_t region_bytes;
} StackUsage;

StackUsage stack_usage(void);
/* Paints the stack region again below the current stack pointer. */
void repaint_below_stack_pointer(void);
void paint_stack(uint32_t *from, uint32_t *below);

#endif
