//! Every relative link in README.md, CHANGELOG.md and the pages under docs/ resolves to a
//! file inside the repository (a link to `../shared` or a moved page would break in a clone),
//! README.md and the pages under docs/ describe the present (no sessions, rounds or issue
//! numbers), and so do the comments of the code (no issue numbers).

use std::path::{Path, PathBuf};

use tests_host::docs::current_pages;

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
    let mut pages = current_pages(&root);
    pages.push(root.join("CHANGELOG.md"));
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

/// The documentation pages a text names as `docs/<page>.md` (or a page under a docs/
/// subdirectory), in order.
fn named_pages(text: &str) -> Vec<String> {
    let mut pages = Vec::new();
    for (at, _) in text.match_indices("docs/") {
        let preceded = text[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '-');
        let rest = &text[at..];
        let end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || "/-_.".contains(c)))
            .unwrap_or(rest.len());
        let name = rest[..end].trim_end_matches('.');
        if !preceded && name.ends_with(".md") {
            pages.push(name.to_string());
        }
    }
    pages
}

/// Code, scripts and scenarios name documentation pages in their comments and messages
/// (`see docs/guide/model.md`); a moved or renamed page must take them along.
#[test]
fn every_docs_page_the_code_and_scenarios_name_exists() {
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
        "scripts",
    ] {
        source_files(&root.join(directory), &mut files);
    }
    for entry in std::fs::read_dir(root.join("nav-sim/scenarios")).unwrap() {
        files.push(entry.unwrap().path());
    }
    let this_test = root.join("tests-host/tests/doc_links.rs");
    let mut named = 0;
    let mut missing = Vec::new();
    for file in files.iter().filter(|file| **file != this_test) {
        let text = std::fs::read_to_string(file).unwrap_or_default();
        for page in named_pages(&text) {
            named += 1;
            if !root.join(&page).is_file() {
                missing.push(format!("{}: {page}", file.display()));
            }
        }
    }
    // The scenarios alone name pages a hundred times: a parser that finds few is broken.
    assert!(named >= 100, "only {named} page names found");
    assert!(
        missing.is_empty(),
        "pages that do not exist:\n{}",
        missing.join("\n")
    );
}

#[test]
fn page_names_are_found_in_text() {
    assert_eq!(
        named_pages(
            "see docs/guide/model.md. and (docs/results/a.md), not mydocs/x.md or docs/x.rs"
        ),
        ["docs/guide/model.md", "docs/results/a.md"]
    );
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

/// Units of a measurement of the software's own cost: instructions and cycles, memory in
/// bytes, and execution times below the millisecond (a time in ms or s is the model's: the
/// 2 ms frame, a measurement 10 ms late).
const COST_UNITS: [&str; 22] = [
    "instruction",
    "instructions",
    "instr",
    "cycle",
    "cycles",
    "byte",
    "bytes",
    "kilobyte",
    "kilobytes",
    "B",
    "kB",
    "KB",
    "KiB",
    "kiB",
    "MB",
    "MiB",
    "ns",
    "nanoseconds",
    "µs",
    "μs",
    "us",
    "microseconds",
];

/// Byte counts that define a wire format (the replay log's records and header, the IMU's SPI
/// packet, the 8-byte words of the replay setup and output): a definition, like the constant
/// beside it, not a measurement. Each is matched with the word after it (up to a hyphen).
const WIRE_FORMAT_SIZES: [&str; 9] = [
    "80-byte record",
    "80 bytes each",
    "80-byte records",
    "80-byte buffer",
    "16-byte header",
    "8-byte word",
    "8-byte words",
    "8-byte little",
    "34 bytes,",
];

/// The first figure in `text` that states a cost of the software (a number followed by a
/// unit of [`COST_UNITS`], e.g. "8,384 bytes", "~2 KB", "10,400 instructions", "600 ns",
/// "a 672-byte struct"), with the word after it; `None` if there is none. A number is digits
/// with thousands commas, a decimal point or an exponent, and a `k`/`M` multiplier; it starts
/// a word (not `f64`, `x2`, `3×3`), and one space or hyphen may separate it from the unit.
fn cost_figure(text: &str) -> Option<String> {
    let chars: Vec<char> = text.chars().collect();
    let at = |i: usize| chars.get(i).copied().unwrap_or(' ');
    let starts_word = |i: usize| {
        i == 0 || {
            let before = at(i - 1);
            !(before.is_alphanumeric() || "_.×^/'-".contains(before))
        }
    };
    let word_at = |start: usize| {
        let start = start.min(chars.len());
        let mut i = start;
        while at(i).is_alphabetic() {
            i += 1;
        }
        (chars[start..i].iter().collect::<String>(), i)
    };
    let separated = |i: usize| [' ', '-', '\u{a0}', '\u{202f}'].contains(&at(i));
    for start in 0..chars.len() {
        if !(chars[start].is_ascii_digit() && starts_word(start)) {
            continue;
        }
        let mut i = start;
        while at(i).is_ascii_digit() || ([',', '.'].contains(&at(i)) && at(i + 1).is_ascii_digit())
        {
            i += 1;
        }
        if at(i) == 'e' && (at(i + 1).is_ascii_digit() || at(i + 1) == '-') {
            i += 2;
            while at(i).is_ascii_digit() {
                i += 1;
            }
        }
        let mut unit_start = if separated(i) { i + 1 } else { i };
        let (mut unit, mut end) = word_at(unit_start);
        if ["k", "K", "M", "thousand"].contains(&unit.as_str()) && separated(end) {
            unit_start = end + 1;
            (unit, end) = word_at(unit_start);
        }
        if unit.is_empty() || !COST_UNITS.contains(&unit.as_str()) {
            continue;
        }
        let (next, next_end) = word_at(end + usize::from(at(end) == ' '));
        let mut figure: String = chars[start..end].iter().collect();
        if !next.is_empty() {
            figure = chars[start..next_end].iter().collect();
        } else if at(end) == ',' {
            figure.push(',');
        }
        if !WIRE_FORMAT_SIZES.contains(&figure.as_str()) {
            return Some(figure);
        }
    }
    None
}

/// The comments of a Rust source file, each run of consecutive comment lines joined into one
/// text (a figure may be split across lines): whole-line `//`, `///` and `//!` comments, and
/// a `//` comment after code outside a string literal.
fn comments(source: &str) -> Vec<(usize, String)> {
    let mut found: Vec<(usize, String)> = Vec::new();
    let mut open = false;
    for (index, line) in source.lines().enumerate() {
        let trimmed = line.trim_start();
        let comment = if trimmed.starts_with("//") {
            Some(trimmed.trim_start_matches('/').trim_start_matches('!'))
        } else {
            let mut quotes = 0;
            let mut after_code = None;
            for (at, c) in line.char_indices() {
                if c == '"' {
                    quotes += 1;
                } else if quotes % 2 == 0 && line[at..].starts_with("//") {
                    after_code = Some(&line[at + 2..]);
                    break;
                }
            }
            after_code
        };
        match (comment, open) {
            (Some(text), true) if trimmed.starts_with("//") => {
                if let Some((_, joined)) = found.last_mut() {
                    joined.push(' ');
                    joined.push_str(text.trim());
                }
            }
            (Some(text), _) => found.push((index + 1, text.trim().to_string())),
            (None, _) => {}
        }
        open = comment.is_some() && trimmed.starts_with("//");
    }
    found
}

/// The flight crates' comments give reasons, not measurements: a figure of the software's
/// cost (instructions, cycles, bytes, an execution time) goes stale with the next change of
/// the code or the compiler, so it lives in docs/guide/performance.md or docs/guide/reliability.md next
/// to the command that measures it again.
#[test]
fn the_flight_code_comments_state_no_measured_cost() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .unwrap();
    let mut files = Vec::new();
    for directory in ["nav-core", "nav-fsw"] {
        source_files(&root.join(directory), &mut files);
    }
    let sources: Vec<&PathBuf> = files
        .iter()
        .filter(|file| file.extension().is_some_and(|extension| extension == "rs"))
        .collect();
    assert!(sources.len() >= 40, "only {} sources found", sources.len());
    let mut figures = Vec::new();
    for file in sources {
        let text = std::fs::read_to_string(file).unwrap();
        for (line, comment) in comments(&text) {
            if let Some(figure) = cost_figure(&comment) {
                figures.push(format!(
                    "{}: comment from line {line}: `{figure}`",
                    file.display()
                ));
            }
        }
    }
    assert!(
        figures.is_empty(),
        "measured figures in comments (move them to docs/guide/performance.md with their command):\n{}",
        figures.join("\n")
    );
}

