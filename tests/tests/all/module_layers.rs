//! The protocol crates' modules layer without a cycle (`docs/architecture.md`): wire layout ->
//! messages and commands -> decoders -> client and readers. Each top-level module's `crate::`
//! paths are read from its source (names re-exported at the crate root resolved through
//! `lib.rs`), and the module graph must have no cycle.
//!
//! `host-tool` stands on floors (`host-tool/src/lib.rs`): the command line, the subcommands
//! (each child of `commands/` a unit of its own), the Wireshark generator, and the shared
//! modules. Its graph must have no cycle either, and a module may use only modules on lower
//! floors: no shared module uses a subcommand or the generator, no subcommand another one.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The source of every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a file without its comment lines (doc comments included) and without its
/// unit-test modules (a `#[cfg(test)]` line, attributes, then `mod`: the rest of the file),
/// whose `use super::*` is the file's own module, not its parent.
fn code(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let end = (0..lines.len())
        .find(|&i| {
            lines[i].trim() == "#[cfg(test)]"
                && lines[i + 1..]
                    .iter()
                    .find(|l| !l.trim_start().starts_with("#["))
                    .is_some_and(|l| l.trim_start().starts_with("mod "))
        })
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .filter(|l| !l.trim_start().starts_with("//"))
        .copied()
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident_at(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The top-level items of `a, b::{c, d}, e` (commas at brace depth 0).
fn items(list: &str) -> Vec<&str> {
    let (mut out, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, c) in list.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(list[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(list[start..].trim());
    out
}

/// Each name re-exported at the root (`pub use module::{A, B}`) and the module it comes from.
fn reexports(lib: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for stmt in lib.split(';') {
        let Some(at) = stmt.find("pub use ") else {
            continue;
        };
        let path = stmt[at + 8..].trim();
        let module = ident_at(path);
        let rest = path[module.len()..].trim_start_matches("::");
        for name in rest.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
            if !name.is_empty() && name != "self" && name != "as" {
                map.insert(name.to_string(), module.to_string());
            }
        }
    }
    map
}

/// The paths a use tree names after `crate::` or `super::`: `a::b` gives `[a, b]`,
/// `{a, b::{c, d}}` gives `[a]`, `[b, c]`, `[b, d]`.
fn expand(tree: &str) -> Vec<Vec<String>> {
    let mut prefix = Vec::new();
    let mut rest = tree;
    loop {
        rest = rest.trim_start();
        if let Some(list) = rest.strip_prefix('{') {
            let mut depth = 1;
            let end = list
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '{' => 1,
                        '}' => -1,
                        _ => 0,
                    };
                    depth == 0
                })
                .map_or(list.len(), |(i, _)| i);
            return items(&list[..end])
                .into_iter()
                .flat_map(expand)
                .map(|tail| prefix.iter().cloned().chain(tail).collect())
                .collect();
        }
        let name = ident_at(rest);
        if name.is_empty() || name == "self" {
            break;
        }
        prefix.push(name.to_string());
        match rest[name.len()..].strip_prefix("::") {
            Some(after) => rest = after,
            None => break,
        }
    }
    vec![prefix]
}

/// The module path of a source file below `src`: `commands/decode/mod.rs` is
/// `[commands, decode]`, `lib.rs` is `[]`.
fn module_path(rel: &Path) -> Vec<String> {
    let mut path: Vec<String> = rel
        .components()
        .map(|c| {
            c.as_os_str()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    if path
        .last()
        .is_some_and(|l| l == "mod" || l == "lib" || l == "main")
    {
        path.pop();
    }
    path
}

/// The unit a module path belongs to: its top-level module, or, below a folder named in
/// `split` (host-tool's `commands`), the folder's child (`commands::decode`).
fn unit(path: &[String], split: &[&str]) -> Option<String> {
    let first = path.first()?;
    match path.get(1) {
        Some(child) if split.contains(&first.as_str()) => Some(format!("{first}::{child}")),
        _ => Some(first.clone()),
    }
}

/// The units each unit uses: a unit is a top-level module, or a child of a folder named in
/// `split`. Read from the `crate::` and `super::` paths of the sources (`use` trees
/// expanded, names re-exported at the crate root resolved through `lib.rs`); `main.rs` is
/// left out.
fn graph_of(src: &Path, split: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let lib = code(&fs::read_to_string(src.join("lib.rs")).unwrap());
    let names = reexports(&lib);
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut sources: Vec<(Vec<String>, String)> = Vec::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap();
        if rel == Path::new("lib.rs") || rel == Path::new("main.rs") {
            continue;
        }
        sources.push((module_path(rel), code(&fs::read_to_string(&f).unwrap())));
    }
    let modules: BTreeSet<String> = sources
        .iter()
        .filter_map(|(p, _)| p.first().cloned())
        .collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (path, text) in &sources {
        let Some(me) = unit(path, split) else {
            continue;
        };
        let deps = graph.entry(me.clone()).or_default();
        for (at, _) in text
            .match_indices("crate::")
            .chain(text.match_indices("super::"))
        {
            if text[..at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':' || c == '$')
            {
                continue;
            }
            let mut rest = &text[at..];
            let mut base: Vec<String> = Vec::new();
            if let Some(r) = rest.strip_prefix("crate::") {
                rest = r;
            } else {
                // Each `super::` climbs one module from this file's (`a/b.rs` and
                // `a/b/mod.rs` are both `a::b`).
                base = path.clone();
                while let Some(r) = rest.strip_prefix("super::") {
                    base.pop();
                    rest = r;
                }
            }
            for tail in expand(rest) {
                let mut full: Vec<String> = base.iter().cloned().chain(tail).collect();
                let Some(first) = full.first() else {
                    continue;
                };
                if !modules.contains(first) {
                    match names.get(first) {
                        Some(m) => full = vec![m.clone()],
                        None => continue,
                    }
                }
                if let Some(dep) = unit(&full, split).filter(|d| *d != me) {
                    deps.insert(dep);
                }
            }
        }
    }
    graph
}

/// The top-level modules each top-level module uses.
fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    graph_of(src, &[])
}

