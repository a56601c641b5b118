//! Every relative link in README.md, CHANGELOG.md and docs/*.md resolves to a file inside the
//! repository (a link to `../shared` or a moved page would break in a clone).

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

#[test]
fn link_targets_are_parsed() {
    assert_eq!(
        link_targets("see [a](docs/a.md) and [b](b.md#x), not ](x"),
        ["docs/a.md", "b.md#x"]
    );
}
