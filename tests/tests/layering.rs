//! The house rules of ARCHITECTURE.md, checked on the sources:
//!
//! - in `sim-core`, every path a file names points to its own layer or one below
//!   (`mesh` < `collision` < `solver` < `design` < `scenario`; `error` is below all);
//! - in every crate, no two files import each other, directly or round a loop;
//! - `sim-core` knows nothing of iceoryx2, the processes' messages or command lines;
//! - no source file over 700 lines outside tests, no function over 120 lines.
//!
//! How imports are read: every `use` tree and every `crate::`/`super::` path in a file's
//! code (comments and its `#[cfg(test)] mod tests` left out), resolved to the file that
//! defines the module, and through a `mod.rs`'s `pub use` to the file that defines the
//! item. A `mod.rs`'s own `mod` and `pub use` lines are declarations, not imports.

#![allow(clippy::unwrap_used)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The workspace root (`SAIHO_LAYERING_ROOT` checks another checkout, such as an older
/// commit's, to see what the checker reports there).
fn root() -> PathBuf {
    std::env::var_os("SAIHO_LAYERING_ROOT")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(".."))
}

/// The crates whose sources are checked, and their `src` folders.
const CRATES: [&str; 6] = [
    "sim-core",
    "cloth-sim",
    "haptic-loop",
    "ui",
    "shared",
    "tools",
];

/// sim-core's layers, bottom first.
const LAYERS: [&str; 7] = [
    "error",
    "mesh",
    "collision",
    "solver",
    "fabric",
    "design",
    "scenario",
];

/// One source file as a module.
struct Module {
    path: PathBuf,
    /// Module path inside the crate (`["collision", "contact", "cache"]`; root: empty).
    name: Vec<String>,
    is_mod_rs: bool,
    /// The code without comments and without the inline test module.
    code: String,
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The code of a file without comments, string contents and its trailing
/// `#[cfg(test)] mod tests { .. }`.
fn code_of(text: &str) -> String {
    let mut kept = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        if t == "#[cfg(test)]"
            && lines
                .get(i + 1)
                .is_some_and(|n| n.trim_start().starts_with("mod tests"))
        {
            break;
        }
        let mut l = String::new();
        let mut in_str = false;
        let mut prev = ' ';
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            if !in_str && c == '/' && chars.peek() == Some(&'/') {
                break;
            }
            if c == '"' && prev != '\\' {
                in_str = !in_str;
            }
            if !in_str {
                l.push(c);
            }
            prev = c;
        }
        kept.push(l);
    }
    kept.join("\n")
}

fn modules(krate: &str) -> Vec<Module> {
    let src = root().join(krate).join("src");
    let mut files = Vec::new();
    if !src.is_dir() {
        return Vec::new();
    }
    rust_files(&src, &mut files);
    files
        .into_iter()
        .filter(|p| p.file_name().is_some_and(|n| n != "tests.rs"))
        .filter(|p| !p.starts_with(src.join("bin")))
        .map(|p| {
            let rel = p.strip_prefix(&src).unwrap().with_extension("");
            let mut name: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            let last = name.last().cloned().unwrap_or_default();
            let is_mod_rs = last == "mod";
            if is_mod_rs || last == "lib" || last == "main" {
                name.pop();
            }
            let code = code_of(&std::fs::read_to_string(&p).unwrap());
            Module {
                path: p,
                name,
                is_mod_rs,
                code,
            }
        })
        .collect()
}

/// The paths of a `use` tree, each as its segments (`use a::{b, c::d}` -> `a::b`,
/// `a::c::d`).
fn expand_use(tree: &str) -> Vec<Vec<String>> {
    // One space between words (`d as e`), none around punctuation.
    let mut tree = tree.split_whitespace().collect::<Vec<_>>().join(" ");
    for p in ["::", "{", "}", ","] {
        tree = tree
            .replace(&format!(" {p}"), p)
            .replace(&format!("{p} "), p);
    }
    let mut out = Vec::new();
    expand_into(&tree, &mut Vec::new(), &mut out);
    out
}

