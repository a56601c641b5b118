//! Host files through semihosting (ARM semihosting OPEN / READ / WRITE / CLOSE), for the
//! replay firmware: the sensor log is streamed in, the outputs streamed out. Paths are
//! relative to QEMU's working directory.

use cortex_m_semihosting::{nr, syscall};

/// A host file could not be opened, read or written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum HostFileError {
    /// OPEN failed (missing file, bad path).
    Open,
    /// WRITE did not take every byte.
    Write,
}

/// An open host file.
pub struct HostFile {
    handle: usize,
}

impl HostFile {
    fn open(path_nul_terminated: &str, mode: usize) -> Result<Self, HostFileError> {
        let bytes = path_nul_terminated.as_bytes();
        let Some((&0, name)) = bytes.split_last() else {
            return Err(HostFileError::Open);
        };
        // SAFETY: OPEN reads `name.len()` bytes from a live, NUL-terminated buffer.
        let handle = unsafe { syscall!(OPEN, bytes.as_ptr(), mode, name.len()) };
        if handle == usize::MAX {
            Err(HostFileError::Open)
        } else {
            Ok(Self { handle })
        }
    }

    /// Opens an existing file for binary reading (`path` must end in `\0`).
    ///
    /// # Errors
    /// [`HostFileError::Open`].
    pub fn open_read(path: &str) -> Result<Self, HostFileError> {
        Self::open(path, nr::open::R_BINARY)
    }

    /// Creates (truncates) a file for binary writing (`path` must end in `\0`).
    ///
    /// # Errors
    /// [`HostFileError::Open`].
    pub fn create(path: &str) -> Result<Self, HostFileError> {
        Self::open(path, nr::open::W_TRUNC_BINARY)
    }

    /// Reads up to `buffer.len()` bytes; returns how many were read (0 at the end).
    pub fn read(&mut self, buffer: &mut [u8]) -> usize {
        // SAFETY: READ writes at most `buffer.len()` bytes into the live buffer and returns
        // the number of bytes it did NOT read.
        let not_read = unsafe { syscall!(READ, self.handle, buffer.as_mut_ptr(), buffer.len()) };
        buffer.len().saturating_sub(not_read)
    }

    /// Writes all of `bytes`.
    ///
    /// # Errors
    /// [`HostFileError::Write`] if the host took fewer bytes.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), HostFileError> {
        // SAFETY: WRITE reads `bytes.len()` bytes from the live buffer; it returns the number
        // of bytes not written.
        let not_written = unsafe { syscall!(WRITE, self.handle, bytes.as_ptr(), bytes.len()) };
        if not_written == 0 {
            Ok(())
        } else {
            Err(HostFileError::Write)
        }
    }
}

impl Drop for HostFile {
    fn drop(&mut self) {
        // SAFETY: CLOSE of a handle this struct owns.
        let _ = unsafe { syscall!(CLOSE, self.handle) };
    }
}

/// Reads exactly `buffer.len()` bytes unless the file ends first; returns the count read.
pub fn read_full(file: &mut HostFile, buffer: &mut [u8]) -> usize {
    let mut filled = 0;
    while filled < buffer.len() {
        let Some(rest) = buffer.get_mut(filled..) else {
            break;
        };
        let read = file.read(rest);
        if read == 0 {
            break;
        }
        filled += read;
    }
    filled
}
