//! The library's layering (`src/lib.rs`, "Layers"), derived from the sources: every module
//! imports only from its own layer and the layers below, no two source files import each
//! other in a circle, and no Rust file of the repository is longer than a reader can hold.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's layers from the bottom, with their rank: a module may import from a layer
/// of lower rank, or from its own layer.
const LAYERS: [(&str, u32); 8] = [
    ("scenario", 0),
    ("output", 0),
    ("setup", 1),
    ("world", 2),
    ("logs", 3),
    ("harness", 4),
    ("campaign", 5),
    ("studies", 6),
];

/// Longest source file (lines).
const MAX_FILE_LINES: usize = 800;

fn source_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(directory: &Path, files: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(directory)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|extension| extension == "rs") {
            files.push(path);
        }
    }
}

/// The module path of a library source file (`world/truth.rs` → `["world", "truth"]`,
/// `world/mod.rs` → `["world"]`, `lib.rs` → `[]`).
fn module_path(relative: &Path) -> Vec<String> {
    let mut parts: Vec<String> = relative
        .iter()
        .map(|part| part.to_string_lossy().into_owned())
        .collect();
    let file = parts.pop().unwrap();
    let stem = file.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The code of a file without its comments (line comments and doc comments).
fn code_lines(text: &str) -> impl Iterator<Item = &str> {
    text.lines()
        .map(|line| line.split("//").next().unwrap_or(""))
        .filter(|line| !line.trim().is_empty())
}

/// The paths one use-tree names, starting at `text` (after its `crate::`, `super::` or
/// `self::`), each appended to `prefix`: `a::b`, `a::{b, c::{d, self}}`, `a::*`,
/// `a::b as c`. Returns the text after the tree. Grouped imports are expanded, so
/// `crate::setup::{dispersion, SetupError}` names `setup::dispersion`, which a reader of the
/// first segment alone would miss.
fn use_tree<'a>(mut text: &'a str, prefix: &[String], paths: &mut Vec<Vec<String>>) -> &'a str {
    let mut path = prefix.to_vec();
    loop {
        text = text.trim_start();
        if let Some(inner) = text.strip_prefix('{') {
            text = inner;
            loop {
                text = text.trim_start();
                if let Some(after) = text.strip_prefix('}') {
                    return after;
                }
                text = use_tree(text, &path, paths).trim_start();
                if let Some(after) = text.strip_prefix(',') {
                    text = after;
                } else {
                    return text.strip_prefix('}').unwrap_or(text);
                }
            }
        }
        let name: String = text
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '*')
            .collect();
        text = &text[name.len()..];
        if !name.is_empty() && name != "self" && name != "*" {
            path.push(name);
        }
        match text.strip_prefix("::") {
            Some(next) => text = next,
            None => {
                paths.push(path);
                // `a::b as c`: the alias names nothing of the crate.
                return match text.trim_start().strip_prefix("as ") {
                    Some(alias) => alias
                        .trim_start()
                        .trim_start_matches(|c: char| c.is_ascii_alphanumeric() || c == '_'),
                    None => text,
                };
            }
        }
    }
}

/// Every `crate::…`, `super::…` and `self::…` path in `code`, in any form (a `use`, a
/// grouped `use`, a path-qualified call), resolved to an absolute path, for a file whose
/// module is `module` (`is_mod_file`: a `mod.rs`, whose `super` is its parent). A group
/// directly at the crate root (`crate::{a::X, b::Y}`) is returned as the one path `["{"]`.
fn referenced_paths(code: &str, module: &[String], is_mod_file: bool) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    let bytes = code.as_bytes();
    for keyword in ["crate::", "super::", "self::"] {
        for (at, _) in code.match_indices(keyword) {
            let starts_word = at == 0
                || !(bytes[at - 1].is_ascii_alphanumeric()
                    || bytes[at - 1] == b'_'
                    || bytes[at - 1] == b':');
            if !starts_word {
                continue;
            }
            let rest = &code[at + keyword.len()..];
            if keyword == "crate::" && rest.starts_with('{') {
                paths.push(vec!["{".to_string()]);
                continue;
            }
            // `super` of a file module is its parent; of a `mod.rs` (or of an inline `mod
            // tests` inside a file) the parent of the directory. `self` is the module.
            let base: Vec<String> = match keyword {
                "crate::" => Vec::new(),
                "super::" if !is_mod_file => module[..module.len().saturating_sub(1)].to_vec(),
                _ => module.to_vec(),
            };
            let mut named = Vec::new();
            use_tree(rest, &[], &mut named);
            for segments in named {
                let mut absolute = base.clone();
                for segment in segments {
                    if segment == "super" {
                        absolute.pop();
                    } else {
                        absolute.push(segment);
                    }
                }
                paths.push(absolute);
            }
        }
    }
    paths
}

