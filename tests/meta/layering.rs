//! The layering of `src/`, checked on its real import graph
//! (`imports::Tree`: every `use` and path resolved to the module that
//! defines what it names):
//!
//! 1. and 2. No circle among sibling modules, at every level of the module
//!    tree: the top-level modules (`od`, `sdo`, `device`, ...), the files
//!    and directories of each module directory, and the modules of each
//!    program. A module's own file (`mod.rs`) is the root of its directory,
//!    as `lib.rs` is the crate's: its children may use what it defines and
//!    it may use them; its children among themselves form no circle.
//! 3. Every import goes down the layer table [`LAYERS`] (or sideways where
//!    a layer allows it), and every top-level module has a place in it.
//! 4. The CiA 301 layers never name a profile (`cia418`, `cia419`,
//!    `deltaq`) nor the tools (`sim`, `log`, the programs), not even in
//!    tests or doc links; a `#[path]` never takes a file from another
//!    module's directory.
//!
//! Test code (`#[cfg(test)]`) may reach up to other CiA 301 layers for
//! its fixtures, so rules 1 to 3 read the code a build ships.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fs;
use std::path::Path;

use super::imports::{roots, Edge, Tree};

/// A layer of the crate: its top-level modules, and whether they may
/// import each other (the circle check keeps those imports one-way).
struct Layer {
    name: &'static str,
    modules: &'static [&'static str],
    sideways: bool,
}

/// The layers of `src/`, from the bottom (DESIGN.md, "Layers and modules").
const LAYERS: &[Layer] = &[
    Layer {
        name: "base: frames, identifiers, errors, time, the contract, abort codes",
        modules: &[
            "abort", "bytes", "clock", "cob_id", "error", "frame", "machine", "queue", "testing",
            "wire",
        ],
        sideways: true,
    },
    Layer {
        name: "the object dictionary and the program download objects",
        modules: &["od", "program"],
        sideways: false,
    },
    Layer {
        name: "the protocols and trace formats",
        modules: &["emcy", "lss", "nmt", "pdo", "sdo", "sync", "time", "trace"],
        sideways: true,
    },
    Layer {
        name: "every message, and the prelude",
        modules: &["message", "prelude"],
        sideways: true,
    },
    Layer {
        name: "the CiA 302-2 boot-up manager",
        modules: &["manager"],
        sideways: false,
    },
    Layer {
        name: "the CiA 301 device core",
        modules: &["device"],
        sideways: false,
    },
    Layer {
        name: "EDS and DCF: describing a device",
        modules: &["eds"],
        sideways: false,
    },
    Layer {
        name: "the CiA 418 battery module profile",
        modules: &["cia418"],
        sideways: false,
    },
    Layer {
        name: "the CiA 419 charger profile",
        modules: &["cia419"],
        sideways: false,
    },
    Layer {
        name: "the Delta-Q charger",
        modules: &["deltaq"],
        sideways: false,
    },
    Layer {
        name: "simulation",
        modules: &["sim"],
        sideways: false,
    },
    Layer {
        name: "log analysis",
        modules: &["log"],
        sideways: false,
    },
    Layer {
        name: "the programs",
        modules: &["bin"],
        sideways: false,
    },
];

/// The profiles and tools: the layers from this one up are not CiA 301.
const FIRST_ABOVE_CIA301: &str = "cia418";

/// The layer index of top-level module `top`.
fn layer_of(layers: &[Layer], top: &str) -> Option<usize> {
    layers.iter().position(|l| l.modules.contains(&top))
}

/// Every `.rs` file under `dir`, by path relative to `base` with `/`.
fn read_sources(dir: &Path, base: &Path, out: &mut BTreeMap<String, String>) {
    let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            read_sources(&path, base, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(base).expect("under src");
            let rel = rel.to_string_lossy().replace('\\', "/");
            let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
            out.insert(rel, text);
        }
    }
}

