//! No recursion in the flight binary's call graph. The test command disassembles the
//! panic-never flight ELF (`llvm-objdump -d`, the whole flight path: scheduler, filter,
//! calibration manager, input checks, after LTO) and passes the listing in
//! `NAV_FLIGHT_DISASSEMBLY`; this test builds the call graph from the direct calls and tail
//! calls (`bl`, and `b`/`b.w` into another function) and requires it to be acyclic
//! (Tarjan's strongly connected components, iterative: no SCC with more than one function and
//! no function calling itself). Indirect calls (`blx`, `bx` to a register other than `lr`)
//! cannot be followed statically, so the test also requires there are none.
//!
//! Instructions past a function's size in the ELF symbol table (`NAV_FLIGHT_ELF`: padding and
//! literal pools that the disassembler decodes as code) are not part of the function and are
//! skipped; a function whose symbol has no size (e.g. defmt's `_defmt_timestamp`, defined in
//! assembly) ends at its first unconditional return (`pop {…, pc}` or `bx lr`).
//!
//! Ignored by default (needs the firmware build); `scripts/test.sh` runs it.

use std::collections::HashMap;

/// Function name of a branch target `<name>` or `<name+0x10>`, and whether it had an offset.
fn target_of(operand: &str) -> Option<(&str, bool)> {
    let inner = operand.split('<').nth(1)?.split('>').next()?;
    Some(match inner.split_once('+') {
        Some((name, _)) => (name, true),
        None => (inner, false),
    })
}

/// The call graph: function → callees (by name). `sizes`: function name → size in bytes
/// (instructions at or past the end are skipped); a function without a size is read whole.
fn call_graph(
    listing: &str,
    sizes: &HashMap<String, u64>,
) -> (Vec<String>, HashMap<String, Vec<String>>, Vec<String>) {
    let mut functions = Vec::new();
    let mut edges: HashMap<String, Vec<String>> = HashMap::new();
    let mut indirect = Vec::new();
    let mut current: Option<String> = None;
    let mut end = u64::MAX;
    let mut sized = false;
    for line in listing.lines() {
        let trimmed = line.trim();
        if let Some(header) = trimmed.strip_suffix(">:") {
            if let Some((address, name)) = header.split_once(" <") {
                current = Some(name.to_string());
                functions.push(name.to_string());
                let start = u64::from_str_radix(address, 16).unwrap_or(0);
                sized = sizes.contains_key(name);
                end = sizes
                    .get(name)
                    .map_or(u64::MAX, |size| start.saturating_add(*size));
                continue;
            }
        }
        let Some(function) = &current else { continue };
        // "addr:  mnemonic operands"
        let Some((address, instruction)) = trimmed.split_once(':') else {
            continue;
        };
        match u64::from_str_radix(address.trim(), 16) {
            Ok(address) if address >= end => continue,
            _ => {}
        }
        let mut parts = instruction.split_whitespace();
        let Some(mnemonic) = parts.next() else {
            continue;
        };
        let operands: String = parts.collect::<Vec<_>>().join(" ");
        let base = mnemonic.split('.').next().unwrap_or(mnemonic);
        let returns = (base == "pop" && operands.contains("pc"))
            || (base == "bx" && operands.starts_with("lr"));
        if returns && !sized {
            end = 0; // what follows up to the next symbol is padding
        }
        match base {
            "bl" => {
                if let Some((name, _)) = target_of(&operands) {
                    edges
                        .entry(function.clone())
                        .or_default()
                        .push(name.to_string());
                }
            }
            // Conditional and unconditional branches: a tail call when the target is another
            // function (intra-function branches name the current function with an offset).
            "b" | "beq" | "bne" | "bcs" | "bcc" | "bhs" | "blo" | "bmi" | "bpl" | "bvs" | "bvc"
            | "bhi" | "bls" | "bge" | "blt" | "bgt" | "ble" => {
                if let Some((name, has_offset)) = target_of(&operands) {
                    if name != function || !has_offset {
                        edges
                            .entry(function.clone())
                            .or_default()
                            .push(name.to_string());
                    }
                }
            }
            "blx" => indirect.push(format!("{function}: {trimmed}")),
            "bx" if !operands.starts_with("lr") => indirect.push(format!("{function}: {trimmed}")),
            _ => {}
        }
    }
    (functions, edges, indirect)
}

