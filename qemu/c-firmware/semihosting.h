/* Semihosting (Arm's host I/O through `bkpt 0xAB`, which QEMU serves with
 * `-semihosting-config enable=on`): files of QEMU's working directory, the console and the
 * exit code. */
#ifndef NAV_SEMIHOSTING_H
#define NAV_SEMIHOSTING_H

#include <stddef.h>
#include <stdint.h>

/* Opens `path` for reading ("rb") or writing ("wb"); a handle, or -1. */
int host_open(const char *path, int write);
/* Reads up to `length` bytes; the bytes read (0 at the end). */
size_t host_read(int handle, void *buffer, size_t length);
/* Writes `length` bytes; 0 when all were written. */
int host_write(int handle, const void *buffer, size_t length);
/* Closes a handle. */
void host_close(int handle);
/* Writes a NUL-terminated string to QEMU's standard output. */
void host_print(const char *text);
/* Ends the program: QEMU exits with 0 when `success`, 1 otherwise. */
void host_exit(int success) __attribute__((noreturn));

#endif
