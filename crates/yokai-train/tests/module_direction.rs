//! The crate's top-level modules depend one way (the order is in `lib.rs`): no module may
//! reach back, directly or around a loop, to one that depends on it. A check of the
//! `crate::…` paths in the sources, which is where every dependency inside the crate is
//! written; comments and unit-test modules are left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Top-level module → the top-level modules it names.
fn edges(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let modules: BTreeSet<String> = std::fs::read_dir(src)
        .unwrap()
        .flatten()
        .map(|e| {
            e.file_name()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let rel = path.strip_prefix(src).unwrap();
            let top = rel
                .components()
                .next()
                .unwrap()
                .as_os_str()
                .to_string_lossy();
            let top = top.trim_end_matches(".rs").to_string();
            if top == "lib" || rel.file_name().is_some_and(|n| n == "tests.rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let code = text.split("#[cfg(test)]\nmod tests").next().unwrap();
            for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for (k, _) in line.match_indices("crate::") {
                    let rest = &line[k + "crate::".len()..];
                    let names: Vec<&str> = match rest.strip_prefix('{') {
                        // `crate::{a, b::c}`: the group's first words.
                        Some(group) => group
                            .split('}')
                            .next()
                            .unwrap()
                            .split(',')
                            .map(|p| p.trim().split("::").next().unwrap())
                            .collect(),
                        None => vec![rest
                            .split(|c: char| !c.is_alphanumeric() && c != '_')
                            .next()
                            .unwrap()],
                    };
                    for name in names {
                        if name != top && modules.contains(name) {
                            out.entry(top.clone()).or_default().insert(name.to_string());
                        }
                    }
                }
            }
        }
    }
    out
}

/// A path from `from` back to itself through `edges`, if there is one.
fn loop_through(edges: &BTreeMap<String, BTreeSet<String>>, from: &str) -> Option<Vec<String>> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![vec![from.to_string()]];
    while let Some(path) = stack.pop() {
        let last = path.last().unwrap();
        for next in edges.get(last).into_iter().flatten() {
            if next == from {
                return Some([path.clone(), vec![next.clone()]].concat());
            }
            if seen.insert(next.clone()) {
                stack.push([path.clone(), vec![next.clone()]].concat());
            }
        }
    }
    None
}

#[test]
fn no_top_level_module_reaches_back_to_one_that_depends_on_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = edges(&src);
    // The check sees the dependencies it must: a test that found none would pass anything.
    assert!(edges["trainer"].contains("network") && edges["policy"].contains("artifact"));
    let loops: Vec<String> = edges
        .keys()
        .filter_map(|m| loop_through(&edges, m))
        .map(|l| l.join(" -> "))
        .collect();
    assert!(
        loops.is_empty(),
        "import cycles in yokai-train:\n  {}",
        loops.join("\n  ")
    );
}

#[test]
fn the_check_finds_a_cycle_when_there_is_one() {
    let mut edges = BTreeMap::new();
    edges.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    edges.insert("b".to_string(), BTreeSet::from(["c".to_string()]));
    assert_eq!(loop_through(&edges, "a"), None);
    edges.insert("c".to_string(), BTreeSet::from(["a".to_string()]));
    assert_eq!(loop_through(&edges, "a").unwrap().join(" "), "a b c a");
}
