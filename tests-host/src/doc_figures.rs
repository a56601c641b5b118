//! The documentation states no measured figure by hand: a figure on a page is either inside
//! a results block, held by a results file the page cites, or declared as an input.
//!
//! - A results block is `<!-- results: PATH -->` … `<!-- end results -->`, PATH relative to
//!   the page; its content must equal the results file without its header line (the file is
//!   written by a command, see `nav_sim::output::results`).
//! - Elsewhere, a figure is a number followed by a unit of measurement ([`UNITS`]: "17,520
//!   instructions", "5.6 m", "2.5 %", "4×") or the NEES or NIS followed by a number ("NEES
//!   14.1"). It passes if its number, as written (thousands commas aside), appears in a
//!   results file the page includes or links, or if the page declares it as an input: a
//!   configured value, a specification or a paper's figure, listed in a comment
//!   `<!-- inputs: 2 ms; 100 °/s; 12 km/s -->` (each declared input must occur on the page).
//! - [`DEFINITIONS`] are conventions every page may use (1σ, a 95 % interval, the 2 ms
//!   frame).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Units of a measured quantity, longest first where one is a prefix of another.
pub const UNITS: [&str; 41] = [
    "instructions",
    "instruction",
    "cycles",
    "cycle",
    "bytes",
    "byte",
    "KiB",
    "kiB",
    "kB",
    "KB",
    "MB",
    "MiB",
    "B",
    "ms",
    "µs",
    "μs",
    "ns",
    "min",
    "h",
    "s",
    "%",
    "×",
    "km/s",
    "km",
    "m/s²",
    "m/s",
    "mm",
    "m",
    "µg",
    "mg",
    "µrad",
    "mrad",
    "rad",
    "°/s",
    "°/h",
    "°",
    "″",
    "arcsec",
    "ppm",
    "σ",
    "sigma",
];

/// Words after which a number is a measured figure: "NEES 14.1", "NIS of 3.02".
pub const PREFIXES: [&str; 2] = ["NEES", "NIS"];

/// Figures that are conventions, not measurements: confidence bounds and levels, and the
/// flight software's frame period.
pub const DEFINITIONS: [&str; 8] = [
    "1 σ", "2 σ", "3 σ", "95 %", "99 %", "99.9 %", "100 %", "2 ms",
];

/// A figure found on a page: its 1-based line, the number as written and its unit (or the
/// prefix word), and the figure as `number unit`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Figure {
    /// The 1-based line of the page.
    pub line: usize,
    /// The number as written ("17,520").
    pub number: String,
    /// `number unit` ("17,520 instructions", "NEES 14.1").
    pub text: String,
}

/// A results block of a page: the results file it names and the lines between its markers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResultsBlock {
    /// The path after `results:`, relative to the page.
    pub file: String,
    /// The 1-based line of the opening marker.
    pub line: usize,
    /// The text between the markers (each line with its newline).
    pub content: String,
}

const OPEN: &str = "<!-- results:";
const CLOSE: &str = "<!-- end results -->";

/// The results blocks of `page` and the page with their content blanked (line numbers kept).
///
/// # Errors
/// A message naming the line of a block that is not closed, or a close without an open.
pub fn results_blocks(page: &str) -> Result<(Vec<ResultsBlock>, String), String> {
    let mut blocks = Vec::new();
    let mut outside = String::new();
    let mut open: Option<ResultsBlock> = None;
    for (index, line) in page.lines().enumerate() {
        let trimmed = line.trim();
        if let Some(rest) = trimmed.strip_prefix(OPEN) {
            if let Some(block) = &open {
                return Err(format!("line {}: block not closed", block.line));
            }
            let file = rest.trim_end_matches("-->").trim().to_string();
            open = Some(ResultsBlock {
                file,
                line: index + 1,
                content: String::new(),
            });
            outside.push('\n');
        } else if trimmed == CLOSE {
            blocks.push(
                open.take()
                    .ok_or(format!("line {}: no block open", index + 1))?,
            );
            outside.push('\n');
        } else if let Some(block) = &mut open {
            block.content.push_str(line);
            block.content.push('\n');
            outside.push('\n');
        } else {
            outside.push_str(line);
            outside.push('\n');
        }
    }
    match open {
        Some(block) => Err(format!("line {}: block not closed", block.line)),
        None => Ok((blocks, outside)),
    }
}