fn real_sources() -> BTreeMap<String, String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut sources = BTreeMap::new();
    read_sources(&src, &src, &mut sources);
    sources
}

/// `sdo::observer` for a module, `crate` for a root.
fn name(tree: &Tree, m: usize) -> String {
    let path = &tree.modules[m].path;
    if path.is_empty() {
        "crate".into()
    } else {
        path.join("::")
    }
}

fn ancestors(tree: &Tree, m: usize) -> Vec<usize> {
    let mut chain = vec![m];
    while let Some(p) = chain.last().and_then(|&a| tree.modules[a].parent) {
        chain.push(p);
    }
    chain
}

fn evidence(e: &Edge) -> String {
    format!("src/{}:{} `{}`", e.from_file, e.line, e.written)
}

/// The circles among sibling modules, at every level: each as
/// `in <parent>: a -> b -> a` with where each step is written.
fn sibling_cycles(tree: &Tree, edges: &[Edge]) -> Vec<String> {
    // parent -> child -> child it uses -> one place it is written.
    let mut levels: BTreeMap<usize, Graph> = BTreeMap::new();
    for e in edges.iter().filter(|e| !e.test && !e.facade) {
        let (from, to) = (ancestors(tree, e.from), ancestors(tree, e.to));
        let Some(at) = from.iter().position(|m| to.contains(m)) else {
            continue; // a program naming the library
        };
        let parent = from[at];
        let Some(to_at) = to.iter().position(|&m| m == parent) else {
            continue;
        };
        if at == 0 || to_at == 0 {
            continue; // a module and its own descendant
        }
        let (a, b) = (from[at - 1], to[to_at - 1]);
        let level = levels.entry(parent).or_default();
        level.entry(b).or_default();
        level
            .entry(a)
            .or_default()
            .entry(b)
            .or_insert_with(|| evidence(e));
    }
    let mut out = Vec::new();
    for (parent, graph) in &levels {
        for cycle in cycles(graph) {
            let steps: Vec<String> = cycle
                .windows(2)
                .map(|w| graph[&w[0]][&w[1]].clone())
                .collect();
            let path: Vec<String> = cycle
                .iter()
                .map(|&m| tree.modules[m].path.last().cloned().unwrap_or_default())
                .collect();
            out.push(format!(
                "in {}: {} ({})",
                name(tree, *parent),
                path.join(" -> "),
                steps.join("; ")
            ));
            let part = strongly_connected(graph, cycle[0]);
            if part.len() + 1 > cycle.len() {
                let names: Vec<String> = part.iter().map(|&m| name(tree, m)).collect();
                out.push(format!("  all in one circle: {}", names.join(", ")));
            }
        }
    }
    out
}

type Graph = BTreeMap<usize, BTreeMap<usize, String>>;

/// Every node `from` reaches in `graph`, itself included.
fn reach(graph: &Graph, from: usize) -> BTreeSet<usize> {
    let mut seen = BTreeSet::from([from]);
    let mut queue = VecDeque::from([from]);
    while let Some(n) = queue.pop_front() {
        for &next in graph.get(&n).into_iter().flat_map(|m| m.keys()) {
            if seen.insert(next) {
                queue.push_back(next);
            }
        }
    }
    seen
}

/// The strongly connected part of `graph` holding `node`: what it reaches
/// that reaches it back.
fn strongly_connected(graph: &Graph, node: usize) -> BTreeSet<usize> {
    reach(graph, node)
        .into_iter()
        .filter(|&n| reach(graph, n).contains(&node))
        .collect()
}