/// A cycle in `graph`, if there is one, as the modules along it.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == node) {
            let mut cycle = path[i..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, graph, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut Vec::new(), &mut done))
}

fn crate_src(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(name)
        .join("src")
}

#[test]
fn protocol_crates_have_no_module_cycle() {
    for name in ["aeolus-proto", "aydp-proto", "aok-proto"] {
        let g = graph(&crate_src(name));
        assert!(g.len() > 3, "{name}: modules not found: {g:?}");
        if let Some(cycle) = find_cycle(&g) {
            panic!("{name}: import cycle {}", cycle.join(" -> "));
        }
    }
}

#[test]
fn host_tool_has_no_module_cycle() {
    let g = graph_of(&crate_src("host-tool"), &["commands"]);
    assert!(g.len() > 10, "host-tool: modules not found: {g:?}");
    if let Some(cycle) = find_cycle(&g) {
        panic!("host-tool: import cycle {}", cycle.join(" -> "));
    }
}

/// The floor of a host-tool unit: 3 the command line, 2 a subcommand, 1 the Wireshark
/// generator, 0 a shared module.
fn host_tool_floor(unit: &str) -> u8 {
    match unit {
        "cli" => 3,
        u if u == "commands" || u.starts_with("commands::") => 2,
        "wireshark" => 1,
        _ => 0,
    }
}

/// The edges of `graph` that go to the same floor or up (shared modules may use each other).
fn back_doors(graph: &BTreeMap<String, BTreeSet<String>>, floor: fn(&str) -> u8) -> Vec<String> {
    let mut out = Vec::new();
    for (m, deps) in graph {
        for d in deps {
            let (from, to) = (floor(m), floor(d));
            if to > from || (to == from && from > 0) {
                out.push(format!("{m} -> {d}"));
            }
        }
    }
    out
}

#[test]
fn host_tool_uses_only_lower_floors() {
    let g = graph_of(&crate_src("host-tool"), &["commands"]);
    for unit in [
        "cli",
        "commands::decode",
        "commands::web",
        "wireshark",
        "endpoint",
        "decoders",
    ] {
        assert!(g.contains_key(unit), "host-tool: no unit {unit} in {g:?}");
    }
    assert!(g["cli"].contains("commands::decode") && g["commands::decode"].contains("decoders"));
    let doors = back_doors(&g, host_tool_floor);
    assert!(
        doors.is_empty(),
        "host-tool: a module uses one on its own floor or above: {}",
        doors.join(", ")
    );
}

#[test]
fn aok_layers_as_documented() {
    let g = graph(&crate_src("aok-proto"));
    let uses = |m: &str, d: &str| g.get(m).is_some_and(|s| s.contains(d));
    // Wire values and frames below the decoders, decoders below the client.
    assert!(uses("message", "command") && !uses("command", "message"));
    assert!(!uses("command", "decoder") && !uses("message", "decoder"));
    assert!(uses("decoder", "message") && uses("decoder", "command"));
    assert!(uses("client", "decoder") && !uses("decoder", "client"));
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let mut g = BTreeMap::new();
    g.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    g.insert("b".to_string(), BTreeSet::from(["c".to_string()]));
    g.insert("c".to_string(), BTreeSet::from(["a".to_string()]));
    assert_eq!(find_cycle(&g).map(|c| c.len()), Some(4));
    g.get_mut("c").unwrap().clear();
    assert_eq!(find_cycle(&g), None);
}

#[test]
fn the_floor_check_finds_a_back_door() {
    let mut g = BTreeMap::new();
    g.insert(
        "cli".to_string(),
        BTreeSet::from(["commands::decode".to_string()]),
    );
    g.insert(
        "commands::decode".to_string(),
        BTreeSet::from(["proto".to_string(), "commands::watch".to_string()]),
    );
    g.insert(
        "proto".to_string(),
        BTreeSet::from(["commands::decode".to_string()]),
    );
    assert_eq!(
        back_doors(&g, host_tool_floor),
        [
            "commands::decode -> commands::watch",
            "proto -> commands::decode"
        ]
    );
}

#[test]
fn use_trees_expand_to_paths() {
    let paths = expand("commands::{decode::{self, Event}, watch}, x");
    assert_eq!(
        paths,
        [
            vec!["commands", "decode"],
            vec!["commands", "decode", "Event"],
            vec!["commands", "watch"]
        ]
    );
}
