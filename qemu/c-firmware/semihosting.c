/* Semihosting calls (Arm "Semihosting for AArch32 and AArch64": operation in r0, the
 * argument block's address in r1, the result in r0). */
#include "semihosting.h"

enum {
  SYS_OPEN = 0x01,
  SYS_CLOSE = 0x02,
  SYS_WRITE0 = 0x04,
  SYS_WRITE = 0x05,
  SYS_READ = 0x06,
  SYS_EXIT = 0x18,
  MODE_READ_BINARY = 1,
  MODE_WRITE_BINARY = 5,
  APPLICATION_EXIT = 0x20026,
  RUN_TIME_ERROR = 0x20023
};

static int semihost(int operation, const void *argument) {
  register int r0 __asm__("r0") = operation;
  register const void *r1 __asm__("r1") = argument;
  __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

static size_t length_of(const char *text) {
  size_t length = 0;
  while (text[length] != '\0') length++;
  return length;
}

int host_open(const char *path, int write) {
  uintptr_t block[3] = {(uintptr_t)path, write ? MODE_WRITE_BINARY : MODE_READ_BINARY,
                        length_of(path)};
  return semihost(SYS_OPEN, block);
}

size_t host_read(int handle, void *buffer, size_t length) {
  uintptr_t block[3] = {(uintptr_t)handle, (uintptr_t)buffer, length};
  int not_read = semihost(SYS_READ, block);
  return not_read < 0 ? 0 : length - (size_t)not_read;
}

int host_write(int handle, const void *buffer, size_t length) {
  uintptr_t block[3] = {(uintptr_t)handle, (uintptr_t)buffer, length};
  return semihost(SYS_WRITE, block);
}

void host_close(int handle) {
  uintptr_t block[1] = {(uintptr_t)handle};
  semihost(SYS_CLOSE, block);
}

void host_print(const char *text) { semihost(SYS_WRITE0, text); }

void host_exit(int success) {
  /* AArch32: the reason code itself is the argument. */
  semihost(SYS_EXIT, (const void *)(uintptr_t)(success ? APPLICATION_EXIT : RUN_TIME_ERROR));
  for (;;) {
  }
}
