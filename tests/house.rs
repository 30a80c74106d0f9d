//! The library's imports go one way (ARCHITECTURE.md): read from the
//! `crate::` paths of `src/`, no file imports one that imports it back, by
//! any way round, and neither does a top-level module; and nothing but the
//! crate root takes a name through the crate root (`crate::Error` is
//! `crate::error::Error`), so the root is the front door, never a floor.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a source file: `src/mesh/load/mod.rs` is
/// `["mesh", "load"]`, `src/lib.rs` is `[]`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// The paths a file's code names from the crate (`crate::a::b`, and
/// `super::c` as seen from `module`), whole from the crate root; comments
/// are left out (a doc link is no import), and so are a file's own tests.
fn crate_paths(text: &str, module: &[String]) -> Vec<Vec<String>> {
    let text = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    let code: Vec<&str> = text.lines().map(|l| l.split("//").next().unwrap_or("")).collect();
    let code = code.join("\n");
    let is_name = |c: char| c.is_alphanumeric() || c == '_';
    let mut paths = Vec::new();
    let mut rest = code.as_str();
    loop {
        let next = ["crate::", "super::"].into_iter().filter_map(|word| rest.find(word).map(|at| (at, word))).min();
        let Some((at, word)) = next else { break };
        let before = rest[..at].chars().next_back();
        rest = &rest[at + word.len()..];
        let end = rest.find(|c: char| !(is_name(c) || c == ':')).unwrap_or(rest.len());
        let written = &rest[..end];
        rest = &rest[end..];
        if before.is_some_and(is_name) {
            continue; // `holo_crate::`, not this crate
        }
        let mut path: Vec<String> =
            if word == "super::" { module[..module.len().saturating_sub(1)].to_vec() } else { Vec::new() };
        for part in written.split("::").filter(|s| !s.is_empty()) {
            if part == "super" {
                path.pop();
            } else {
                path.push(part.to_string());
            }
        }
        // `use crate::{a, b::c};`: each name of the group (a nested group by
        // the path before it).
        let Some(group) = rest.strip_prefix('{') else {
            paths.push(path);
            continue;
        };
        let mut depth = 0;
        let mut names = vec![String::new()];
        for c in group.chars() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => break,
                '}' => depth -= 1,
                ',' if depth == 0 => names.push(String::new()),
                _ if depth == 0 => names.last_mut().unwrap().push(c),
                _ => {}
            }
        }
        for name in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
            let mut p = path.clone();
            let name = name.split(" as ").next().unwrap_or(name);
            p.extend(name.split("::").filter(|s| !s.is_empty() && *s != "self" && *s != "*").map(String::from));
            paths.push(p);
        }
    }
    paths
}

#[test]
fn the_library_imports_go_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let modules: BTreeMap<Vec<String>, PathBuf> = files.iter().map(|f| (module_of(&src, f), f.clone())).collect();

    let mut file_edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    let mut through_root = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let me = module_of(&src, file);
        for path in crate_paths(&text, &me) {
            // The longest module prefix of the path is the file it imports.
            let target = (0..=path.len()).rev().find_map(|n| modules.get(&path[..n]).map(|f| (n, f)));
            let Some((n, target)) = target else { continue };
            if n == 0 && !me.is_empty() && !path.is_empty() {
                through_root.push(format!("{}: crate::{}", file.display(), path.join("::")));
            }
            if target != file && n > 0 {
                file_edges.entry(file.clone()).or_default().insert(target.clone());
            }
        }
    }
    assert!(through_root.is_empty(), "names taken through the crate root:\n{}", through_root.join("\n"));

    // No circle of files, and none of top-level modules.
    let top = |f: &PathBuf| module_of(&src, f).first().cloned().unwrap_or_default();
    let mut module_edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, tos) in &file_edges {
        for to in tos {
            if top(from) != top(to) {
                module_edges.entry(top(from)).or_default().insert(top(to));
            }
        }
    }
    if let Some(circle) = find_circle(&file_edges) {
        panic!(
            "files that import each other: {}",
            circle.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" → ")
        );
    }
    if let Some(circle) = find_circle(&module_edges) {
        panic!("modules that import each other: {}", circle.join(" → "));
    }
}

/// A circle of the graph, when it has one (depth-first, by colour).
fn find_circle<T: Ord + Clone>(edges: &BTreeMap<T, BTreeSet<T>>) -> Option<Vec<T>> {
    fn visit<T: Ord + Clone>(
        node: &T,
        edges: &BTreeMap<T, BTreeSet<T>>,
        done: &mut BTreeSet<T>,
        stack: &mut Vec<T>,
    ) -> Option<Vec<T>> {
        if let Some(at) = stack.iter().position(|n| n == node) {
            let mut circle = stack[at..].to_vec();
            circle.push(node.clone());
            return Some(circle);
        }
        if done.contains(node) {
            return None;
        }
        stack.push(node.clone());
        for next in edges.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, edges, done, stack) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(node.clone());
        None
    }
    let mut done = BTreeSet::new();
    edges.keys().find_map(|n| visit(n, edges, &mut done, &mut Vec::new()))
}

#[test]
fn a_circle_and_a_name_through_the_root_are_found() {
    let edges: BTreeMap<u8, BTreeSet<u8>> =
        [(1, [2].into()), (2, [3].into()), (3, [1].into()), (4, [1].into())].into_iter().collect();
    assert_eq!(find_circle(&edges), Some(vec![1, 2, 3, 1]));
    let line: BTreeMap<u8, BTreeSet<u8>> = [(1, [2].into()), (2, [3].into())].into_iter().collect();
    assert_eq!(find_circle(&line), None);
    let code = "use crate::{Error, geometry::Geometry};\n// crate::mesh is a comment\nlet x = crate::math::dot(a, b);";
    assert_eq!(crate_paths(code, &[]), [vec!["Error"], vec!["geometry", "Geometry"], vec!["math", "dot"]]);
    let module = ["output".to_string(), "claim".to_string()];
    let code = "use super::interrupt;\nuse super::super::Error;\n#[cfg(test)]\nmod tests {\n    use crate::mesh;\n}";
    assert_eq!(crate_paths(code, &module), [vec!["output", "interrupt"], vec!["Error"]]);
}
