//! The module import graph of a Rust source tree, read from the source the
//! way the compiler resolves it (not by searching text for names).
//!
//! Every `.rs` file is lexed (comments and string literals dropped) and its
//! module tree followed from the crate roots through `mod x;` (with
//! `#[path]`) and inline `mod x { .. }`. Each `use` tree (grouped over
//! several lines, `pub use`, `self`, globs, `as`) and each path in code
//! (`crate::x::y`, `super::y`, `self::y`, `$crate::y`, `child::y`,
//! `imported::y`) is resolved to the module that defines the item:
//! through child modules, items defined in a module, the names a module
//! imports (re-exports are followed to the definition) and glob imports.
//! Code under `#[cfg(test)]` is marked as test code.
//!
//! Not seen: macros invoked by their bare name (textual `macro_rules!`
//! scope) and names that reach a module only through a function body's
//! local `use` from another module.

use std::collections::{BTreeMap, BTreeSet};

/// A token: an identifier or keyword, a string literal, `::`, or one
/// other punctuation character.
#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Str(String),
    Sep,
    Punct(char),
}

/// `text` as tokens with their line numbers (from 1), without comments,
/// lifetimes and character literals.
fn lex(text: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = text.chars().collect();
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    let (mut i, mut line, mut out) = (0, 1, Vec::new());
    while i < c.len() {
        let ch = c[i];
        let start_line = line;
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if let Some(open) = raw_string_start(&c, i) {
            // r"..", r#".."#, br"..": ends at a quote and as many hashes.
            let hashes = open - i - usize::from(ch == 'b') - 1;
            let mut j = open + 1;
            let mut s = String::new();
            while j < c.len() && !(c[j] == '"' && (1..=hashes).all(|h| at(j + h) == '#')) {
                line += usize::from(c[j] == '\n');
                s.push(c[j]);
                j += 1;
            }
            out.push((Tok::Str(s), start_line));
            i = j + 1 + hashes;
        } else if ch == '"' || (ch == 'b' && at(i + 1) == '"') {
            let mut j = i + usize::from(ch == 'b') + 1;
            let mut s = String::new();
            while j < c.len() && c[j] != '"' {
                if c[j] == '\\' {
                    j += 1;
                }
                line += usize::from(at(j) == '\n');
                s.push(at(j));
                j += 1;
            }
            out.push((Tok::Str(s), start_line));
            i = j + 1;
        } else if ch == '\'' {
            // A character literal ('a', '\n', '\u{1F}') or a lifetime ('a).
            if at(i + 1) == '\\' {
                i += 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3;
            } else {
                i += 1;
                while is_ident_char(at(i)) {
                    i += 1;
                }
            }
        } else if is_ident_char(ch) || (ch == '$' && is_ident_char(at(i + 1))) {
            // `$crate` and macro variables are read without the `$`;
            // `r#type` as `type`.
            i += usize::from(ch == '$');
            if ch == 'r' && at(i + 1) == '#' {
                i += 2;
            }
            let from = i;
            while is_ident_char(at(i)) {
                i += 1;
            }
            out.push((Tok::Ident(c[from..i].iter().collect()), line));
        } else if ch == ':' && at(i + 1) == ':' {
            out.push((Tok::Sep, line));
            i += 2;
        } else {
            out.push((Tok::Punct(ch), line));
            i += 1;
        }
    }
    out
}

fn is_ident_char(ch: char) -> bool {
    ch.is_alphanumeric() || ch == '_'
}

/// The index of the opening quote if a raw string starts at `i`.
fn raw_string_start(c: &[char], i: usize) -> Option<usize> {
    let mut j = i + usize::from(c[i] == 'b');
    if c.get(j) != Some(&'r') || (j > i && c[i] != 'b') {
        return None;
    }
    j += 1;
    while c.get(j) == Some(&'#') {
        j += 1;
    }
    (c.get(j) == Some(&'"')).then_some(j)
}

