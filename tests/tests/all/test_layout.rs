//! Each crate of the workspace has one integration-test binary, `tests/all/main.rs`, with one
//! module per test file: a file at the top of a crate's `tests/` would be a binary of its own,
//! linked on its own against the crate's dependencies, and a file in `tests/all/` that
//! `main.rs` does not name is never compiled. Checked for every member of the root
//! `Cargo.toml`'s `members = [...]` (`firmware-embassy` is its own workspace):
//!
//! 1. no `tests/*.rs` file at the top of the crate's `tests/` folder (a crate without one has
//!    no tests of this kind);
//! 2. where `tests/all/main.rs` exists, its `mod NAME;` lines name exactly the `tests/all/NAME.rs`
//!    files and the `tests/all/NAME/mod.rs` folders;
//! 3. no `[[test]]` section of the crate's `Cargo.toml` names another test target than
//!    `tests/all/main.rs`.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ is inside the workspace")
        .to_path_buf()
}

/// The members of the root `Cargo.toml`'s `[workspace]`, in their order.
fn members(root: &Path) -> Vec<String> {
    let text = fs::read_to_string(root.join("Cargo.toml")).expect("read the root Cargo.toml");
    let code: String = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let start = code
        .lines()
        .scan(0, |at, line| {
            let here = *at;
            *at += line.len() + 1;
            Some((here, line))
        })
        .find(|(_, line)| {
            line.trim_start()
                .strip_prefix("members")
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
        .map(|(at, _)| at)
        .expect("a `members = [...]` line in the root Cargo.toml");
    let list = &code[start..];
    let open = list.find('[').expect("members = [");
    let close = list.find(']').expect("members = [...]");
    list[open + 1..close]
        .split(',')
        .map(|m| m.trim().trim_matches('"').to_owned())
        .filter(|m| !m.is_empty())
        .collect()
}

/// The `mod NAME;` lines of `main` (with attributes before `mod`, on the line or on the lines
/// above, and `pub`/`pub(crate)`): the names of those that are files of `tests/all/`, and the
/// names and paths of those with a `#[path = "..."]` (a helper kept elsewhere, relative to
/// `tests/all/`). Inline `mod NAME { ... }` blocks are no files and not counted.
fn declared_modules(main: &str) -> (BTreeSet<String>, Vec<(String, String)>) {
    let mut files = BTreeSet::new();
    let mut pathed = Vec::new();
    let mut path: Option<String> = None;
    for line in main.lines() {
        let mut rest = line.trim();
        if rest.starts_with("//") || rest.is_empty() {
            continue;
        }
        // Attributes: `#[cfg(feature = "x")] mod name;`, `#[path = "../x.rs"]`.
        while let Some(after) = rest.strip_prefix("#[") {
            let mut depth = 1;
            let mut end = None;
            for (i, c) in after.char_indices() {
                match c {
                    '[' => depth += 1,
                    ']' => {
                        depth -= 1;
                        if depth == 0 {
                            end = Some(i);
                            break;
                        }
                    }
                    _ => {}
                }
            }
            let Some(end) = end else { break };
            if let Some(value) = after[..end]
                .strip_prefix("path")
                .and_then(|v| v.trim_start().strip_prefix('='))
            {
                path = Some(value.trim().trim_matches('"').to_owned());
            }
            rest = after[end + 1..].trim_start();
        }
        if rest.is_empty() {
            // Attributes alone on the line: they belong to the next item.
            continue;
        }
        for vis in ["pub(crate) ", "pub(super) ", "pub "] {
            if let Some(r) = rest.strip_prefix(vis) {
                rest = r.trim_start();
            }
        }
        let item_path = path.take();
        if let Some(name) = rest
            .strip_prefix("mod ")
            .and_then(|r| r.trim().strip_suffix(';'))
        {
            match item_path {
                Some(p) => pathed.push((name.trim().to_owned(), p)),
                None => {
                    files.insert(name.trim().to_owned());
                }
            }
        }
    }
    (files, pathed)
}

/// The modules `tests/all/` holds: `NAME.rs` files (but `main.rs`) and `NAME/mod.rs` folders.
fn module_files(all: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for entry in fs::read_dir(all).expect("read tests/all") {
        let path = entry.expect("a tests/all entry").path();
        let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        if path.is_dir() {
            if path.join("mod.rs").is_file() {
                out.insert(name.to_owned());
            }
        } else if let Some(stem) = name.strip_suffix(".rs")
            && stem != "main"
        {
            out.insert(stem.to_owned());
        }
    }
    out
}

/// The test targets of `[[test]]` sections that are not `tests/all/main.rs`, as the manifest
/// names them (their `path`, else their `name`).
fn other_test_targets(manifest: &str) -> Vec<String> {
    /// A `[[test]]` section's `name` and `path`.
    type Section = Option<(Option<String>, Option<String>)>;
    fn close(section: Section, out: &mut Vec<String>) {
        if let Some((name, path)) = section {
            let fine = match (&name, &path) {
                (_, Some(p)) => p == "tests/all/main.rs",
                (Some(n), None) => n == "all",
                (None, None) => false,
            };
            if !fine {
                out.push(
                    path.or(name)
                        .unwrap_or_else(|| "an unnamed [[test]]".into()),
                );
            }
        }
    }
    let mut out = Vec::new();
    let mut section: Section = None;
    for line in manifest.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.starts_with('[') {
            close(section.take(), &mut out);
            if line == "[[test]]" {
                section = Some((None, None));
            }
        } else if let Some((name, path)) = section.as_mut()
            && let Some((key, value)) = line.split_once('=')
        {
            let value = value.trim().trim_matches('"').to_owned();
            match key.trim() {
                "name" => *name = Some(value),
                "path" => *path = Some(value),
                _ => {}
            }
        }
    }
    close(section, &mut out);
    out
}

/// What is wrong with `crate_dir`'s tests, one sentence each.
fn offences(root: &Path, member: &str) -> Vec<String> {
    let crate_dir = root.join(member);
    let tests = crate_dir.join("tests");
    let mut out = Vec::new();
    if tests.is_dir() {
        let mut top: Vec<String> = fs::read_dir(&tests)
            .expect("read tests/")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "rs"))
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        top.sort();
        for file in top {
            out.push(format!(
                "{member}/tests/{file} is a test binary of its own: move it to \
                 {member}/tests/all/{file} and name it with `mod {};` in {member}/tests/all/main.rs",
                file.trim_end_matches(".rs")
            ));
        }
    }
    let all = tests.join("all");
    let main = all.join("main.rs");
    if main.is_file() {
        let (declared, pathed) =
            declared_modules(&fs::read_to_string(&main).expect("read main.rs"));
        for (name, path) in pathed {
            if !all.join(&path).is_file() {
                out.push(format!(
                    "{member}/tests/all/main.rs declares `mod {name};` at {path}, which is \
                     no file (relative to {member}/tests/all/)"
                ));
            }
        }
        let files = module_files(&all);
        for missing in files.difference(&declared) {
            out.push(format!(
                "{member}/tests/all/main.rs has no `mod {missing};` for \
                 {member}/tests/all/{missing}, which is therefore never compiled"
            ));
        }
        for extra in declared.difference(&files) {
            out.push(format!(
                "{member}/tests/all/main.rs declares `mod {extra};`, but there is no \
                 {member}/tests/all/{extra}.rs nor {member}/tests/all/{extra}/mod.rs"
            ));
        }
    }
    let manifest = fs::read_to_string(crate_dir.join("Cargo.toml")).unwrap_or_default();
    for target in other_test_targets(&manifest) {
        out.push(format!(
            "{member}/Cargo.toml has a [[test]] section for {target}, a test binary besides \
             tests/all/main.rs: give a feature-gated test `#[cfg(feature = ...)]` on its `mod` \
             line instead"
        ));
    }
    out
}