/// One shortest circle through each strongly connected part of `graph`
/// that has a circle, as the nodes along it (the first repeated last).
fn cycles(graph: &Graph) -> Vec<Vec<usize>> {
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for &start in graph.keys() {
        if done.contains(&start) {
            continue;
        }
        let part = strongly_connected(graph, start);
        done.extend(part.iter().copied());
        // The shortest way from `start` back to itself, by breadth first.
        let mut came_from: BTreeMap<usize, usize> = BTreeMap::new();
        let mut queue = VecDeque::from([start]);
        'search: while let Some(n) = queue.pop_front() {
            for &next in graph[&n].keys().filter(|k| part.contains(k)) {
                if next == start {
                    let mut cycle = vec![start, n];
                    while let Some(&p) = came_from.get(cycle.last().expect("a node")) {
                        cycle.push(p);
                    }
                    if n == start {
                        cycle.pop();
                    }
                    cycle.reverse();
                    out.push(cycle);
                    break 'search;
                }
                if next != start && !came_from.contains_key(&next) {
                    came_from.insert(next, n);
                    queue.push_back(next);
                }
            }
        }
    }
    out
}

/// Imports that climb the layer table, and top-level modules it does not
/// place.
fn upward_imports(layers: &[Layer], tree: &Tree, edges: &[Edge]) -> Vec<String> {
    let mut out = Vec::new();
    let tops: BTreeSet<String> = tree
        .modules
        .iter()
        .filter_map(|m| m.path.first().cloned())
        .collect();
    for top in tops.iter().filter(|t| layer_of(layers, t).is_none()) {
        out.push(format!("`{top}` has no layer in the table"));
    }
    // One line per file and module named: where it first does, and how often.
    let mut seen: BTreeMap<(String, String), (String, usize)> = BTreeMap::new();
    for e in edges.iter().filter(|e| !e.test) {
        let Some(from) = layer_of(layers, &e.from_top) else {
            continue;
        };
        for to_top in &e.to_tops {
            let Some(to) = layer_of(layers, to_top) else {
                continue;
            };
            if to > from || (to == from && !layers[from].sideways) {
                let line = format!(
                    "{}: `{}` ({}) names `{to_top}` ({})",
                    evidence(e),
                    e.from_top,
                    layers[from].name,
                    layers[to].name
                );
                let key = (e.from_file.clone(), to_top.clone());
                seen.entry(key).or_insert((line, 0)).1 += 1;
            }
        }
    }
    for (line, n) in seen.into_values() {
        match n {
            1 => out.push(line),
            n => out.push(format!("{line}, and {} more in the file", n - 1)),
        }
    }
    out
}

/// Imports, test code included, from below `first_above` to a module at
/// or above it.
fn below_naming_above(layers: &[Layer], first_above: &str, edges: &[Edge]) -> Vec<String> {
    let limit = layer_of(layers, first_above).expect("in the table");
    let mut out = Vec::new();
    for e in edges {
        if layer_of(layers, &e.from_top).is_none_or(|l| l >= limit) {
            continue;
        }
        for to_top in e
            .to_tops
            .iter()
            .filter(|t| layer_of(layers, t).is_some_and(|l| l >= limit))
        {
            out.push(format!(
                "{}: `{}` names `{to_top}`",
                evidence(e),
                e.from_top
            ));
        }
    }
    out
}