fn expand_into(tree: &str, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    // Split at top-level commas.
    let mut depth = 0;
    let mut start = 0;
    let bytes: Vec<char> = tree.chars().collect();
    let mut parts = Vec::new();
    for (i, c) in bytes.iter().enumerate() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(bytes[start..i].iter().collect::<String>());
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(bytes[start..].iter().collect::<String>());
    for part in parts.into_iter().filter(|p| !p.is_empty()) {
        match part.find('{') {
            Some(b) => {
                let head = part[..b].trim_end_matches("::");
                let inner = &part[b + 1..part.len() - 1];
                let n = prefix.len();
                prefix.extend(head.split("::").filter(|s| !s.is_empty()).map(String::from));
                expand_into(inner, prefix, out);
                prefix.truncate(n);
            }
            None => {
                let body = part.split(" as ").next().unwrap_or(&part).to_string();
                let mut p = prefix.clone();
                p.extend(body.split("::").filter(|s| !s.is_empty()).map(String::from));
                out.push(p);
            }
        }
    }
}

/// Every path a module's code names: its `use` trees and inline `crate::`/`super::` paths.
/// A `mod.rs`'s `pub use` lines (its re-exports) are left out.
fn named_paths(m: &Module) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let code = &m.code;
    let mut rest = code.as_str();
    // `use` statements (possibly spanning lines), up to their `;`.
    while let Some(i) = rest.find("use ") {
        let before = &rest[..i];
        let at_start = before
            .chars()
            .last()
            .is_none_or(|c| c.is_whitespace() || c == '{' || c == ';' || c == '}');
        let after = &rest[i + 4..];
        let Some(end) = after.find(';') else { break };
        let is_reexport =
            before.trim_end().ends_with("pub") || before.trim_end().ends_with("pub(crate)");
        if at_start && !(m.is_mod_rs && is_reexport) {
            out.extend(expand_use(&after[..end]));
        }
        rest = &after[end..];
    }
    // Inline paths.
    for key in ["crate::", "super::"] {
        let mut s = code.as_str();
        while let Some(i) = s.find(key) {
            let prev = s[..i].chars().last();
            let tail = &s[i..];
            let len = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(tail.len());
            if prev.is_none_or(|c| !(c.is_alphanumeric() || c == '_' || c == ':')) {
                out.push(
                    tail[..len]
                        .split("::")
                        .filter(|s| !s.is_empty())
                        .map(String::from)
                        .collect(),
                );
            }
            s = &tail[len.max(1)..];
        }
    }
    out
}

/// Resolves `path` named in `from` to the module that defines it (None: outside the
/// crate). Through a `mod.rs`'s `pub use`, an item resolves to its defining module.
fn resolve(
    path: &[String],
    from: &Module,
    known: &BTreeSet<Vec<String>>,
    reexports: &BTreeMap<(Vec<String>, String), Vec<String>>,
) -> Option<Vec<String>> {
    let mut abs: Vec<String> = match path.first().map(String::as_str) {
        Some("crate") => Vec::new(),
        Some("super") => {
            // `super` is the parent module (for a mod.rs, the folder's parent).
            let mut base = from.name.clone();
            let mut segs = path;
            while segs.first().is_some_and(|s| s == "super") {
                base.pop();
                segs = &segs[1..];
            }
            let mut b = base;
            b.extend(segs.iter().cloned());
            return longest(&b, known, reexports);
        }
        Some("self") => from.name.clone(),
        _ => return None,
    };
    abs.extend(path[1..].iter().cloned());
    longest(&abs, known, reexports)
}

fn longest(
    abs: &[String],
    known: &BTreeSet<Vec<String>>,
    reexports: &BTreeMap<(Vec<String>, String), Vec<String>>,
) -> Option<Vec<String>> {
    for n in (0..=abs.len()).rev() {
        let m = abs[..n].to_vec();
        if known.contains(&m) {
            // An item re-exported by this module: its defining module.
            if let Some(item) = abs.get(n)
                && let Some(def) = reexports.get(&(m.clone(), item.clone()))
            {
                return Some(def.clone());
            }
            return Some(m);
        }
    }
    None
}

