//! README.md and the docs state no measured figure by hand (`tests_host::doc_figures` says
//! how a figure is accounted for): every results block equals its results file, every other
//! figure is held by a results file the page cites or declared as an input, every results
//! file is generated (its header) and shown, and the documentation stays short enough to
//! read. `NAV_RESULTS_BLESS=1` rewrites the results blocks from their files.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use tests_host::doc_figures::{
    cited_results, declared_inputs, included_part, numbers, results_blocks, unaccounted,
    unused_inputs,
};
use tests_host::docs::{current_pages, markdown_files, results_directory};
use tests_host::project_root;

/// The longest README (lines): what it is, the two commands, the data flow, the
/// integrator's snippet and a map of the docs.
const README_MAX_LINES: usize = 150;
/// The most words of all pages under docs/ together, the generated reference pages
/// (docs/reference/, one table row per parameter or key, written from the code) left out.
const DOCS_MAX_WORDS: usize = 35_000;

fn relative(path: &Path) -> String {
    path.strip_prefix(project_root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// `page` with every results block's content replaced by its file's included part.
fn blessed(page: &str, directory: &Path) -> String {
    let mut text = String::new();
    let mut skipping = false;
    for line in page.lines() {
        let trimmed = line.trim();
        if skipping && trimmed != "<!-- end results -->" {
            continue;
        }
        skipping = false;
        text.push_str(line);
        text.push('\n');
        if let Some(rest) = trimmed.strip_prefix("<!-- results:") {
            let file = directory.join(rest.trim_end_matches("-->").trim());
            let results = std::fs::read_to_string(&file).unwrap_or_default();
            text.push_str(included_part(&results));
            skipping = true;
        }
    }
    text
}

/// The problems of one page: stale blocks, unaccounted figures and unused inputs.
fn page_problems(page: &Path, bless: bool) -> Vec<String> {
    let mut text = std::fs::read_to_string(page).unwrap();
    let directory = page.parent().unwrap();
    if bless {
        let rewritten = blessed(&text, directory);
        if rewritten != text {
            std::fs::write(page, &rewritten).unwrap();
            text = rewritten;
        }
    }
    let name = relative(page);
    let (blocks, outside) = match results_blocks(&text) {
        Ok(found) => found,
        Err(error) => return vec![format!("{name}: {error}")],
    };
    let mut problems = Vec::new();
    for block in &blocks {
        match std::fs::read_to_string(directory.join(&block.file)) {
            Ok(results) if included_part(&results) == block.content => {}
            Ok(_) => problems.push(format!(
                "{name}:{}: the block differs from {} (NAV_RESULTS_BLESS=1 cargo test -p tests-host --test doc_figures copies it in)",
                block.line, block.file
            )),
            Err(error) => problems.push(format!("{name}:{}: {}: {error}", block.line, block.file)),
        }
    }
    let mut held = BTreeSet::new();
    for file in cited_results(directory, &text, &blocks) {
        if let Ok(results) = std::fs::read_to_string(&file) {
            held.extend(numbers(included_part(&results)));
        }
    }
    let inputs = declared_inputs(&text);
    for figure in unaccounted(&outside, &held, &inputs) {
        problems.push(format!(
            "{name}:{}: `{}` is neither in a results file the page cites nor a declared input",
            figure.line, figure.text
        ));
    }
    for input in unused_inputs(&outside, &inputs) {
        problems.push(format!(
            "{name}: declared input `{input}` is not on the page"
        ));
    }
    problems
}

#[test]
fn every_figure_of_the_readme_and_docs_is_generated_or_declared() {
    let root = project_root();
    let bless = std::env::var("NAV_RESULTS_BLESS").is_ok_and(|value| value == "1");
    let pages = current_pages(&root);
    assert!(pages.len() >= 8, "only {} pages found", pages.len());
    // The results files hold the measured figures, and the reference pages are written from
    // the flight's own tables (their generator's test keeps them equal); every other page must
    // account for its own.
    let results = results_directory();
    let reference = root.join("docs").join("reference");
    let problems: Vec<String> = pages
        .iter()
        .filter(|page| !page.starts_with(&results) && !page.starts_with(&reference))
        .flat_map(|page| page_problems(page, bless))
        .collect();
    assert!(
        problems.is_empty(),
        "{} figures typed by hand (put them in a results block, cite the results file that \
         holds them, or declare an input with <!-- inputs: ... -->):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn every_results_file_is_generated_and_shown() {
    let root = project_root();
    let files = markdown_files(&results_directory());
    assert!(files.len() >= 3, "only {} results files", files.len());
    let mut cited: BTreeSet<PathBuf> = BTreeSet::new();
    for page in current_pages(&root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let directory = page.parent().unwrap();
        let (blocks, _) = results_blocks(&text).unwrap_or_default();
        for file in cited_results(directory, &text, &blocks) {
            if let Ok(file) = file.canonicalize() {
                cited.insert(file);
            }
        }
    }
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let header = text.lines().next().unwrap_or("");
        assert!(
            header.starts_with("<!-- generated by `") && header.ends_with("`; do not edit -->"),
            "{}: no generated-by header: {header}",
            relative(&file)
        );
        assert!(
            cited.contains(&file.canonicalize().unwrap()),
            "{}: no page includes or links it",
            relative(&file)
        );
    }
}

#[test]
fn the_readme_and_the_docs_stay_short() {
    let root = project_root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, at most {README_MAX_LINES}"
    );
    let reference = root.join("docs").join("reference");
    let words: usize = markdown_files(&root.join("docs"))
        .iter()
        .filter(|page| !page.starts_with(&reference))
        .map(|page| {
            std::fs::read_to_string(page)
                .unwrap()
                .split_whitespace()
                .count()
        })
        .sum();
    assert!(
        words > 1_000 && words <= DOCS_MAX_WORDS,
        "docs/ has {words} words, at most {DOCS_MAX_WORDS}"
    );
}

#[test]
fn blessing_copies_each_results_file_into_its_block() {
    let directory = std::env::temp_dir().join(format!("doc-figures-{}", std::process::id()));
    std::fs::create_dir_all(directory.join("results")).unwrap();
    std::fs::write(
        directory.join("results/a.md"),
        "<!-- generated by `x`; do not edit -->\n```text\n5 m\n```\n",
    )
    .unwrap();
    let page = "intro\n<!-- results: results/a.md -->\nstale 4 m\n<!-- end results -->\nend\n";
    assert_eq!(
        blessed(page, &directory),
        "intro\n<!-- results: results/a.md -->\n```text\n5 m\n```\n<!-- end results -->\nend\n"
    );
    std::fs::remove_dir_all(&directory).unwrap();
}