/// Strongly connected components with more than one member, or with a self edge (iterative
/// Tarjan, so the checker has no recursion either).
fn cycles(functions: &[String], edges: &HashMap<String, Vec<String>>) -> Vec<Vec<String>> {
    let index_of: HashMap<&str, usize> = functions
        .iter()
        .enumerate()
        .map(|(i, f)| (f.as_str(), i))
        .collect();
    let successors: Vec<Vec<usize>> = functions
        .iter()
        .map(|f| {
            edges
                .get(f)
                .map(|callees| {
                    callees
                        .iter()
                        .filter_map(|c| index_of.get(c.as_str()).copied())
                        .collect()
                })
                .unwrap_or_default()
        })
        .collect();
    let count = functions.len();
    let mut index = vec![usize::MAX; count];
    let mut low = vec![0; count];
    let mut on_stack = vec![false; count];
    let mut stack = Vec::new();
    let mut next_index = 0;
    let mut found = Vec::new();
    for root in 0..count {
        if index[root] != usize::MAX {
            continue;
        }
        let mut work = vec![(root, 0_usize)];
        while let Some((node, child)) = work.pop() {
            if child == 0 && index[node] == usize::MAX {
                index[node] = next_index;
                low[node] = next_index;
                next_index += 1;
                stack.push(node);
                on_stack[node] = true;
            }
            if let Some(&next) = successors[node].get(child) {
                work.push((node, child + 1));
                if index[next] == usize::MAX {
                    work.push((next, 0));
                } else if on_stack[next] {
                    low[node] = low[node].min(index[next]);
                }
                continue;
            }
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[node]);
            }
            if low[node] == index[node] {
                let mut component = Vec::new();
                while let Some(member) = stack.pop() {
                    on_stack[member] = false;
                    component.push(member);
                    if member == node {
                        break;
                    }
                }
                let self_loop = successors[node].contains(&node);
                if component.len() > 1 || self_loop {
                    found.push(component.iter().map(|&m| functions[m].clone()).collect());
                }
            }
        }
    }
    found
}

/// Function symbol sizes from the ELF symbol table.
fn function_sizes(elf: &[u8]) -> HashMap<String, u64> {
    use object::{Object, ObjectSymbol, SymbolKind};
    let file = object::File::parse(elf).unwrap();
    file.symbols()
        .filter(|symbol| symbol.kind() == SymbolKind::Text && symbol.size() > 0)
        .filter_map(|symbol| Some((symbol.name().ok()?.to_string(), symbol.size())))
        .collect()
}

#[test]
fn the_checker_finds_a_cycle_and_a_self_call() {
    let listing = "\
00000010 <a>:
      10:  bl 0x20 <b>
00000020 <b>:
      20:  b.w 0x10 <a>
00000030 <c>:
      30:  bne 0x32 <c+0x2>
      32:  bl 0x30 <c>
00000040 <d>:
      40:  bl 0x10 <a>
      42:  bx lr
";
    let no_sizes = HashMap::new();
    let (functions, edges, indirect) = call_graph(listing, &no_sizes);
    let found = cycles(&functions, &edges);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(indirect.is_empty());
    // Past e's 2-byte size the "call" back to d is a literal pool, not code.
    let pool =
        "00000040 <d>:\n 40: bl 0x10 <e>\n00000010 <e>:\n 10: b.w 0x10 <e+0x4>\n 12: bl 0x40 <d>\n";
    let sizes = HashMap::from([("e".to_string(), 2)]);
    let (functions, edges, _) = call_graph(pool, &sizes);
    assert!(cycles(&functions, &edges).is_empty());
    let (functions, edges, _) = call_graph(pool, &no_sizes);
    assert_eq!(cycles(&functions, &edges).len(), 1);
    // Unsized: the first unconditional return ends the function.
    let padding = "00000040 <d>:\n 40: bl 0x10 <e>\n00000010 <e>:\n 10: bx lr\n 12: bl 0x40 <d>\n";
    let (functions, edges, _) = call_graph(padding, &no_sizes);
    assert!(cycles(&functions, &edges).is_empty());
}

#[test]
#[ignore = "needs the flight firmware's disassembly; run by scripts/test.sh"]
fn the_flight_binary_has_no_recursion_and_no_indirect_call() {
    let path = std::env::var("NAV_FLIGHT_DISASSEMBLY")
        .expect("NAV_FLIGHT_DISASSEMBLY: llvm-objdump -d listing of the flight ELF");
    let listing = std::fs::read_to_string(path).unwrap();
    let elf_path = std::env::var("NAV_FLIGHT_ELF").expect("NAV_FLIGHT_ELF: the flight ELF");
    let elf = std::fs::read(elf_path).unwrap();
    let sizes = function_sizes(&elf);
    let (functions, edges, indirect) = call_graph(&listing, &sizes);
    let calls: usize = edges.values().map(Vec::len).sum();
    println!(
        "flight binary: {} functions, {calls} direct calls and tail calls, {} indirect calls",
        functions.len(),
        indirect.len()
    );
    assert!(functions.len() > 10, "the listing looks empty");
    assert!(indirect.is_empty(), "indirect calls: {indirect:?}");
    let found = cycles(&functions, &edges);
    assert!(
        found.is_empty(),
        "recursion in the flight binary: {found:?}"
    );
}