/// One name a `use` brings into a module: its path as written and the
/// name it is bound to (`None` for a glob).
#[derive(Clone, Debug)]
pub struct Use {
    pub path: Vec<String>,
    pub name: Option<String>,
    pub public: bool,
    pub test: bool,
    pub line: usize,
}

/// A module: a file, or an inline `mod x { .. }` in one.
#[derive(Debug)]
pub struct Module {
    /// From the crate root: `["sdo", "client"]`; a program's modules start
    /// with `["bin", "<program>"]`.
    pub path: Vec<String>,
    /// The file it is written in, relative to the source directory.
    pub file: String,
    pub parent: Option<usize>,
    root: usize,
    children: BTreeMap<String, usize>,
    items: BTreeSet<String>,
    uses: Vec<Use>,
    /// Paths in code (not in a `use`), with their test flag and line.
    paths: Vec<(Vec<String>, bool, usize)>,
    /// Under `#[cfg(test)]`.
    pub test: bool,
}

/// What a path names: a module, or an item defined in a module.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Found {
    Module(usize),
    Item(usize),
}

impl Found {
    fn module(self) -> usize {
        match self {
            Found::Module(m) | Found::Item(m) => m,
        }
    }
}

/// One resolved import or path: from which file to which file, the
/// top-level modules it passes through, and where it is written.
#[derive(Clone, Debug)]
pub struct Edge {
    /// The importing module and the module defining what it names.
    pub from: usize,
    pub to: usize,
    pub from_file: String,
    pub to_file: String,
    pub from_top: String,
    /// Every top-level module the path names or passes through on its way
    /// to the definition (re-exports included), but the importer's own.
    pub to_tops: BTreeSet<String>,
    /// A `pub use` of the importer's own descendant: a module's facade,
    /// not a dependency of the module on the file.
    pub facade: bool,
    pub test: bool,
    pub line: usize,
    pub written: String,
}

/// The parsed tree: every module of every crate root.
#[derive(Debug, Default)]
pub struct Tree {
    pub modules: Vec<Module>,
    /// Files reached from a root, with how many modules declared them.
    pub reached: BTreeMap<String, usize>,
    /// Files a `mod x;` names that are not in the sources.
    pub missing: Vec<String>,
    lib_root: usize,
}

/// The library's root file and its programs' roots (`bin/<name>/main.rs`,
/// `bin/<name>.rs`), relative to the source directory.
pub fn roots(sources: &BTreeMap<String, String>) -> Vec<(String, Vec<String>)> {
    let mut out = vec![("lib.rs".to_string(), Vec::new())];
    for file in sources.keys() {
        let parts: Vec<&str> = file.split('/').collect();
        match parts.as_slice() {
            ["bin", name, "main.rs"] => {
                out.push((file.clone(), vec!["bin".into(), (*name).into()]))
            }
            ["bin", name] => {
                let name = name.trim_end_matches(".rs");
                out.push((file.clone(), vec!["bin".into(), name.into()]));
            }
            _ => {}
        }
    }
    out
}

impl Tree {
    /// Reads the crates whose root files are `roots` out of `sources`
    /// (file path relative to the source directory, `/`-separated, to
    /// text). The first root is the library (`canopen_codec::` in the
    /// others).
    pub fn parse(sources: &BTreeMap<String, String>, roots: &[(String, Vec<String>)]) -> Tree {
        let mut tree = Tree::default();
        for (n, (file, path)) in roots.iter().enumerate() {
            let id = tree.new_module(path.clone(), file.clone(), None, false);
            if n == 0 {
                tree.lib_root = id;
            }
            tree.parse_file(sources, file, id);
        }
        tree
    }

