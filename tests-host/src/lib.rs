//! Shared helpers for the host integration tests (see `tests/`).

use std::path::{Path, PathBuf};

pub mod doc_figures;
pub mod docs;
pub mod target_log;

/// Root of the project (parent of this crate's directory).
pub fn project_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}