/// `pub use child::{A, B}` in each mod.rs or lib.rs: (module, item) -> defining module.
fn reexport_table(
    mods: &[Module],
    known: &BTreeSet<Vec<String>>,
) -> BTreeMap<(Vec<String>, String), Vec<String>> {
    let mut table = BTreeMap::new();
    for m in mods.iter().filter(|m| m.is_mod_rs || m.name.is_empty()) {
        for line in m.code.split(';') {
            let t = line.trim();
            let Some(tree) = t
                .strip_prefix("pub use ")
                .or_else(|| t.strip_prefix("pub(crate) use "))
            else {
                continue;
            };
            for p in expand_use(tree) {
                let Some(item) = p.last().cloned() else {
                    continue;
                };
                let mut def = m.name.clone();
                def.extend(p[..p.len() - 1].iter().cloned());
                if known.contains(&def) {
                    table.insert((m.name.clone(), item), def);
                }
            }
        }
    }
    table
}

/// The import graph of a crate: module -> the modules it names (itself and its
/// ancestors' facades left out).
fn graph(mods: &[Module]) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let known: BTreeSet<Vec<String>> = mods.iter().map(|m| m.name.clone()).collect();
    let reexports = reexport_table(mods, &known);
    let mut g = BTreeMap::new();
    for m in mods {
        let deps: BTreeSet<Vec<String>> = named_paths(m)
            .iter()
            .filter_map(|p| resolve(p, m, &known, &reexports))
            .filter(|d| *d != m.name && !m.name.starts_with(d))
            .collect();
        g.insert(m.name.clone(), deps);
    }
    g
}

/// The cycles of a graph (one per strongly connected component larger than a node).
fn cycles(g: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<Vec<String>> {
    // Kosaraju on a small graph.
    let nodes: Vec<&Vec<String>> = g.keys().collect();
    let mut order = Vec::new();
    let mut seen = BTreeSet::new();
    fn visit<'a>(
        n: &'a Vec<String>,
        g: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        seen: &mut BTreeSet<&'a Vec<String>>,
        order: &mut Vec<&'a Vec<String>>,
    ) {
        if !seen.insert(n) {
            return;
        }
        for d in g.get(n).into_iter().flatten() {
            if let Some((k, _)) = g.get_key_value(d) {
                visit(k, g, seen, order);
            }
        }
        order.push(n);
    }
    for n in &nodes {
        visit(n, g, &mut seen, &mut order);
    }
    let mut rev: BTreeMap<&Vec<String>, Vec<&Vec<String>>> = BTreeMap::new();
    for (a, ds) in g {
        for d in ds {
            if let Some((k, _)) = g.get_key_value(d) {
                rev.entry(k).or_default().push(a);
            }
        }
    }
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for n in order.into_iter().rev() {
        if done.contains(n) {
            continue;
        }
        let mut comp = Vec::new();
        let mut stack = vec![n];
        while let Some(x) = stack.pop() {
            if !done.insert(x) {
                continue;
            }
            comp.push(x.join("::"));
            stack.extend(rev.get(x).into_iter().flatten());
        }
        if comp.len() > 1 {
            comp.sort();
            out.push(comp);
        }
    }
    out
}

#[test]
fn no_file_imports_round_a_loop_in_any_crate() {
    let mut found = Vec::new();
    for krate in CRATES {
        for c in cycles(&graph(&modules(krate))) {
            found.push(format!("{krate}: {}", c.join(" <-> ")));
        }
    }
    assert!(found.is_empty(), "import loops:\n{}", found.join("\n"));
}

#[test]
fn sim_core_layers_import_only_downwards() {
    let rank = |s: &str| LAYERS.iter().position(|l| *l == s);
    let mods = modules("sim-core");
    let g = graph(&mods);
    let mut bad = Vec::new();
    for (m, deps) in &g {
        let Some(own) = m.first().and_then(|r| rank(r)) else {
            continue;
        };
        for d in deps {
            if let Some(r) = d.first().and_then(|r| rank(r))
                && r > own
            {
                bad.push(format!("{} -> {}", m.join("::"), d.join("::")));
            }
        }
    }
    assert!(bad.is_empty(), "upward imports:\n{}", bad.join("\n"));
    // And the check sees real edges: the solver does name collision and mesh.
    let solver_deps: BTreeSet<String> = g
        .iter()
        .filter(|(m, _)| m.first().is_some_and(|r| r == "solver"))
        .flat_map(|(_, d)| d.iter().filter_map(|x| x.first().cloned()))
        .collect();
    assert!(solver_deps.contains("collision") && solver_deps.contains("mesh"));
}