/// Doc links (`[x](crate::deltaq::y)`, ``[`crate::cia418::Z`]``) and other
/// comment paths to a module at or above `first_above`, in the files of
/// the modules below it; as `src/file:line`.
fn doc_links_above(
    layers: &[Layer],
    first_above: &str,
    sources: &BTreeMap<String, String>,
) -> Vec<String> {
    let limit = layer_of(layers, first_above).expect("in the table");
    let above: Vec<&str> = layers[limit..]
        .iter()
        .flat_map(|l| l.modules.iter().copied())
        .collect();
    let mut out = Vec::new();
    for (file, text) in sources {
        let top = file.split('/').next().unwrap_or("").trim_end_matches(".rs");
        if layer_of(layers, top).is_none_or(|l| l >= limit) {
            continue;
        }
        for (n, line) in text.lines().enumerate() {
            let Some((_, comment)) = line.split_once("//") else {
                continue;
            };
            let named = above.iter().any(|m| {
                comment.match_indices(m).any(|(at, _)| {
                    let end = at + m.len();
                    let ident =
                        |b: Option<u8>| b.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_');
                    let word = !ident(at.checked_sub(1).map(|i| comment.as_bytes()[i]))
                        && !ident(comment.as_bytes().get(end).copied());
                    word && (comment[..at].ends_with("::") || comment[end..].starts_with("::"))
                })
            });
            if named {
                out.push(format!("src/{file}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    out
}

/// Files the module tree does not reach, reaches twice, or takes from
/// another module's directory (a `#[path]` across modules).
fn tree_problems(tree: &Tree, sources: &BTreeMap<String, String>) -> Vec<String> {
    let mut out: Vec<String> = tree
        .missing
        .iter()
        .map(|f| format!("src/{f}: declared, not found"))
        .collect();
    for file in sources.keys() {
        match tree.reached.get(file) {
            None => out.push(format!("src/{file}: in no module tree")),
            Some(&n) if n > 1 => out.push(format!("src/{file}: the file of {n} modules")),
            _ => {}
        }
    }
    for module in &tree.modules {
        let Some(top) = module.path.first() else {
            continue;
        };
        let dir = module
            .file
            .split('/')
            .next()
            .unwrap_or("")
            .trim_end_matches(".rs");
        if dir != top {
            out.push(format!(
                "src/{}: the file of `{}`",
                module.file,
                module.path.join("::")
            ));
        }
    }
    out
}

fn assert_none(problems: &[String], rule: &str) {
    assert!(problems.is_empty(), "{rule}:\n{}", problems.join("\n"));
}

#[test]
fn sibling_modules_form_no_circle() {
    let sources = real_sources();
    let tree = Tree::parse(&sources, &roots(&sources));
    let edges = tree.edges();
    assert_none(
        &sibling_cycles(&tree, &edges),
        "import circles among sibling modules (break each by moving what both \
         need to the lower one or to a new leaf)",
    );
}

#[test]
fn every_import_goes_down_the_layers() {
    let sources = real_sources();
    let tree = Tree::parse(&sources, &roots(&sources));
    assert_none(
        &upward_imports(LAYERS, &tree, &tree.edges()),
        "imports that climb the layers (tests/meta/layering.rs, LAYERS)",
    );
    // The table names no module that is gone.
    for layer in LAYERS {
        for m in layer.modules {
            assert!(
                tree.modules
                    .iter()
                    .any(|x| x.path.first().is_some_and(|t| t == m)),
                "`{m}` in the layer table is not a module"
            );
        }
    }
}

#[test]
fn cia301_layers_never_name_a_profile() {
    let sources = real_sources();
    let tree = Tree::parse(&sources, &roots(&sources));
    let mut problems = below_naming_above(LAYERS, FIRST_ABOVE_CIA301, &tree.edges());
    problems.extend(doc_links_above(LAYERS, FIRST_ABOVE_CIA301, &sources));
    assert_none(
        &problems,
        "CiA 301 layers must not name a device profile or a tool (DESIGN.md, layering rule)",
    );
}

#[test]
fn the_graph_reads_the_whole_tree() {
    let sources = real_sources();
    let tree = Tree::parse(&sources, &roots(&sources));
    assert_none(&tree_problems(&tree, &sources), "the module tree");
    // A reader that resolved nothing would pass every rule: known imports
    // are seen, at every kind of path.
    let edges = tree.edges();
    let seen = |from: &str, to: &str| {
        edges
            .iter()
            .any(|e| e.from_file == from && e.to_file == to && !e.test)
    };
    for (from, to) in [
        ("od/mod.rs", "abort.rs"),
        ("sdo/server/mod.rs", "abort.rs"),
        ("cob_id.rs", "frame.rs"),
        ("bin/canopen-decode/args.rs", "cob_id.rs"),
    ] {
        assert!(seen(from, to), "src/{from} -> src/{to} not seen");
    }
    assert!(
        edges.len() > 1000,
        "only {} imports and paths resolved",
        edges.len()
    );
    assert!(sources.len() > 200 && tree.modules.len() > sources.len());
}

/// A small tree with a planted circle, an upward import, a profile named
/// from below in test code and in a doc link, and a `#[path]` across
/// modules: the checks report each of them, so they cannot pass silently.
#[test]
fn the_checks_catch_planted_faults() {
    const PLANTED: &[Layer] = &[
        Layer {
            name: "low",
            modules: &["low", "leaf"],
            sideways: true,
        },
        Layer {
            name: "mid",
            modules: &["mid"],
            sideways: false,
        },
        Layer {
            name: "profile",
            modules: &["prof"],
            sideways: false,
        },
    ];
    let files = [
        ("lib.rs", "pub mod leaf;\npub mod low;\npub mod mid;\npub mod prof;\n"),
        ("leaf.rs", "pub struct Leaf;\n"),
        (
            "low.rs",
            "//! See [`x`](crate::prof::P).\nuse crate::{\n    leaf::Leaf,\n    mid::b::Deep,\n};\n\
             #[cfg(test)]\nmod tests {\n    use crate::prof::P;\n}\n",
        ),
        (
            "mid/mod.rs",
            "mod a;\npub mod b;\npub use a::A;\n#[path = \"../prof/stolen.rs\"]\nmod stolen;\n",
        ),
        ("mid/a.rs", "pub struct A;\nfn f() -> super::b::Deep { todo() }\n"),
        ("mid/b.rs", "pub struct Deep;\nuse super::A;\n"),
        ("prof/mod.rs", "pub struct P;\nuse crate::mid::A;\n"),
        ("prof/stolen.rs", "pub struct S;\n"),
        ("prof/orphan.rs", "pub struct O;\n"),
    ];
    let sources: BTreeMap<String, String> = files
        .iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect();
    let tree = Tree::parse(&sources, &roots(&sources));
    let edges = tree.edges();

    let circles = sibling_cycles(&tree, &edges);
    assert_eq!(
        circles,
        ["in mid: a -> b -> a (src/mid/a.rs:2 `super::b::Deep`; src/mid/b.rs:2 `super::A`)"],
    );
    assert_eq!(
        upward_imports(PLANTED, &tree, &edges),
        ["src/low.rs:2 `crate::mid::b::Deep`: `low` (low) names `mid` (mid)"],
    );
    assert_eq!(
        below_naming_above(PLANTED, "prof", &edges),
        ["src/low.rs:8 `crate::prof::P`: `low` names `prof`"],
    );
    assert_eq!(
        doc_links_above(PLANTED, "prof", &sources),
        ["src/low.rs:1: //! See [`x`](crate::prof::P)."],
    );
    assert_eq!(
        tree_problems(&tree, &sources),
        [
            "src/prof/orphan.rs: in no module tree",
            "src/prof/stolen.rs: the file of `mid::stolen`"
        ],
    );
    // Without the planted faults the same checks find nothing.
    let mut fixed = sources.clone();
    fixed.insert(
        "mid/b.rs".into(),
        "pub struct Deep;\nuse crate::leaf::Leaf;\n".into(),
    );
    fixed.insert("low.rs".into(), "use crate::leaf::Leaf;\n".into());
    fixed.insert(
        "mid/mod.rs".into(),
        "mod a;\npub mod b;\npub use a::A;\n".into(),
    );
    fixed.remove("prof/stolen.rs");
    fixed.remove("prof/orphan.rs");
    let tree = Tree::parse(&fixed, &roots(&fixed));
    let edges = tree.edges();
    assert_eq!(sibling_cycles(&tree, &edges), Vec::<String>::new());
    assert_eq!(upward_imports(PLANTED, &tree, &edges), Vec::<String>::new());
    assert_eq!(
        below_naming_above(PLANTED, "prof", &edges),
        Vec::<String>::new()
    );
    assert_eq!(tree_problems(&tree, &fixed), Vec::<String>::new());
}