struct Source {
    module: Vec<String>,
    file: PathBuf,
    text: String,
}

fn library_sources() -> Vec<Source> {
    let root = source_root();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    files
        .into_iter()
        .filter(|file| !file.starts_with(root.join("bin")) && !file.ends_with("main.rs"))
        .map(|file| {
            let relative = file.strip_prefix(&root).unwrap().to_path_buf();
            Source {
                module: module_path(&relative),
                text: std::fs::read_to_string(&file).unwrap(),
                file: relative,
            }
        })
        .collect()
}

fn rank(layer: &str) -> Option<u32> {
    LAYERS
        .iter()
        .find(|(name, _)| *name == layer)
        .map(|(_, rank)| *rank)
}

/// The module graph: for each source module, the source modules it imports (the longest
/// module prefix of each path it names). Inline `mod tests` blocks count as their file.
fn module_graph(sources: &[Source]) -> (Graph, Vec<String>) {
    let modules: BTreeSet<Vec<String>> =
        sources.iter().map(|source| source.module.clone()).collect();
    let mut graph = BTreeMap::new();
    let mut problems = Vec::new();
    for source in sources {
        let code: String = code_lines(&source.text).collect::<Vec<_>>().join("\n");
        let is_mod_file = source.file.ends_with("mod.rs") || source.file.ends_with("lib.rs");
        let mut targets = BTreeSet::new();
        for path in referenced_paths(&code, &source.module, is_mod_file) {
            if path.last().is_some_and(|segment| segment == "{") && path.len() == 1 {
                problems.push(format!(
                    "{}: `crate::{{…}}` groups several modules in one import; write one `use` per module",
                    source.file.display()
                ));
                continue;
            }
            let target = (1..=path.len())
                .rev()
                .map(|length| path[..length].to_vec())
                .find(|prefix| modules.contains(prefix));
            match target {
                Some(target) if target.is_empty() && !source.module.is_empty() => problems.push(format!(
                    "{}: `crate::{}` goes through the crate root's re-exports; name the layer's module",
                    source.file.display(),
                    path.join("::")
                )),
                Some(target) if target != source.module => {
                    targets.insert(target);
                }
                _ => {}
            }
        }
        graph.insert(source.module.clone(), targets);
    }
    (graph, problems)
}