#[test]
fn cost_figures_are_found_and_physics_is_not() {
    for (text, figure) in [
        (
            "the frame loop takes 8,384 bytes of stack",
            "8,384 bytes of",
        ),
        ("the filter (6 kB) is reset", "6 kB"),
        ("a copy of the ~2 KB model", "2 KB model"),
        ("costs 10,400 instructions", "10,400 instructions"),
        ("about 600 ns on the host", "600 ns on"),
        ("1.54 µs per frame", "1.54 µs per"),
        ("the 672-byte measurement", "672-byte measurement"),
        ("a 4.8 kB filter", "4.8 kB filter"),
        ("(27.6 kB: host use)", "27.6 kB"),
        ("10k instructions", "10k instructions"),
        ("~540\ninstructions", "540\ninstructions"),
        ("(12,000 cycles)", "12,000 cycles"),
        ("2 KiB", "2 KiB"),
        ("84 KB in the propagation", "84 KB in"),
    ] {
        let text = text.replace('\n', " ");
        let figure = figure.replace('\n', " ");
        assert_eq!(
            cost_figure(&text).as_deref(),
            Some(figure.as_str()),
            "{text}"
        );
    }
    for text in [
        "the 2 ms frame at 500 Hz",
        "a 10″ star sensor, 1e-9 rad",
        "a GNSS fix 10 ms late, 15 states",
        "the 3×3 B block, f64 values, x2 bytes",
        "records of [`RECORD_SIZE`] = 80 bytes each",
        "the documented 80-byte records; a 16-byte header; nine 8-byte words",
        "as 8-byte little-endian words",
        "reads [`PACKET_SIZE`] = 34 bytes, all",
        "the largest instruction count",
        "Σ_k over 15 terms k of 6 columns s",
    ] {
        assert_eq!(cost_figure(text), None, "{text}");
    }
}

#[test]
fn comments_are_joined_per_run_and_strings_are_not_comments() {
    let source = "/// a figure split\n/// across lines\nlet url = \"http://x\"; // after code\nfn f() {}\n//! module\n";
    assert_eq!(
        comments(source),
        [
            (1, "a figure split across lines".to_string()),
            (3, "after code".to_string()),
            (5, "module".to_string()),
        ]
    );
}