#[test]
fn the_checker_finds_a_loop_and_an_upward_import() {
    // Two files that name each other, written as the checker reads them.
    let m = |name: &[&str], code: &str| Module {
        path: PathBuf::new(),
        name: name.iter().map(|s| s.to_string()).collect(),
        is_mod_rs: false,
        code: code_of(code),
    };
    let mods = vec![
        m(&["mesh", "a"], "use crate::mesh::b::{X, Y};\nfn f() {}"),
        m(
            &["mesh", "b"],
            "// use crate::nothing;\nfn g() { super::a::f(); }",
        ),
        m(&["mesh"], ""),
    ];
    let c = cycles(&graph(&mods));
    assert_eq!(c, vec![vec!["mesh::a".to_string(), "mesh::b".to_string()]]);
    assert_eq!(
        expand_use("super::{a::{B, C}, d as e}"),
        vec![
            vec!["super", "a", "B"],
            vec!["super", "a", "C"],
            vec!["super", "d"]
        ]
    );
}

#[test]
fn sim_core_knows_nothing_of_processes() {
    let toml = std::fs::read_to_string(root().join("sim-core/Cargo.toml")).unwrap();
    for dep in ["iceoryx2", "shared", "clap"] {
        assert!(
            !toml.lines().any(|l| l.trim_start().starts_with(dep)),
            "sim-core depends on {dep}"
        );
    }
    for m in modules("sim-core") {
        assert!(
            !m.code.contains("iceoryx2") && !m.code.contains("shared::"),
            "{} names iceoryx2 or the processes' messages",
            m.path.display()
        );
    }
}

/// Lines of each function (from its `fn` line to its closing brace) in `text`.
fn function_lengths(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim_start();
        let rest = [
            "pub fn ",
            "pub(crate) fn ",
            "pub(super) fn ",
            "fn ",
            "const fn ",
            "pub const fn ",
        ]
        .iter()
        .find_map(|p| t.strip_prefix(p));
        let Some(rest) = rest else { continue };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let mut depth = 0i32;
        let mut opened = false;
        for (j, l) in lines.iter().enumerate().skip(i) {
            let code = code_of(l);
            for c in code.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if !opened && code.trim_end().ends_with(';') {
                break;
            }
            if opened && depth <= 0 {
                out.push((name.clone(), i + 1, j - i + 1));
                break;
            }
        }
    }
    out
}

#[test]
fn no_long_files_or_functions() {
    let mut files = Vec::new();
    for dir in [
        "sim-core",
        "cloth-sim",
        "haptic-loop",
        "ui",
        "shared",
        "tools",
        "tests",
    ] {
        rust_files(&root().join(dir), &mut files);
    }
    let mut bad = Vec::new();
    for p in files
        .iter()
        .filter(|p| !p.components().any(|c| c.as_os_str() == "target"))
    {
        let text = std::fs::read_to_string(p).unwrap();
        // Judged by the path inside the workspace: the root itself is `tests/..`, and
        // every absolute path through it has a `tests` component (so, until
        // 2026-11-30, no file was ever held to the length).
        let rel = p.strip_prefix(root()).unwrap_or(p);
        let in_tests = rel
            .components()
            .any(|c| c.as_os_str() == "tests" || c.as_os_str() == "benches")
            || rel.file_name().is_some_and(|n| n == "tests.rs");
        let n = text.lines().count();
        if n > 700 && !in_tests {
            bad.push(format!("{}: {n} lines", p.display()));
        }
        for (name, line, len) in function_lengths(&text) {
            if len > 120 {
                bad.push(format!("{}:{line}: fn {name} is {len} lines", p.display()));
            }
        }
    }
    assert!(bad.is_empty(), "too long:\n{}", bad.join("\n"));
    // The counter counts: this file's own `function_lengths` is more than 20 lines.
    let me = std::fs::read_to_string(root().join(file!())).unwrap_or_default();
    let own = function_lengths(&me);
    assert!(
        own.iter()
            .any(|(n, _, len)| n == "function_lengths" && *len > 20),
        "{own:?}"
    );
}