    fn new_module(
        &mut self,
        path: Vec<String>,
        file: String,
        parent: Option<usize>,
        test: bool,
    ) -> usize {
        let id = self.modules.len();
        let root = parent.map_or(id, |p| self.modules[p].root);
        self.modules.push(Module {
            path,
            file,
            parent,
            root,
            children: BTreeMap::new(),
            items: BTreeSet::new(),
            uses: Vec::new(),
            paths: Vec::new(),
            test,
        });
        if let Some(p) = parent {
            let name = self.modules[id].path.last().cloned().unwrap_or_default();
            self.modules[p].children.insert(name, id);
        }
        id
    }

    /// The directory a `mod x;` in module `m` looks in for `x.rs`.
    fn child_dir(&self, m: usize) -> String {
        let module = &self.modules[m];
        let (dir, stem) = match module.file.rsplit_once('/') {
            Some((d, f)) => (format!("{d}/"), f),
            None => (String::new(), module.file.as_str()),
        };
        let mut dir = if ["mod.rs", "lib.rs", "main.rs"].contains(&stem) {
            dir
        } else {
            format!("{dir}{}/", stem.trim_end_matches(".rs"))
        };
        // Inline modules between the file's module and `m`.
        let file_depth = self.file_module_depth(m);
        for name in &module.path[file_depth..] {
            dir.push_str(name);
            dir.push('/');
        }
        dir
    }

    /// The path length of the module the file of `m` starts.
    fn file_module_depth(&self, m: usize) -> usize {
        let mut at = m;
        while let Some(p) = self.modules[at].parent {
            if self.modules[p].file != self.modules[m].file {
                break;
            }
            at = p;
        }
        self.modules[at].path.len()
    }

