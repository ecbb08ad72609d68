//! No import cycles between the source files of one crate.
//!
//! House rule: inside each workspace crate, no two files of `src/` import
//! each other, directly or through a longer loop. Files that lean on each
//! other cannot be read, tested or moved apart; the loop is usually a type
//! in the wrong file.
//!
//! File A imports file B when A names an item (or module) defined in B:
//! through `use crate::…`, `use super::…`, `use self::…`, or an inline path
//! in code (`crate::x::Y`, `super::Y`, `self::x::Y`, `$crate::…`). A path is
//! resolved to the file that defines the item: its module path is walked
//! through the files of `src/`, then the item is looked up in the last
//! module's file, following that file's `use`s (re-exports such as
//! `pub use a::A;` in lib.rs) to where the item really lives. So a lib.rs
//! re-export is a way through, not an import of its own: `pub use a::A;`
//! (a relative path) adds no edge. `mod x;` is no import, and neither is
//! `use super::*;` (a test module's) nor anything behind `#[cfg(test)]`.
//!
//! The reading is a small lexer, not a Rust parser: items a macro generates
//! are not seen (a name not found falls back to the module file that was
//! named), `#[path]`, `include!` and `#[macro_export]` macros are not
//! followed, and `src/main.rs` beside a `src/lib.rs` is read as if it were
//! part of the library.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// How many re-exports a name is followed through.
const MAX_HOPS: usize = 8;