#[test]
fn every_module_imports_only_from_its_layer_and_the_layers_below() {
    let sources = library_sources();
    let (graph, mut problems) = module_graph(&sources);
    for (module, targets) in &graph {
        let Some(layer) = module.first() else {
            continue;
        };
        let Some(own) = rank(layer) else {
            problems.push(format!(
                "module {} is in no layer of LAYERS",
                module.join("::")
            ));
            continue;
        };
        for target in targets {
            let Some(target_layer) = target.first() else {
                continue;
            };
            let allowed =
                target_layer == layer || rank(target_layer).is_some_and(|other| other < own);
            if !allowed {
                problems.push(format!(
                    "{} (layer {layer}) imports {} (layer {target_layer}): an import upward or across",
                    module.join("::"),
                    target.join("::")
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

type Graph = BTreeMap<Vec<String>, BTreeSet<Vec<String>>>;

/// A cycle of `graph` (its modules in import order, the first repeated at the end), if any:
/// a depth-first search whose explicit stack is the path.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    let mut done: BTreeSet<Vec<String>> = BTreeSet::new();
    for start in graph.keys() {
        if done.contains(start) {
            continue;
        }
        let mut path: Vec<Vec<String>> = vec![start.clone()];
        let mut pending: Vec<Vec<Vec<String>>> = vec![graph[start].iter().cloned().collect()];
        while let Some(next_targets) = pending.last_mut() {
            let Some(next) = next_targets.pop() else {
                pending.pop();
                if let Some(finished) = path.pop() {
                    done.insert(finished);
                }
                continue;
            };
            if let Some(at) = path.iter().position(|module| *module == next) {
                let mut cycle: Vec<String> =
                    path[at..].iter().map(|module| module.join("::")).collect();
                cycle.push(next.join("::"));
                return Some(cycle);
            }
            if !done.contains(&next) {
                pending.push(
                    graph
                        .get(&next)
                        .map(|targets| targets.iter().cloned().collect())
                        .unwrap_or_default(),
                );
                path.push(next);
            }
        }
    }
    None
}

#[test]
fn no_source_files_import_each_other_in_a_circle() {
    let (graph, _) = module_graph(&library_sources());
    if let Some(cycle) = find_cycle(&graph) {
        panic!("import cycle: {}", cycle.join(" -> "));
    }
}

#[test]
fn the_checker_sees_an_upward_import_a_cycle_and_a_grouped_import() {
    let source = |module: &str, text: &str| Source {
        module: module.split("::").map(str::to_string).collect(),
        file: PathBuf::from(format!("{}.rs", module.replace("::", "/"))),
        text: text.to_string(),
    };
    let sources = vec![
        source(
            "scenario",
            "use crate::world::truth::Truth; // crate::harness in a comment\n",
        ),
        source("world::truth", "use super::sensors::X;\n"),
        source(
            "world::sensors",
            "pub fn f() { crate::world::truth::g() }\n",
        ),
        source("setup", "use crate::{scenario::A, world::B};\n"),
    ];
    let (graph, problems) = module_graph(&sources);
    let strings =
        |module: &str| -> Vec<String> { module.split("::").map(str::to_string).collect() };
    assert_eq!(
        graph[&strings("scenario")],
        BTreeSet::from([strings("world::truth")])
    );
    assert!(graph[&strings("world::truth")].contains(&strings("world::sensors")));
    assert!(graph[&strings("world::sensors")].contains(&strings("world::truth")));
    assert_eq!(problems.len(), 1, "{problems:?}");
    let cycle = find_cycle(&graph).expect("truth and sensors import each other");
    assert!(cycle.contains(&"world::sensors".to_string()), "{cycle:?}");
    let mut acyclic = graph.clone();
    acyclic.insert(strings("world::sensors"), BTreeSet::new());
    assert_eq!(find_cycle(&acyclic), None);
}

#[test]
fn the_checker_sees_grouped_nested_aliased_and_self_imports() {
    let module = |path: &str| -> Vec<String> { path.split("::").map(str::to_string).collect() };
    let code = "use crate::setup::{dispersion, streams::{self, Stream as S}, SetupError};\n\
                use super::{launch::*, prior};\n\
                fn f() { self::inner::g(); crate::world::truth::h() }";
    let mut paths = referenced_paths(code, &module("setup::fsw"), false);
    paths.sort();
    let expected: Vec<Vec<String>> = [
        "setup::SetupError",
        "setup::dispersion",
        "setup::fsw::inner::g",
        "setup::launch",
        "setup::prior",
        "setup::streams",
        "setup::streams::Stream",
        "world::truth::h",
    ]
    .iter()
    .map(|path| module(path))
    .collect();
    assert_eq!(paths, expected);
}

/// The same length rule in every crate of the repository (flight, simulator, firmware, tests,
/// fuzz targets, the integrator example), not only in this library.
#[test]
fn no_rust_file_of_the_repository_is_longer_than_the_limit() {
    let repository = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for crate_dir in [
        "nav-core",
        "nav-fsw",
        "nav-c",
        "nav-sim",
        "tests-host",
        "qemu",
        "fuzz",
        "examples",
    ] {
        for tree in ["src", "tests", "benches", "fuzz_targets", "integrator/src"] {
            let directory = repository.join(crate_dir).join(tree);
            if directory.is_dir() {
                rust_files(&directory, &mut files);
            }
        }
    }
    assert!(files.len() > 100, "found only {} Rust files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|file| {
            let lines = std::fs::read_to_string(file).unwrap().lines().count();
            (lines > MAX_FILE_LINES).then(|| format!("{} has {lines} lines", file.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "longer than {MAX_FILE_LINES} lines:\n{}",
        long.join("\n")
    );
}