/// The part of a results file a page includes: everything after its header line.
pub fn included_part(results_file: &str) -> &str {
    results_file.split_once('\n').map_or("", |(_, rest)| rest)
}

/// The inputs a page declares (`<!-- inputs: a; b -->`, any number of such comments), each
/// normalised as [`normalise`] does.
pub fn declared_inputs(page: &str) -> Vec<String> {
    let mut inputs = Vec::new();
    let mut rest = page;
    while let Some(start) = rest.find("<!-- inputs:") {
        let after = &rest[start + "<!-- inputs:".len()..];
        let end = after.find("-->").unwrap_or(after.len());
        inputs.extend(
            after[..end]
                .split(';')
                .map(normalise)
                .filter(|input| !input.is_empty()),
        );
        rest = &after[end..];
    }
    inputs
}

/// `figure` with one space between number and unit, whatever separated them ("2-ms",
/// "2\u{a0}ms", "2ms" → "2 ms"), thousands commas removed and surrounding space trimmed.
pub fn normalise(figure: &str) -> String {
    let figure = figure.trim();
    let chars: Vec<char> = figure.chars().collect();
    let mut text = String::new();
    for (i, &c) in chars.iter().enumerate() {
        let digit_before = i > 0 && chars[i - 1].is_ascii_digit();
        let is_separator = [' ', '-', '\u{a0}', '\u{202f}'].contains(&c);
        let digit_after = chars.get(i + 1).is_some_and(char::is_ascii_digit);
        if c == ',' && digit_before && digit_after {
            // Thousands separators: "1,420 s" is declared and held as "1420 s".
        } else if is_separator && digit_before && !digit_after {
            text.push(' ');
        } else if digit_before && !c.is_ascii_digit() && !",.e".contains(c) && !is_separator {
            text.push(' ');
            text.push(c);
        } else {
            text.push(c);
        }
    }
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The numbers of a results file, thousands commas removed (a page may write "17,520" for
/// the file's "17520").
pub fn numbers(text: &str) -> BTreeSet<String> {
    let chars: Vec<char> = text.chars().collect();
    let mut found = BTreeSet::new();
    let mut i = 0;
    while i < chars.len() {
        if chars[i].is_ascii_digit() {
            let end = number_end(&chars, i);
            found.insert(plain(&chars[i..end].iter().collect::<String>()));
            i = end;
        } else {
            i += 1;
        }
    }
    found
}

/// The number without thousands commas.
fn plain(number: &str) -> String {
    number.replace(',', "")
}

/// The end of the number starting at `start`: digits, thousands commas and a decimal point
/// followed by a digit, and an exponent.
fn number_end(chars: &[char], start: usize) -> usize {
    let at = |i: usize| chars.get(i).copied().unwrap_or(' ');
    let mut i = start;
    while at(i).is_ascii_digit() || ([',', '.'].contains(&at(i)) && at(i + 1).is_ascii_digit()) {
        i += 1;
    }
    let exponent_digit =
        |i: usize| at(i).is_ascii_digit() || (at(i) == '-' && at(i + 1).is_ascii_digit());
    if at(i) == 'e' && exponent_digit(i + 1) {
        i += 2;
        while at(i).is_ascii_digit() {
            i += 1;
        }
    }
    i
}

/// The figures of `text` ([`UNITS`] after a number, a number after [`PREFIXES`]), with
/// their lines.
pub fn figures(text: &str) -> Vec<Figure> {
    let mut found = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let chars: Vec<char> = line.chars().collect();
        let at = |i: usize| chars.get(i).copied().unwrap_or(' ');
        let mut i = 0;
        while i < chars.len() {
            // A number starts a word: not `f64`, `x2`, `3×3`, `v0.1`, `1-5`.
            let starts_word = i == 0 || {
                let before = at(i - 1);
                let joined = before.is_alphanumeric() || "_.^/'×".contains(before);
                let hyphenated = before == '-' && i >= 2 && at(i - 2).is_alphanumeric();
                !(joined || hyphenated)
            };
            if !(chars[i].is_ascii_digit() && starts_word) {
                i += 1;
                continue;
            }
            let end = number_end(&chars, i);
            let number: String = chars[i..end].iter().collect();
            if let Some(unit) = unit_after(&chars, end) {
                found.push(Figure {
                    line: index + 1,
                    text: format!("{number} {unit}"),
                    number,
                });
            } else if let Some(prefix) = prefix_before(&chars, i) {
                found.push(Figure {
                    line: index + 1,
                    text: format!("{prefix} {number}"),
                    number,
                });
            }
            i = end.max(i + 1);
        }
    }
    found
}

/// The unit of [`UNITS`] right after a number ending at `end` (after at most one space,
/// no-break space or hyphen; `×` only when attached), if it ends a word.
fn unit_after(chars: &[char], end: usize) -> Option<&'static str> {
    let at = |i: usize| chars.get(i).copied().unwrap_or(' ');
    let separated = [' ', '-', '\u{a0}', '\u{202f}'].contains(&at(end));
    let start = if separated { end + 1 } else { end };
    UNITS.into_iter().find(|unit| {
        let unit_chars: Vec<char> = unit.chars().collect();
        let matches = unit_chars
            .iter()
            .enumerate()
            .all(|(k, c)| at(start + k) == *c);
        let after = at(start + unit_chars.len());
        // A unit ends its word; `2 min(s, t)` is a function, not minutes.
        let ends_word = !(after.is_alphanumeric() || after == '_' || after == '(');
        let attached_only = *unit == "×" && separated;
        // A number before " × 12" is a dimension, not a ratio.
        matches && ends_word && !attached_only
    })
}