#[test]
fn every_crate_has_one_integration_test_binary() {
    let root = workspace_root();
    let members = members(&root);
    assert!(
        members.iter().any(|m| m == "tests") && members.len() > 5,
        "the root Cargo.toml's members were not read: {members:?}"
    );
    let all: Vec<String> = members.iter().flat_map(|m| offences(&root, m)).collect();
    assert!(
        all.is_empty(),
        "{} problems with the one-test-binary layout:\n{}",
        all.len(),
        all.join("\n")
    );
}

#[test]
fn the_module_lines_are_read_with_their_attributes() {
    let main = "//! doc\n#[macro_use]\nmod harness;\n#[cfg(feature = \"browser\")] mod web;\n\
                pub mod common;\n#[path = \"x/y.rs\"] pub(crate) mod odd;\nmod inline {\n}\n\
                // mod commented;\n#[path = \"../support/t.rs\"]\nmod kept;\n";
    let (files, pathed) = declared_modules(main);
    let got: Vec<String> = files.into_iter().collect();
    assert_eq!(got, ["common", "harness", "web"]);
    assert_eq!(
        pathed,
        [
            ("odd".to_owned(), "x/y.rs".to_owned()),
            ("kept".to_owned(), "../support/t.rs".to_owned())
        ]
    );
    let manifest = "[package]\nname = \"x\"\n\n[[test]]\nname = \"all\"\npath = \"tests/all/main.rs\"\n\
                    \n[[test]]\nname = \"io\"\nrequired-features = [\"a\"]\n\n[features]\na = []\n";
    assert_eq!(other_test_targets(manifest), ["io"]);
}
