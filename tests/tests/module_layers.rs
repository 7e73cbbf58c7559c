//! The protocol crates' modules layer without a cycle (`docs/architecture.md`): wire layout ->
//! messages and commands -> decoders -> client and readers. Each top-level module's `crate::`
//! paths are read from its source (names re-exported at the crate root resolved through
//! `lib.rs`), and the module graph must have no cycle.

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

/// The code of a file without its comment lines (doc comments included).
fn code(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
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

/// The top-level modules each top-level module uses.
fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let lib = code(&fs::read_to_string(src.join("lib.rs")).unwrap());
    let names = reexports(&lib);
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut sources: BTreeMap<String, String> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" {
            continue;
        }
        let text = code(&fs::read_to_string(&f).unwrap());
        sources.entry(module).or_default().push_str(&text);
    }
    let modules: BTreeSet<String> = sources.keys().cloned().collect();
    let resolve = |name: &str| -> Option<String> {
        if modules.contains(name) {
            Some(name.to_string())
        } else {
            names.get(name).cloned()
        }
    };
    let mut graph = BTreeMap::new();
    for (module, text) in &sources {
        let mut deps = BTreeSet::new();
        for (at, _) in text.match_indices("crate::") {
            let rest = &text[at + 7..];
            let targets: Vec<&str> = if let Some(list) = rest.strip_prefix('{') {
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
                items(&list[..end]).into_iter().map(ident_at).collect()
            } else {
                vec![ident_at(rest)]
            };
            for t in targets {
                if let Some(dep) = resolve(t).filter(|d| d != module) {
                    deps.insert(dep);
                }
            }
        }
        graph.insert(module.clone(), deps);
    }
    graph
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
fn aok_layers_as_documented() {
    let g = graph(&crate_src("aok-proto"));
    let uses = |m: &str, d: &str| g.get(m).is_some_and(|s| s.contains(d));
    // Wire values and frames below the decoders, decoders below the client.
    assert!(uses("message", "command") && !uses("command", "message"));
    assert!(!uses("command", "pc") && !uses("message", "pc"));
    assert!(uses("pc", "message") && uses("device", "command"));
    assert!(uses("client", "pc") && !uses("pc", "client"));
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