/// The prefix word of [`PREFIXES`] before a number starting at `start` ("NEES 14.1", "NEES
/// of 14.1", "NEES = 14.1", "NEES: 14.1").
fn prefix_before(chars: &[char], start: usize) -> Option<&'static str> {
    let before: String = chars[..start].iter().collect();
    let before = before.trim_end();
    let before = before
        .strip_suffix(" of")
        .or_else(|| before.strip_suffix('='))
        .or_else(|| before.strip_suffix(':'))
        .unwrap_or(before)
        .trim_end();
    PREFIXES.into_iter().find(|prefix| {
        before.ends_with(prefix)
            && !before[..before.len() - prefix.len()]
                .chars()
                .next_back()
                .is_some_and(char::is_alphanumeric)
    })
}

/// The results files a page cites: those of its blocks and those it links (`](…results/…)`),
/// as paths resolved against the page's directory.
pub fn cited_results(page_directory: &Path, page: &str, blocks: &[ResultsBlock]) -> Vec<PathBuf> {
    let mut cited: Vec<PathBuf> = blocks
        .iter()
        .map(|block| page_directory.join(&block.file))
        .collect();
    let mut rest = page;
    while let Some(start) = rest.find("](") {
        let after = &rest[start + 2..];
        let Some(end) = after.find(')') else { break };
        let target = after[..end].split('#').next().unwrap_or("");
        if target.contains("results/") && !target.contains("://") {
            cited.push(page_directory.join(target));
        }
        rest = &after[end..];
    }
    cited
}

/// The figures of `outside` (a page without its results blocks) that neither a number of
/// `held` nor an input of `inputs` nor a [`DEFINITIONS`] entry accounts for.
pub fn unaccounted(outside: &str, held: &BTreeSet<String>, inputs: &[String]) -> Vec<Figure> {
    figures(outside)
        .into_iter()
        .filter(|figure| {
            let text = normalise(&figure.text);
            !(held.contains(&plain(&figure.number))
                || inputs.contains(&text)
                || DEFINITIONS.contains(&text.as_str()))
        })
        .collect()
}