// ---------------------------------------------------------------------------
// Lexing: identifiers, `::` and single punctuation; comments, strings, char
// literals and numbers are dropped, so what is left can be brace-counted.

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
    /// A number (kept so two names around it do not look adjacent).
    Lit,
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn lex(src: &str) -> Vec<Tok> {
    let c: Vec<char> = src.chars().collect();
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            // Line and doc comments.
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            // Block comments nest in Rust.
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
                    i += 1;
                }
            }
        } else if ch == '"' {
            i = skip_string(&c, i);
        } else if ch == '\'' {
            if at(i + 1) == '\\' {
                // An escaped char literal: '\n', '\'', '\u{..}'.
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3; // 'x'
            } else {
                out.push(Tok::Punct('\'')); // a lifetime or label
                i += 1;
            }
        } else if ch.is_ascii_digit() {
            while i < c.len() && is_ident_char(c[i]) {
                i += 1;
            }
            out.push(Tok::Lit);
        } else if is_ident_start(ch) {
            let start = i;
            while i < c.len() && is_ident_char(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            let raw_string = at(i) == '"' || (at(i) == '#' && matches!(at(i + 1), '"' | '#'));
            match word.as_str() {
                "r" | "br" | "cr" if raw_string => i = skip_raw_string(&c, i),
                "b" | "c" if at(i) == '"' => i = skip_string(&c, i),
                "b" if at(i) == '\'' => {
                    // b'x' or b'\n'
                    i += 1;
                    if at(i) == '\\' {
                        i += 1;
                    }
                    i += 2;
                }
                "r" if at(i) == '#' && is_ident_start(at(i + 1)) => {
                    // A raw identifier, r#type.
                    let start = i + 1;
                    i += 1;
                    while i < c.len() && is_ident_char(c[i]) {
                        i += 1;
                    }
                    out.push(Tok::Ident(c[start..i].iter().collect()));
                }
                _ => out.push(Tok::Ident(word)),
            }
        } else if ch == ':' && at(i + 1) == ':' {
            out.push(Tok::Sep);
            i += 2;
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

/// Past the string starting with the `"` at `i`.
fn skip_string(c: &[char], mut i: usize) -> usize {
    i += 1;
    while i < c.len() {
        match c[i] {
            '\\' => i += 2,
            '"' => return i + 1,
            _ => i += 1,
        }
    }
    i
}

/// Past the raw string whose `#`s or `"` start at `i`.
fn skip_raw_string(c: &[char], mut i: usize) -> usize {
    let mut hashes = 0;
    while c.get(i) == Some(&'#') {
        hashes += 1;
        i += 1;
    }
    i += 1; // the opening quote
    while i < c.len() {
        if c[i] == '"' && (1..=hashes).all(|h| c.get(i + h) == Some(&'#')) {
            return i + 1 + hashes;
        }
        i += 1;
    }
    i
}

// ---------------------------------------------------------------------------
// Scanning one file: what it defines, what it names, what its `use`s bring in.

/// A path the file names, as written.
#[derive(Debug)]
struct Ref {
    /// The inline modules (`mod x { … }`) it sits in, inside the file.
    scope: Vec<String>,
    path: Vec<String>,
    /// `use path::*`
    glob: bool,
}

/// One name a file-level `use` brings into the file's module.
#[derive(Debug)]
struct Import {
    /// The name it is known by here (the alias, if any).
    name: String,
    path: Vec<String>,
    glob: bool,
}

#[derive(Debug, Default)]
struct FileScan {
    /// Names of the items at the file's top level.
    defines: BTreeSet<String>,
    refs: Vec<Ref>,
    imports: Vec<Import>,
}

struct Scanner {
    t: Vec<Tok>,
}

impl Scanner {
    fn ident(&self, k: usize) -> Option<&str> {
        match self.t.get(k) {
            Some(Tok::Ident(s)) => Some(s),
            _ => None,
        }
    }

    fn punct(&self, k: usize, ch: char) -> bool {
        self.t.get(k) == Some(&Tok::Punct(ch))
    }

    fn sep(&self, k: usize) -> bool {
        self.t.get(k) == Some(&Tok::Sep)
    }

    /// The attribute `#[…]` or `#![…]` at `k`: its end and whether it is
    /// `cfg(test)`.
    fn attribute(&self, k: usize) -> Option<(usize, bool)> {
        let open = if self.punct(k + 1, '!') { k + 2 } else { k + 1 };
        if !self.punct(k, '#') || !self.punct(open, '[') {
            return None;
        }
        let mut depth = 0;
        let mut j = open;
        while j < self.t.len() {
            if self.punct(j, '[') {
                depth += 1;
            } else if self.punct(j, ']') {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            j += 1;
        }
        let inner = &self.t[(open + 1).min(j)..j];
        let cfg_test =
            inner == [Tok::Ident("cfg".into()), Tok::Punct('('), Tok::Ident("test".into()), Tok::Punct(')')];
        Some((j + 1, cfg_test))
    }

    /// Past the item starting at `k` (its attributes, then up to its `;` or
    /// the end of its first `{ … }` block).
    fn skip_item(&self, mut k: usize) -> usize {
        while let Some((end, _)) = self.attribute(k) {
            k = end;
        }
        let mut depth = 0i32;
        while k < self.t.len() {
            match self.t[k] {
                Tok::Punct('(' | '[' | '{') => depth += 1,
                Tok::Punct(')' | ']') => depth -= 1,
                Tok::Punct('}') => {
                    depth -= 1;
                    if depth == 0 {
                        return k + 1;
                    }
                }
                Tok::Punct(';') if depth == 0 => return k + 1,
                _ => {}
            }
            k += 1;
        }
        k
    }

    /// The use tree at `k` (after `use` or inside braces), with `prefix`
    /// already read; its leaves are pushed to `out` as (path, name, glob).
    fn use_tree(&self, k: &mut usize, mut path: Vec<String>, out: &mut Vec<(Vec<String>, String, bool)>) {
        if self.sep(*k) {
            // `::std::…`, an external crate in 2015 style.
            path.push("::".into());
            *k += 1;
        }
        loop {
            if let Some(seg) = self.ident(*k) {
                path.push(seg.to_owned());
                *k += 1;
                if self.sep(*k) {
                    *k += 1;
                    continue;
                }
                // A leaf: `a::b`, `a::b as c`, `a::{self}`.
                let mut name = path.last().cloned().unwrap_or_default();
                if path.last().is_some_and(|s| s == "self") && path.len() > 1 {
                    path.pop();
                    name = path.last().cloned().unwrap_or_default();
                }
                if self.ident(*k) == Some("as") {
                    name = self.ident(*k + 1).unwrap_or("_").to_owned();
                    *k += 2;
                }
                out.push((path, name, false));
                return;
            } else if self.punct(*k, '*') {
                *k += 1;
                out.push((path, "*".into(), true));
                return;
            } else if self.punct(*k, '{') {
                *k += 1;
                while *k < self.t.len() && !self.punct(*k, '}') {
                    let before = *k;
                    self.use_tree(k, path.clone(), out);
                    if self.punct(*k, ',') {
                        *k += 1;
                    } else if *k == before {
                        *k += 1; // not a use tree: do not loop forever
                    }
                }
                *k += 1;
                return;
            } else {
                return;
            }
        }
    }

    fn scan(self) -> FileScan {
        let mut s = FileScan::default();
        let mut depth = 0i32;
        // The inline modules open here: name and the brace depth of their body.
        let mut inline: Vec<(String, i32)> = Vec::new();
        // Inside a top-level `some_macro! { … }`, whose items count as the file's.
        let mut in_macro = false;
        let mut i = 0;
        while i < self.t.len() {
            let scope = || inline.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
            if let Some((end, cfg_test)) = self.attribute(i) {
                let inner = self.punct(i + 1, '!');
                i = match (cfg_test, inner) {
                    (true, true) if depth == 0 => return FileScan::default(), // a test-only file
                    (true, false) => self.skip_item(end),
                    _ => end,
                };
                continue;
            }
            match &self.t[i] {
                Tok::Punct('{') => {
                    let call = i >= 2 && self.punct(i - 1, '!') && self.ident(i - 2).is_some();
                    in_macro |= depth == 0 && call && self.ident(i - 2) != Some("macro_rules");
                    depth += 1;
                }
                Tok::Punct('}') => {
                    depth -= 1;
                    in_macro &= depth > 0;
                    while inline.last().is_some_and(|(_, d)| *d > depth) {
                        inline.pop();
                    }
                }
                Tok::Ident(word) if word == "use" => {
                    let mut k = i + 1;
                    let mut leaves = Vec::new();
                    self.use_tree(&mut k, Vec::new(), &mut leaves);
                    for (path, name, glob) in leaves {
                        if glob && path == ["super"] {
                            continue; // `use super::*;`, a test module's
                        }
                        if depth == 0 {
                            s.imports.push(Import { name, path: path.clone(), glob });
                        }
                        s.refs.push(Ref { scope: scope(), path, glob });
                    }
                    while k < self.t.len() && !self.punct(k, ';') {
                        k += 1;
                    }
                    i = k + 1;
                    continue;
                }
                Tok::Ident(word) if word == "mod" => {
                    if let Some(name) = self.ident(i + 1) {
                        if depth == 0 {
                            s.defines.insert(name.to_owned());
                        }
                        if self.punct(i + 2, '{') {
                            inline.push((name.to_owned(), depth + 1));
                        }
                    }
                }
                Tok::Ident(word) if (depth == 0 || in_macro && depth == 1) && is_item_keyword(word) => {
                    // `const fn f`, `static mut X`, `unsafe fn f`: skip to the name;
                    // a const generic (`<const N: usize>`) is no item.
                    let generic = i > 0 && (self.punct(i - 1, '<') || self.punct(i - 1, ','));
                    let mut k = i + 1;
                    while matches!(self.ident(k), Some("fn" | "mut" | "unsafe" | "async" | "extern")) {
                        k += 1;
                    }
                    if let Some(name) = self.ident(k).filter(|n| *n != "_" && !generic) {
                        s.defines.insert(name.to_owned());
                    }
                }
                Tok::Ident(word) if word == "macro_rules" && depth == 0 && self.punct(i + 1, '!') => {
                    if let Some(name) = self.ident(i + 2) {
                        s.defines.insert(name.to_owned());
                    }
                }
                Tok::Ident(first) if self.sep(i + 1) && !(i > 0 && self.sep(i - 1)) => {
                    // A path in code: `crate::a::B`, `super::f`, `child::g`.
                    let mut path = vec![first.clone()];
                    let mut k = i + 1;
                    while self.sep(k) {
                        match self.ident(k + 1) {
                            Some(seg) => path.push(seg.to_owned()),
                            None => break,
                        }
                        k += 2;
                    }
                    s.refs.push(Ref { scope: scope(), path, glob: false });
                    i = k;
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
        s
    }
}

fn is_item_keyword(word: &str) -> bool {
    matches!(word, "struct" | "enum" | "union" | "trait" | "type" | "const" | "static" | "fn")
}

// ---------------------------------------------------------------------------
// One crate: its files, their module paths, and the import graph.

struct SrcFile {
    /// Relative to `src/`, e.g. `sim/truth.rs`.
    rel: String,
    module: Vec<String>,
    scan: FileScan,
}

/// Where a path leads.
enum Target {
    /// The file that defines the item.
    Defined(usize),
    /// The item was not found; the file of the module that was named.
    Fallback(usize),
    /// Outside the crate (a re-export of another crate's item).
    External,
}

struct CrateGraph {
    name: String,
    files: Vec<SrcFile>,
    /// Module path to file.
    modules: HashMap<Vec<String>, usize>,
    /// (importer, imported) to the names that tie them.
    edges: BTreeMap<(usize, usize), BTreeSet<String>>,
    /// Paths whose item was not found (`file: path`).
    unresolved: Vec<String>,
}

/// Every `.rs` file under `dir`, but not under `src/bin/`.
fn rust_files(src: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            if path != src.join("bin") {
                rust_files(src, &path, out);
            }
        } else if path.extension().is_some_and(|x| x == "rs") {
            out.push(path);
        }
    }
}

/// `lib.rs`/`main.rs` is the root, `a.rs` and `a/mod.rs` are `a`, `a/b.rs` is `a::b`.
fn module_path(rel: &str) -> Vec<String> {
    if rel == "lib.rs" || rel == "main.rs" {
        return Vec::new();
    }
    let mut path: Vec<String> = rel.trim_end_matches(".rs").split('/').map(str::to_owned).collect();
    if path.last().is_some_and(|s| s == "mod") {
        path.pop();
    }
    path
}

impl CrateGraph {
    fn read(name: &str, src: &Path) -> Self {
        let mut paths = Vec::new();
        rust_files(src, src, &mut paths);
        let mut files = Vec::new();
        for path in paths {
            let rel = path.strip_prefix(src).expect("under src").to_string_lossy().replace('\\', "/");
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let scan = Scanner { t: lex(&text) }.scan();
            files.push(SrcFile { module: module_path(&rel), rel, scan });
        }
        let mut modules = HashMap::new();
        for (idx, f) in files.iter().enumerate() {
            // With both, lib.rs is the root the modules hang from.
            if f.rel != "main.rs" || !files.iter().any(|g| g.rel == "lib.rs") {
                modules.insert(f.module.clone(), idx);
            }
        }
        let mut graph = CrateGraph {
            name: name.to_owned(),
            files,
            modules,
            edges: BTreeMap::new(),
            unresolved: Vec::new(),
        };
        graph.link();
        graph
    }

    /// The path as seen from module `here`, made absolute (from the crate
    /// root); `None` when it leaves the crate.
    fn absolute(&self, here: &[String], path: &[String]) -> Option<Vec<String>> {
        let first = path.first()?;
        let (mut base, rest) = match first.as_str() {
            "crate" => (Vec::new(), &path[1..]),
            "self" => (here.to_vec(), &path[1..]),
            "super" => {
                let mut base = here.to_vec();
                let supers = path.iter().take_while(|s| *s == "super").count();
                for _ in 0..supers {
                    base.pop()?;
                }
                (base, &path[supers..])
            }
            _ => {
                // A 2018 uniform path is a child module of `here`, if a file says so.
                let mut child = here.to_vec();
                child.push(first.clone());
                if !self.modules.contains_key(&child) {
                    return None;
                }
                (here.to_vec(), path)
            }
        };
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The deepest module file `path` walks through, and how many segments that took.
    fn walk(&self, path: &[String]) -> (usize, usize) {
        let mut n = 0;
        while n < path.len() && self.modules.contains_key(&path[..=n]) {
            n += 1;
        }
        (self.modules[&path[..n]], n)
    }

    /// The file that defines what the absolute `path` names.
    fn resolve(&self, path: &[String], hops: usize) -> Target {
        let (file, n) = self.walk(path);
        let Some(name) = path.get(n) else {
            return Target::Defined(file); // a module
        };
        let f = &self.files[file];
        if f.scan.defines.contains(name) {
            return Target::Defined(file);
        }
        if hops < MAX_HOPS {
            let rest = &path[n + 1..];
            // A name the module's own `use` brings in: follow it.
            if let Some(import) = f.scan.imports.iter().find(|i| !i.glob && i.name == *name) {
                let Some(mut to) = self.absolute(&f.module, &import.path) else {
                    return Target::External;
                };
                to.extend(rest.iter().cloned());
                return self.resolve(&to, hops + 1);
            }
            // A glob re-export, if the name is defined behind it.
            for import in f.scan.imports.iter().filter(|i| i.glob) {
                if let Some(mut to) = self.absolute(&f.module, &import.path) {
                    to.push(name.clone());
                    to.extend(rest.iter().cloned());
                    if let Target::Defined(d) = self.resolve(&to, hops + 1) {
                        return Target::Defined(d);
                    }
                }
            }
            // Not here, but the module glob-imports another crate: most likely from there.
            if f.scan.imports.iter().any(|i| i.glob && self.absolute(&f.module, &i.path).is_none()) {
                return Target::External;
            }
        }
        Target::Fallback(file)
    }

    /// The import edges of every file.
    fn link(&mut self) {
        let mut edges: BTreeMap<(usize, usize), BTreeSet<String>> = BTreeMap::new();
        let mut unresolved = Vec::new();
        for (from, f) in self.files.iter().enumerate() {
            for r in &f.scan.refs {
                let here: Vec<String> = f.module.iter().chain(&r.scope).cloned().collect();
                if !matches!(r.path[0].as_str(), "crate" | "self" | "super") {
                    continue; // an external crate, or a relative path (a lib.rs re-export)
                }
                let Some(path) = self.absolute(&here, &r.path) else { continue };
                let (_, n) = self.walk(&path);
                // The name that ties the files: the item, else the module.
                let name = match (r.glob, path.get(n)) {
                    (true, _) => format!("{}::*", path.last().map_or("crate", String::as_str)),
                    (false, Some(item)) => item.clone(),
                    (false, None) => path.last().cloned().unwrap_or_else(|| "crate".into()),
                };
                let to = match self.resolve(&path, 0) {
                    Target::Defined(to) => to,
                    Target::Fallback(to) => {
                        unresolved.push(format!("{}: {}", f.rel, r.path.join("::")));
                        to
                    }
                    Target::External => continue,
                };
                if to != from {
                    edges.entry((from, to)).or_default().insert(name);
                }
            }
        }
        self.edges = edges;
        self.unresolved = unresolved;
    }

    /// The strongly connected components of two or more files (Tarjan).
    fn cycles(&self) -> Vec<Vec<usize>> {
        struct Tarjan<'a> {
            next: &'a [Vec<usize>],
            index: Vec<Option<usize>>,
            low: Vec<usize>,
            on_stack: Vec<bool>,
            stack: Vec<usize>,
            counter: usize,
            out: Vec<Vec<usize>>,
        }
        impl Tarjan<'_> {
            fn visit(&mut self, v: usize) {
                self.index[v] = Some(self.counter);
                self.low[v] = self.counter;
                self.counter += 1;
                self.stack.push(v);
                self.on_stack[v] = true;
                for &w in &self.next[v] {
                    match self.index[w] {
                        None => {
                            self.visit(w);
                            self.low[v] = self.low[v].min(self.low[w]);
                        }
                        Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                        Some(_) => {}
                    }
                }
                if Some(self.low[v]) == self.index[v] {
                    let mut component = Vec::new();
                    while let Some(w) = self.stack.pop() {
                        self.on_stack[w] = false;
                        component.push(w);
                        if w == v {
                            break;
                        }
                    }
                    if component.len() > 1 {
                        component.sort();
                        self.out.push(component);
                    }
                }
            }
        }
        let n = self.files.len();
        let mut next = vec![Vec::new(); n];
        for &(a, b) in self.edges.keys() {
            next[a].push(b);
        }
        let mut t = Tarjan {
            next: &next,
            index: vec![None; n],
            low: vec![0; n],
            on_stack: vec![false; n],
            stack: Vec::new(),
            counter: 0,
            out: Vec::new(),
        };
        for v in 0..n {
            if t.index[v].is_none() {
                t.visit(v);
            }
        }
        t.out.sort();
        t.out
    }

    /// `crate: a.rs -> b.rs (A, B); b.rs -> a.rs (C)`: the edges inside a component.
    fn describe(&self, component: &[usize]) -> String {
        let inside: BTreeSet<usize> = component.iter().copied().collect();
        let edges: Vec<String> = self
            .edges
            .iter()
            .filter(|((a, b), _)| inside.contains(a) && inside.contains(b))
            .map(|((a, b), names)| {
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                format!("{} -> {} ({})", self.files[*a].rel, self.files[*b].rel, names.join(", "))
            })
            .collect();
        format!("{}: {}", self.name, edges.join("; "))
    }
}

// ---------------------------------------------------------------------------
// The workspace.

fn toml_at(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse().unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Each workspace member's package name and `src/` directory.
fn members() -> Vec<(String, PathBuf)> {
    let ws = toml_at(&Path::new(ROOT).join("Cargo.toml"));
    let members = ws["workspace"]["members"].as_array().expect("[workspace] members");
    members
        .iter()
        .map(|m| {
            let dir = Path::new(ROOT).join(m.as_str().expect("member"));
            let manifest = toml_at(&dir.join("Cargo.toml"));
            let name = manifest["package"]["name"].as_str().expect("package name").to_owned();
            (name, dir.join("src"))
        })
        .collect()
}

/// Set `UPM_FILE_IMPORTS_EDGES=1` (with `--nocapture`) to see every edge.
#[test]
fn no_file_import_cycles_in_any_crate() {
    let (mut files, mut edges, mut unresolved, mut found) = (0, 0, 0, Vec::new());
    let members = members();
    for (name, src) in &members {
        let graph = CrateGraph::read(name, src);
        files += graph.files.len();
        edges += graph.edges.len();
        unresolved += graph.unresolved.len();
        for u in &graph.unresolved {
            eprintln!("not found, counted against the module's file: {name}: {u}");
        }
        if std::env::var_os("UPM_FILE_IMPORTS_EDGES").is_some() {
            for ((a, b), names) in &graph.edges {
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                eprintln!(
                    "{name}: {} -> {} ({})",
                    graph.files[*a].rel,
                    graph.files[*b].rel,
                    names.join(", ")
                );
            }
        }
        found.extend(graph.cycles().iter().map(|c| graph.describe(c)));
    }
    eprintln!("{} crates, {files} files, {edges} import edges, {unresolved} names not found", members.len());
    // A reader that sees nothing would pass vacuously.
    assert!(files > 100 && edges > 100, "only {files} files and {edges} edges read");
    assert!(found.is_empty(), "files that import each other:\n{}", found.join("\n"));
}

// ---------------------------------------------------------------------------
// The check can fail: tiny crates with a loop, written to a temporary directory.

/// A directory removed when dropped, even if the test panics.
struct TempCrate(PathBuf);

impl TempCrate {
    fn new(case: &str, files: &[(&str, &str)]) -> Self {
        let dir = std::env::temp_dir().join(format!("upm-file-imports-{}-{case}", std::process::id()));
        for (rel, text) in files {
            let path = dir.join("src").join(rel);
            std::fs::create_dir_all(path.parent().expect("parent")).expect("create dir");
            std::fs::write(&path, text).expect("write file");
        }
        TempCrate(dir)
    }
}

impl Drop for TempCrate {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The cycles found in a synthetic crate, as file sets and as the message.
fn synthetic_cycles(case: &str, files: &[(&str, &str)]) -> (Vec<BTreeSet<String>>, Vec<String>) {
    let dir = TempCrate::new(case, files);
    let graph = CrateGraph::read(case, &dir.0.join("src"));
    let cycles = graph.cycles();
    let sets = cycles.iter().map(|c| c.iter().map(|&f| graph.files[f].rel.clone()).collect()).collect();
    (sets, cycles.iter().map(|c| graph.describe(c)).collect())
}

#[test]
fn a_direct_mutual_import_is_found() {
    let (sets, text) = synthetic_cycles(
        "direct",
        &[
            ("lib.rs", "mod a;\nmod b;\n"),
            ("a.rs", "use crate::b::B;\npub struct A;\n"),
            ("b.rs", "use crate::a::A;\npub struct B;\n"),
        ],
    );
    let expected: BTreeSet<String> = ["a.rs".to_owned(), "b.rs".to_owned()].into();
    assert_eq!(sets, [expected], "{text:?}");
    assert_eq!(text, ["direct: a.rs -> b.rs (B); b.rs -> a.rs (A)"]);
}

#[test]
fn an_import_through_a_re_export_is_found() {
    let (sets, text) = synthetic_cycles(
        "re-export",
        &[
            ("lib.rs", "mod a;\nmod b;\npub use a::A;\n"),
            ("a.rs", "use crate::b::B;\npub struct A;\n"),
            ("b.rs", "use crate::A;\npub struct B;\n"),
        ],
    );
    let expected: BTreeSet<String> = ["a.rs".to_owned(), "b.rs".to_owned()].into();
    assert_eq!(sets, [expected], "{text:?}");
    assert_eq!(text, ["re-export: a.rs -> b.rs (B); b.rs -> a.rs (A)"]);
}

#[test]
fn test_code_comments_and_strings_are_no_imports() {
    let (sets, text) = synthetic_cycles(
        "quiet",
        &[
            ("lib.rs", "mod a;\nmod b;\n"),
            ("a.rs", "use crate::b::B;\npub struct A;\n"),
            (
                "b.rs",
                "//! See [`crate::a::A`].\npub struct B; // crate::a::A\n\
                 const S: &str = \"crate::a::A\";\n\
                 #[cfg(test)]\nmod tests {\n    use super::*;\n    use crate::a::A;\n}\n",
            ),
        ],
    );
    assert!(sets.is_empty(), "{text:?}");
}
