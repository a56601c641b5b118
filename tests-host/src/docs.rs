//! The documentation's pages and the committed results files the tests compare with.

use std::path::{Path, PathBuf};

use nav_sim::output::results::{self, Comparison};

use crate::project_root;

/// The Markdown files under `directory`, its subdirectories included, sorted.
pub fn markdown_files(directory: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![directory.to_path_buf()];
    while let Some(directory) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&directory) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|extension| extension == "md") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// README.md and every page under docs/ (results and reference pages included): what the
/// documentation says now (history belongs in CHANGELOG.md).
pub fn current_pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md")];
    pages.extend(markdown_files(&root.join("docs")));
    pages
}

/// The directory of the committed results files.
pub fn results_directory() -> PathBuf {
    project_root().join("docs/results")
}

/// How to rewrite the committed results after an intended change.
pub const BLESS_HOW: &str =
    "rerun the failing step with NAV_RESULTS_BLESS=1 (or run scripts/results.sh), then commit docs/results/";

/// Compares the committed results file `name` with `body` measured by `command` (rewrites it
/// with `NAV_RESULTS_BLESS=1`); panics with the first differing line otherwise.
pub fn check_results(name: &str, command: &str, body: &str) {
    check_committed(
        &results_directory().join(name),
        &results::render(command, body),
    );
}

/// Compares the committed file `path` with `fresh` (rewrites it with `NAV_RESULTS_BLESS=1`);
/// panics with the first differing line otherwise.
pub fn check_committed(path: &Path, fresh: &str) {
    match results::compare_or_bless(path, fresh, BLESS_HOW) {
        Ok(Comparison::Unchanged) => {}
        Ok(Comparison::Blessed) => println!("blessed {}", path.display()),
        Ok(Comparison::Changed(message)) => panic!("{message}"),
        Err(error) => panic!("{error}"),
    }
}