/// The declared inputs that do not occur as a figure on the page (a stale declaration).
pub fn unused_inputs(outside: &str, inputs: &[String]) -> Vec<String> {
    let present: BTreeSet<String> = figures(outside)
        .iter()
        .map(|figure| normalise(&figure.text))
        .collect();
    inputs
        .iter()
        .filter(|input| !present.contains(*input))
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(text: &str) -> Vec<String> {
        figures(text)
            .into_iter()
            .map(|figure| figure.text)
            .collect()
    }

    #[test]
    fn figures_with_units_and_prefixes_are_found() {
        assert_eq!(
            texts("worst frame 17,520 instructions; 33 kB of RAM, 2.5 % of the frame"),
            ["17,520 instructions", "33 kB", "2.5 %"]
        );
        assert_eq!(
            texts("5.6 m with it and 651 m without, NEES 14.1, NEES of 13.27, 4×"),
            ["5.6 m", "651 m", "NEES 14.1", "NEES 13.27", "4 ×"]
        );
        assert_eq!(
            texts("a 10-s outage, 1.25 km/s, 3 °/s, 5″, 1e-9 rad, 3.33 σ, 0.05 m/s"),
            [
                "10 s",
                "1.25 km/s",
                "3 °/s",
                "5 ″",
                "1e-9 rad",
                "3.33 σ",
                "0.05 m/s"
            ]
        );
        assert_eq!(texts("line one\n~40 s"), ["40 s"]);
        assert_eq!(figures("line one\n~40 s")[0].line, 2);
    }

    #[test]
    fn numbers_that_are_not_figures_are_not_found() {
        assert!(texts("f64, EGM2008, J2, x2, 12 × 12, 15 states, v0.1, Figs. 1-5").is_empty());
        assert!(texts("the 24-state filter, degree 60, 3-axis, `shift=0`").is_empty());
        assert!(texts("1.85 or newer, 2017, 49(4), 500 frames, 8 runs").is_empty());
        assert!(texts("mass 12 mass, 3 seconds-later 2 sine, 2 min(s, t)").is_empty());
    }

    #[test]
    fn results_blocks_are_cut_out_and_checked_for_closing() {
        let page =
            "a 5 m\n<!-- results: results/x.md -->\n```text\n7 m\n```\n<!-- end results -->\nb\n";
        let (blocks, outside) = results_blocks(page).unwrap();
        assert_eq!(blocks.len(), 1);
        assert_eq!(blocks[0].file, "results/x.md");
        assert_eq!(blocks[0].line, 2);
        assert_eq!(blocks[0].content, "```text\n7 m\n```\n");
        assert_eq!(outside, "a 5 m\n\n\n\n\n\nb\n");
        assert_eq!(texts(&outside), ["5 m"]);
        assert!(results_blocks("<!-- results: x -->\nno end\n").is_err());
        assert!(results_blocks("<!-- end results -->\n").is_err());
        assert_eq!(included_part("<!-- header -->\nbody\n"), "body\n");
    }

    #[test]
    fn a_figure_is_accounted_for_by_a_results_number_an_input_or_a_definition() {
        let held = numbers("worst 17520 instructions, NEES 14.07, 3.038e-5");
        assert!(held.contains("17520") && held.contains("14.07") && held.contains("3.038e-5"));
        let inputs = declared_inputs("<!-- inputs: 2 ms; 100 °/s -->\n<!-- inputs: 12 km/s -->");
        assert_eq!(inputs, ["2 ms", "100 °/s", "12 km/s"]);
        let page = "17,520 instructions, NEES 14.07, a 2-ms frame at 100 °/s, 3σ, 95 % bound,\n\
                    NEES 14.1 and 26,600 instructions";
        let missing: Vec<String> = unaccounted(page, &held, &inputs)
            .into_iter()
            .map(|figure| format!("{}: {}", figure.line, figure.text))
            .collect();
        assert_eq!(missing, ["2: NEES 14.1", "2: 26,600 instructions"]);
        assert_eq!(unused_inputs(page, &inputs), ["12 km/s"]);
    }

    #[test]
    fn figures_are_normalised_to_one_space() {
        assert_eq!(normalise(" 2-ms "), "2 ms");
        assert_eq!(normalise("3σ"), "3 σ");
        assert_eq!(normalise("2\u{a0}ms"), "2 ms");
        assert_eq!(normalise("1.5e-9 rad"), "1.5e-9 rad");
        assert_eq!(normalise("12 km/s"), "12 km/s");
        assert_eq!(normalise("1,420 s"), "1420 s");
        assert_eq!(normalise("1, 2 s"), "1, 2 s");
    }

    #[test]
    fn cited_results_are_blocks_and_links() {
        let blocks = [ResultsBlock {
            file: "results/a.md".into(),
            line: 1,
            content: String::new(),
        }];
        let cited = cited_results(
            Path::new("pages"),
            "see [b](results/b.md#x) and [c](guide.md)",
            &blocks,
        );
        assert_eq!(
            cited,
            [
                PathBuf::from("pages/results/a.md"),
                PathBuf::from("pages/results/b.md")
            ]
        );
    }
}
