//! Every relative link in README.md, CHANGELOG.md and docs/*.md resolves to a file inside the
//! repository (a link to `../shared` or a moved page would break in a clone), README.md and
//! docs/*.md describe the present (no sessions, rounds or issue numbers), and so do the
//! comments of the code (no issue numbers).

use std::path::{Path, PathBuf};

/// The targets of the Markdown links `[text](target)` of `text` (code spans included: a link
/// is written the same way there only on purpose).
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find("](") {
        let after = &rest[start + 2..];
        let Some(end) = after.find(')') else { break };
        targets.push(after[..end].to_string());
        rest = &after[end..];
    }
    targets
}

#[test]
fn every_relative_link_resolves_inside_the_repository() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let root = root.canonicalize().unwrap();
    let mut pages: Vec<PathBuf> = vec![root.join("README.md"), root.join("CHANGELOG.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|extension| extension == "md") {
            pages.push(path);
        }
    }
    let mut checked = 0;
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with('#') || target.starts_with("mailto:") {
                continue;
            }
            let path = target.split('#').next().unwrap();
            let base: &Path = page.parent().unwrap();
            let resolved = base
                .join(path)
                .canonicalize()
                .unwrap_or_else(|_| panic!("{}: link `{target}` does not resolve", page.display()));
            assert!(
                resolved.starts_with(&root),
                "{}: link `{target}` leaves the repository",
                page.display()
            );
            checked += 1;
        }
    }
    // The README alone links a dozen pages: a parser that finds nothing is a broken test.
    assert!(checked >= 12, "only {checked} links found");
}

/// README.md and docs/*.md (history belongs in CHANGELOG.md and the commit messages).
fn current_pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|extension| extension == "md") {
            pages.push(path);
        }
    }
    pages
}

/// The first phrase of `text` that narrates the project's history rather than its state:
/// sessions, rounds, or an issue by number.
fn history_phrase(text: &str) -> Option<String> {
    let lower = text.to_lowercase();
    for phrase in [
        "session",
        "this round",
        "last round",
        "previous round",
        "next round",
    ] {
        if lower.contains(phrase) {
            return Some(phrase.to_string());
        }
    }
    issue_number(text)
}

/// The first mention of an issue by number in `text`, lower-cased.
fn issue_number(text: &str) -> Option<String> {
    let lower = text.to_lowercase();
    lower.match_indices("issue").find_map(|(at, _)| {
        let rest = lower[at + "issue".len()..].trim_start_matches([' ', '#']);
        rest.starts_with(|c: char| c.is_ascii_digit())
            .then(|| lower[at..].chars().take(12).collect())
    })
}

#[test]
fn the_readme_and_docs_describe_the_present() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .unwrap();
    let pages = current_pages(&root);
    assert!(pages.len() >= 8, "only {} pages found", pages.len());
    for page in pages {
        let text = std::fs::read_to_string(&page).unwrap();
        if let Some(phrase) = history_phrase(&text) {
            panic!(
                "{}: `{phrase}` is history: it belongs in CHANGELOG.md",
                page.display()
            );
        }
    }
}

/// The project's source files: Rust, shell, Python and Cargo manifests under the crates,
/// the firmware, the tests, the fuzz targets and the scripts (build output skipped).
fn source_files(directory: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(directory).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            if name != "target" && !name.starts_with('.') {
                source_files(&path, found);
            }
        } else if name == "Cargo.toml"
            || path
                .extension()
                .is_some_and(|extension| ["rs", "sh", "py"].iter().any(|e| extension == *e))
        {
            found.push(path);
        }
    }
}

#[test]
fn the_code_comments_carry_no_issue_numbers() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .unwrap();
    let mut files = Vec::new();
    for directory in [
        "nav-core",
        "nav-fsw",
        "nav-sim",
        "qemu",
        "tests-host",
        "fuzz",
        "scripts",
    ] {
        source_files(&root.join(directory), &mut files);
    }
    assert!(files.len() >= 50, "only {} source files found", files.len());
    let this_test = root.join("tests-host/tests/doc_links.rs");
    for file in files.iter().filter(|file| **file != this_test) {
        let text = std::fs::read_to_string(file).unwrap();
        if let Some(phrase) = issue_number(&text) {
            panic!(
                "{}: `{phrase}` is history: it belongs in CHANGELOG.md and the commit messages",
                file.display()
            );
        }
    }
}

#[test]
fn history_phrases_are_found() {
    assert_eq!(
        history_phrase("As in Issue 21, ...").as_deref(),
        Some("issue 21, ..")
    );
    assert_eq!(history_phrase("see issue #7").as_deref(), Some("issue #7"));
    assert_eq!(
        history_phrase("measured in the previous session").as_deref(),
        Some("session")
    );
    assert_eq!(history_phrase("an issue of the receiver, 3 times"), None);
    assert_eq!(history_phrase("rounds correctly to nearest"), None);
    // Multi-byte characters after the number are cut on a character boundary.
    assert_eq!(
        history_phrase("issue 2σσσσσσσσ").as_deref(),
        Some("issue 2σσσσσ")
    );
}

#[test]
fn link_targets_are_parsed() {
    assert_eq!(
        link_targets("see [a](docs/a.md) and [b](b.md#x), not ](x"),
        ["docs/a.md", "b.md#x"]
    );
}