    fn parse_file(&mut self, sources: &BTreeMap<String, String>, file: &str, module: usize) {
        *self.reached.entry(file.to_string()).or_default() += 1;
        let Some(text) = sources.get(file) else {
            self.missing.push(file.to_string());
            return;
        };
        let toks = lex(text);
        let ident = |i: usize| match toks.get(i) {
            Some((Tok::Ident(s), _)) => Some(s.as_str()),
            _ => None,
        };
        let punct =
            |i: usize, ch: char| matches!(toks.get(i), Some((Tok::Punct(p), _)) if *p == ch);
        let mut scopes = vec![(module, 0usize)];
        let mut depth = 0usize;
        // Attributes seen since the last item: (is cfg(test), path).
        let mut attrs: Vec<(bool, Option<String>)> = Vec::new();
        // The depth of a `#[cfg(test)]` item being read, and if its body
        // has opened.
        let mut test_item: Option<(usize, bool)> = None;
        let mut children = Vec::new();
        let mut i = 0;
        while i < toks.len() {
            let (m, body) = *scopes.last().expect("a scope");
            let line = toks[i].1;
            let test = self.modules[m].test || test_item.is_some();
            match &toks[i].0 {
                Tok::Punct('#')
                    if punct(i + 1, '[') || (punct(i + 1, '!') && punct(i + 2, '[')) =>
                {
                    let open = if punct(i + 1, '[') { i + 1 } else { i + 2 };
                    let close = matching(&toks, open);
                    let inner = &toks[open + 1..close];
                    let cfg_test = is_cfg_test(inner);
                    let path = match inner {
                        [(Tok::Ident(p), _), (Tok::Punct('='), _), (Tok::Str(s), _)]
                            if p == "path" =>
                        {
                            Some(s.clone())
                        }
                        _ => None,
                    };
                    attrs.push((cfg_test, path));
                    i = close + 1;
                    continue;
                }
                Tok::Punct('{') => {
                    depth += 1;
                    if let Some((d, _)) = test_item {
                        if depth == d + 1 {
                            test_item = Some((d, true));
                        }
                    }
                    attrs.clear();
                }
                Tok::Punct('}') => {
                    depth = depth.saturating_sub(1);
                    if scopes.len() > 1 && depth < body {
                        scopes.pop();
                    }
                    if test_item == Some((depth, true)) {
                        test_item = None;
                    }
                    attrs.clear();
                }
                Tok::Punct(';') => {
                    if test_item.is_some_and(|(d, _)| d == depth) {
                        test_item = None;
                    }
                    attrs.clear();
                }
                // `pub(crate)`, `pub(in crate::x)`: not paths.
                Tok::Ident(word) if word == "pub" && punct(i + 1, '(') => {
                    i = matching(&toks, i + 1);
                }
                Tok::Ident(word) if word == "use" => {
                    let public = i > 0 && (ident(i - 1) == Some("pub") || punct(i - 1, ')'));
                    let cfg_test = attrs.iter().any(|a| a.0);
                    let mut out = Vec::new();
                    let end = use_tree(&toks, i + 1, Vec::new(), &mut out);
                    for (path, name) in out {
                        self.modules[m].uses.push(Use {
                            path,
                            name,
                            public,
                            test: test || cfg_test,
                            line,
                        });
                    }
                    attrs.clear();
                    i = end;
                    continue;
                }
                Tok::Ident(word) if word == "mod" && depth == body => {
                    let cfg_test = attrs.iter().any(|a| a.0);
                    let path_attr = attrs.iter().find_map(|a| a.1.clone());
                    attrs.clear();
                    if let Some(name) = ident(i + 1) {
                        let mut path = self.modules[m].path.clone();
                        path.push(name.to_string());
                        let file = self.modules[m].file.clone();
                        if punct(i + 2, '{') {
                            let id = self.new_module(path, file, Some(m), test || cfg_test);
                            depth += 1;
                            scopes.push((id, depth));
                            i += 3;
                            continue;
                        }
                        children.push((m, path, path_attr, test || cfg_test));
                    }
                    i += 2;
                    continue;
                }
                Tok::Ident(word) if depth == body && is_item_keyword(word) => {
                    let name_at = if word == "macro_rules" { i + 2 } else { i + 1 };
                    if let Some(name) = ident(name_at).filter(|n| !is_item_keyword(n) && *n != "_")
                    {
                        self.modules[m].items.insert(name.to_string());
                    }
                    if attrs.iter().any(|a| a.0) && test_item.is_none() {
                        test_item = Some((depth, false));
                    }
                    attrs.clear();
                }
                Tok::Ident(word) if word == "impl" && depth == body => {
                    if attrs.iter().any(|a| a.0) && test_item.is_none() {
                        test_item = Some((depth, false));
                    }
                    attrs.clear();
                }
                Tok::Ident(_) if matches!(toks.get(i + 1), Some((Tok::Sep, _))) => {
                    let after_sep = i > 0 && matches!(toks[i - 1].0, Tok::Sep);
                    let after_dot = i > 0 && punct(i - 1, '.');
                    let mut path = Vec::new();
                    let mut j = i;
                    while let Some(seg) = ident(j) {
                        path.push(seg.to_string());
                        if !matches!(toks.get(j + 1), Some((Tok::Sep, _))) || ident(j + 2).is_none()
                        {
                            break;
                        }
                        j += 2;
                    }
                    if !after_sep && !after_dot && path.len() >= 2 {
                        self.modules[m].paths.push((path, test, line));
                    }
                    i = j + 1;
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
        for (parent, path, path_attr, test) in children {
            let dir = self.child_dir(parent);
            let name = path.last().cloned().unwrap_or_default();
            let file = match path_attr {
                Some(p) => {
                    let base = self.modules[parent]
                        .file
                        .rsplit_once('/')
                        .map_or("", |(d, _)| d);
                    normalize(&format!("{base}/{p}"))
                }
                None if sources.contains_key(&format!("{dir}{name}.rs")) => {
                    format!("{dir}{name}.rs")
                }
                None => format!("{dir}{name}/mod.rs"),
            };
            let id = self.new_module(path, file.clone(), Some(parent), test);
            self.parse_file(sources, &file, id);
        }
    }

    /// Resolves `path` as written in module `from`: what it names and the
    /// modules it passes through (`None` for std, core, other crates and
    /// primitives).
    fn resolve(&self, from: usize, path: &[String], fuel: u8) -> Option<(Found, Vec<usize>)> {
        let first = path.first()?;
        let (mut cur, rest) = match first.as_str() {
            "crate" => (self.modules[from].root, &path[1..]),
            "canopen_codec" if self.modules[from].root != self.lib_root => {
                (self.lib_root, &path[1..])
            }
            "self" | "super" => (from, path),
            _ => {
                let (found, mut via) = self.lookup(from, first, fuel)?;
                via.push(found.module());
                match found {
                    Found::Item(_) => return Some((found, via)),
                    Found::Module(m) => (m, &path[1..]),
                }
            }
        };
        let mut via = vec![cur];
        for seg in rest {
            match seg.as_str() {
                "self" => continue,
                "super" => cur = self.modules[cur].parent?,
                _ => match self.lookup(cur, seg, fuel) {
                    Some((Found::Module(m), more)) => {
                        via.extend(more);
                        cur = m;
                    }
                    Some((found, more)) => {
                        via.extend(more);
                        via.push(found.module());
                        return Some((found, via));
                    }
                    // A name the reader cannot place (a macro, an enum's
                    // variant through a glob): somewhere in `cur`.
                    None => return Some((Found::Item(cur), via)),
                },
            }
            via.push(cur);
        }
        Some((Found::Module(cur), via))
    }

    /// What `name` is in module `m`: a child module, an item defined
    /// there, or what a `use` there binds to it (globs last).
    fn lookup(&self, m: usize, name: &str, fuel: u8) -> Option<(Found, Vec<usize>)> {
        let module = &self.modules[m];
        if let Some(&c) = module.children.get(name) {
            return Some((Found::Module(c), Vec::new()));
        }
        if module.items.contains(name) {
            return Some((Found::Item(m), Vec::new()));
        }
        let fuel = fuel.checked_sub(1)?;
        for u in module
            .uses
            .iter()
            .filter(|u| u.name.as_deref() == Some(name))
        {
            if let Some(found) = self.resolve(m, &u.path, fuel) {
                return Some(found);
            }
        }
        for u in module.uses.iter().filter(|u| u.name.is_none()) {
            if let Some((Found::Module(g), mut via)) = self.resolve(m, &u.path, fuel) {
                if g != m {
                    if let Some((found, more)) = self.lookup(g, name, fuel) {
                        via.extend(more);
                        return Some((found, via));
                    }
                }
            }
        }
        None
    }

    /// The top-level module `m` belongs to (`bin` for the programs), or
    /// `None` for a crate root.
    fn top(&self, m: usize) -> Option<String> {
        self.modules[m].path.first().cloned()
    }

    fn is_descendant(&self, m: usize, of: usize) -> bool {
        let mut at = Some(m);
        while let Some(a) = at {
            if a == of {
                return true;
            }
            at = self.modules[a].parent;
        }
        false
    }

    /// Every import and path of every module but the crate roots,
    /// resolved.
    pub fn edges(&self) -> Vec<Edge> {
        let mut out = Vec::new();
        for (m, module) in self.modules.iter().enumerate() {
            let Some(from_top) = self.top(m) else {
                continue;
            };
            let uses = module
                .uses
                .iter()
                .map(|u| (&u.path, u.public, u.test, u.line));
            let paths = module.paths.iter().map(|(p, t, l)| (p, false, *t, *l));
            for (path, public, test, line) in uses.chain(paths) {
                let Some((found, via)) = self.resolve(m, path, 16) else {
                    continue;
                };
                let target = found.module();
                if self.modules[target].parent.is_none() {
                    continue;
                }
                let to_tops = via
                    .iter()
                    .chain([&target])
                    .filter_map(|&v| self.top(v))
                    .filter(|t| *t != from_top)
                    .collect();
                out.push(Edge {
                    from: m,
                    to: target,
                    from_file: module.file.clone(),
                    to_file: self.modules[target].file.clone(),
                    from_top: from_top.clone(),
                    to_tops,
                    facade: public && self.is_descendant(target, m),
                    test,
                    line,
                    written: path.join("::"),
                });
            }
        }
        out
    }
}

/// True if an attribute's tokens are a `cfg` that holds only in tests:
/// `cfg(test)`, `cfg(all(test, not(feature = "x")))`; not `cfg(not(test))`.
fn is_cfg_test(inner: &[(Tok, usize)]) -> bool {
    if !matches!(inner.first(), Some((Tok::Ident(w), _)) if w == "cfg") {
        return false;
    }
    // For each open parenthesis: whether it opens a `not(..)` or `any(..)`.
    let mut open: Vec<bool> = Vec::new();
    let mut before = "";
    for (t, _) in inner {
        match t {
            Tok::Punct('(') => open.push(before == "not" || before == "any"),
            Tok::Punct(')') => {
                open.pop();
            }
            Tok::Ident(w) if w == "test" && !open.iter().any(|&n| n) => return true,
            _ => {}
        }
        before = match t {
            Tok::Ident(w) => w,
            _ => "",
        };
    }
    false
}

/// True for the keywords that start a named item.
fn is_item_keyword(word: &str) -> bool {
    let items = [
        "fn", "struct", "enum", "trait", "type", "const", "static", "union",
    ];
    items.contains(&word) || word == "macro_rules"
}

/// The index of the bracket closing the one at `open`.
fn matching(toks: &[(Tok, usize)], open: usize) -> usize {
    let mut depth = 0usize;
    for (i, (t, _)) in toks.iter().enumerate().skip(open) {
        match t {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return i;
                }
            }
            _ => {}
        }
    }
    toks.len().saturating_sub(1)
}

/// Reads a use tree from `i` below `prefix` into `out` as (path, bound
/// name); returns the index after it (after the `;` at the top).
fn use_tree(
    toks: &[(Tok, usize)],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) -> usize {
    let top = prefix.is_empty();
    loop {
        match toks.get(i).map(|t| &t.0) {
            Some(Tok::Sep) => i += 1,
            Some(Tok::Punct('{')) => {
                i += 1;
                loop {
                    match toks.get(i).map(|t| &t.0) {
                        Some(Tok::Punct('}')) | None => break,
                        Some(Tok::Punct(',')) => i += 1,
                        _ => i = use_tree(toks, i, prefix.clone(), out),
                    }
                }
                i += 1;
                break;
            }
            Some(Tok::Punct('*')) => {
                out.push((prefix.clone(), None));
                i += 1;
                break;
            }
            Some(Tok::Ident(s)) => {
                let s = s.clone();
                i += 1;
                if matches!(toks.get(i).map(|t| &t.0), Some(Tok::Sep)) {
                    prefix.push(s);
                    continue;
                }
                let mut name = s.clone();
                if s == "self" {
                    name = prefix.last().cloned().unwrap_or_default();
                } else {
                    prefix.push(s);
                }
                if matches!(toks.get(i).map(|t| &t.0), Some(Tok::Ident(a)) if a == "as") {
                    name = match toks.get(i + 1).map(|t| &t.0) {
                        Some(Tok::Ident(alias)) => alias.clone(),
                        _ => name,
                    };
                    i += 2;
                }
                out.push((prefix.clone(), Some(name)));
                break;
            }
            _ => break,
        }
    }
    if top {
        while i < toks.len() && toks[i].0 != Tok::Punct(';') {
            i += 1;
        }
        i += 1;
    }
    i
}

/// `a/b/../c.rs` as `a/c.rs`.
fn normalize(path: &str) -> String {
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            p => parts.push(p),
        }
    }
    parts.join("/")
}
