//! No module-level import cycles in the workspace's crates.
//!
//! Reads every crate of the workspace (the members of the root `Cargo.toml` with a `src/`),
//! follows the `mod` declarations from each crate root (`src/lib.rs`, `src/main.rs`,
//! `src/bin/*.rs`), and builds the graph "module A uses module B" from the paths each file names:
//! `use` declarations and paths written inline (`crate::…`, `super::…`, `self::…`, and paths
//! that start with a name the module imported or declared), plus invocations of the crate's own
//! `macro_rules!` macros. A file is one module: inline modules (`mod tests { … }`, `pub mod out
//! { … }`) belong to the file they are written in. Comments (doc links included: they point at
//! what a reader may look at, not at what the code needs) and string literals are ignored. The
//! test fails on any cycle and names it, with the line that makes each edge. Unit-test modules
//! (`#[cfg(test)] mod … { … }`) are left out: they are clients of their module, not part of its
//! layer.
//!
//! What counts as a dependency, so that a reader can layer the modules:
//! - `mod child;` in a parent is containment, not a use: it does not make the parent depend on
//!   the child.
//! - A path resolves to the module that *defines* the item, through re-exports: a module that
//!   writes `use crate::models::Model` while `models` only re-exports `Model` from
//!   `models::model` depends on `models::model`, not on `models`. So a parent that only declares
//!   and re-exports its children (a facade) is never the target of an edge and cannot close a
//!   cycle with them.
//! - A parent's re-export of its child (`pub use child::Item`) is the parent's use of the
//!   child: the parent's namespace is made of it (edge parent → child). A parent that also
//!   defines items its children use therefore forms a cycle with a child it re-exports; the
//!   fix is to move those items into a module of their own.
//! - Items of other crates (std, dependencies, other workspace crates) are not part of any
//!   crate's module graph; crates themselves cannot form cycles (Cargo forbids it).

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// A module path from the crate root (empty: the root).
type ModPath = Vec<String>;

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Path,
    Punct(char),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    line: usize,
}

/// Splits Rust source into identifiers, `::` and single punctuation, dropping comments, string
/// and character literals, lifetimes and numbers.
fn tokenize(src: &str) -> Vec<Token> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let n = c.len();
    let is_ident_start = |ch: char| ch == '_' || ch.is_alphabetic();
    let is_ident = |ch: char| ch == '_' || ch.is_alphanumeric();
    while i < n {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && i + 1 < n && c[i + 1] == '/' {
            while i < n && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && i + 1 < n && c[i + 1] == '*' {
            let mut depth = 0;
            while i < n {
                if c[i] == '/' && i + 1 < n && c[i + 1] == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && i + 1 < n && c[i + 1] == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if ch == '"'
            || ((ch == 'r' || ch == 'b') && raw_or_byte_string_start(&c, i).is_some())
        {
            // Plain, byte and raw strings.
            let (hashes, start) = if ch == '"' {
                (None, i + 1)
            } else {
                raw_or_byte_string_start(&c, i).unwrap()
            };
            i = start;
            match hashes {
                None => {
                    while i < n && c[i] != '"' {
                        if c[i] == '\\' {
                            i += 1;
                        }
                        if i < n && c[i] == '\n' {
                            line += 1;
                        }
                        i += 1;
                    }
                    i += 1;
                }
                Some(h) => loop {
                    if i >= n {
                        break;
                    }
                    if c[i] == '"' && (0..h).all(|k| c.get(i + 1 + k) == Some(&'#')) {
                        i += 1 + h;
                        break;
                    }
                    if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                },
            }
        } else if ch == '\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime / label ('a).
            if i + 1 < n && c[i + 1] == '\\' {
                i += 2;
                while i < n && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if i + 2 < n && c[i + 2] == '\'' {
                i += 3;
            } else {
                i += 1;
                while i < n && is_ident(c[i]) {
                    i += 1;
                }
            }
        } else if ch.is_ascii_digit() {
            while i < n
                && (is_ident(c[i])
                    || c[i] == '.' && c.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
            {
                i += 1;
            }
        } else if is_ident_start(ch) || (ch == '$' && i + 1 < n && is_ident_start(c[i + 1])) {
            let s = i;
            i += 1;
            while i < n && is_ident(c[i]) {
                i += 1;
            }
            let mut word: String = c[s..i].iter().collect();
            if word == "r" && i < n && c[i] == '#' && i + 1 < n && is_ident_start(c[i + 1]) {
                // Raw identifier r#name.
                let s = i + 1;
                i = s;
                while i < n && is_ident(c[i]) {
                    i += 1;
                }
                word = c[s..i].iter().collect();
            }
            out.push(Token {
                tok: Tok::Ident(word),
                line,
            });
        } else if ch == ':' && i + 1 < n && c[i + 1] == ':' {
            out.push(Token {
                tok: Tok::Path,
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                tok: Tok::Punct(ch),
                line,
            });
            i += 1;
        }
    }
    out
}

/// At `r"`, `r#"`, `b"`, `br"`, `br#"`: the number of `#` (None for a plain byte string) and
/// the index after the opening quote.
fn raw_or_byte_string_start(c: &[char], i: usize) -> Option<(Option<usize>, usize)> {
    if i > 0 && (c[i - 1] == '_' || c[i - 1].is_alphanumeric()) {
        return None;
    }
    let mut j = i;
    let mut raw = false;
    if c[j] == 'b' {
        j += 1;
        if c.get(j) == Some(&'"') {
            return Some((None, j + 1));
        }
    }
    if c.get(j) == Some(&'r') {
        raw = true;
        j += 1;
    }
    if !raw {
        return None;
    }
    let mut h = 0;
    while c.get(j) == Some(&'#') {
        h += 1;
        j += 1;
    }
    (c.get(j) == Some(&'"')).then_some((Some(h), j + 1))
}

/// One path a module names, as written, with the scope it is written in.
#[derive(Debug, Clone)]
struct Named {
    /// The (possibly inline) module the path is written in.
    scope: ModPath,
    segments: Vec<String>,
    line: usize,
    /// Invoked as a macro (`path!`).
    macro_call: bool,
}

/// A `use` binding: `name` in `scope` stands for `target` (relative as written); `glob` for
/// `use target::*`.
#[derive(Debug, Clone)]
struct Binding {
    scope: ModPath,
    name: Option<String>,
    target: Vec<String>,
    line: usize,
}

/// What one file contributes.
#[derive(Debug, Default)]
struct FileInfo {
    /// `mod name;` declarations: (scope, name).
    file_mods: Vec<(ModPath, String)>,
    /// Inline modules `mod name { … }` (their full paths).
    inline_mods: Vec<ModPath>,
    bindings: Vec<Binding>,
    named: Vec<Named>,
    /// `macro_rules!` definitions.
    macros: Vec<String>,
}

fn ident(t: Option<&Token>) -> Option<&str> {
    match t {
        Some(Token {
            tok: Tok::Ident(s), ..
        }) => Some(s),
        _ => None,
    }
}

fn is_punct(t: Option<&Token>, p: char) -> bool {
    matches!(t, Some(Token { tok: Tok::Punct(q), .. }) if *q == p)
}

/// Parses a use tree starting at `toks[i]` (after `use`) with `prefix`, into bindings; returns
/// the index after the tree.
fn parse_use_tree(
    toks: &[Token],
    mut i: usize,
    prefix: Vec<String>,
    scope: &ModPath,
    out: &mut Vec<Binding>,
) -> usize {
    let mut path = prefix;
    if matches!(toks.get(i).map(|t| &t.tok), Some(Tok::Path)) {
        // Leading `::`: an extern crate.
        path.push("::".into());
        i += 1;
    }
    loop {
        match toks.get(i) {
            Some(Token {
                tok: Tok::Ident(s),
                line,
            }) => {
                let line = *line;
                let s = s.clone();
                i += 1;
                if matches!(toks.get(i).map(|t| &t.tok), Some(Tok::Path)) {
                    path.push(s);
                    i += 1;
                    continue;
                }
                // Last segment, maybe `as alias`.
                let mut name = s.clone();
                if s == "self" {
                    name = path.last().cloned().unwrap_or_default();
                } else {
                    path.push(s);
                }
                if ident(toks.get(i)) == Some("as") {
                    name = ident(toks.get(i + 1)).unwrap_or("_").to_string();
                    i += 2;
                }
                out.push(Binding {
                    scope: scope.clone(),
                    name: (name != "_").then_some(name),
                    target: path,
                    line,
                });
                return i;
            }
            Some(Token {
                tok: Tok::Punct('*'),
                line,
            }) => {
                out.push(Binding {
                    scope: scope.clone(),
                    name: None,
                    target: path,
                    line: *line,
                });
                return i + 1;
            }
            Some(Token {
                tok: Tok::Punct('{'),
                ..
            }) => {
                i += 1;
                loop {
                    if is_punct(toks.get(i), '}') {
                        return i + 1;
                    }
                    if toks.get(i).is_none() {
                        return i;
                    }
                    i = parse_use_tree(toks, i, path.clone(), scope, out);
                    if is_punct(toks.get(i), ',') {
                        i += 1;
                    }
                }
            }
            _ => return i,
        }
    }
}

/// True when the item starting at `toks[i]` (after its visibility) carries `#[cfg(test)]`.
fn cfg_test(toks: &[Token], i: usize) -> bool {
    let mut k = i;
    // Skip the visibility (`pub`, `pub(crate)`, `pub(in …)`) backwards.
    while k > 0 {
        match &toks[k - 1].tok {
            Tok::Ident(w) if w == "pub" => k -= 1,
            Tok::Punct(')') if (1..k).rev().any(|m| ident(toks.get(m)) == Some("pub")) => {
                while k > 0 && !is_punct(toks.get(k - 1), '(') {
                    k -= 1;
                }
                k = k.saturating_sub(1);
            }
            _ => break,
        }
    }
    // Attribute groups `#[…]` just before.
    while k > 0 && is_punct(toks.get(k - 1), ']') {
        let end = k - 1;
        let mut start = end;
        while start > 0 && !(is_punct(toks.get(start), '[') && is_punct(toks.get(start - 1), '#')) {
            start -= 1;
        }
        if start == 0 {
            return false;
        }
        let words: Vec<&str> = toks[start + 1..end]
            .iter()
            .map(|t| match &t.tok {
                Tok::Ident(w) => w.as_str(),
                Tok::Punct('(') => "(",
                Tok::Punct(')') => ")",
                _ => "?",
            })
            .collect();
        if words == ["cfg", "(", "test", ")"] {
            return true;
        }
        k = start - 1;
    }
    false
}

/// The index after the block whose `{` is at `toks[open]`.
fn skip_block(toks: &[Token], open: usize) -> usize {
    let mut depth = 0usize;
    let mut k = open;
    while k < toks.len() {
        if is_punct(toks.get(k), '{') {
            depth += 1;
        } else if is_punct(toks.get(k), '}') {
            depth -= 1;
            if depth == 0 {
                return k + 1;
            }
        }
        k += 1;
    }
    k
}

/// Collects the module structure, bindings and named paths of one file whose module is
/// `module`.
fn parse_file(src: &str, module: &ModPath) -> FileInfo {
    let toks = tokenize(src);
    let mut info = FileInfo::default();
    // Stack of (brace depth at which the inline module closes, its path).
    let mut scopes: Vec<(usize, ModPath)> = vec![(usize::MAX, module.clone())];
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        let scope = scopes.last().unwrap().1.clone();
        match &toks[i].tok {
            Tok::Punct('{') => {
                depth += 1;
                i += 1;
            }
            Tok::Punct('}') => {
                if scopes.last().unwrap().0 == depth {
                    scopes.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            Tok::Ident(w) if w == "mod" => {
                let name = ident(toks.get(i + 1)).map(str::to_string);
                match (name, toks.get(i + 2).map(|t| &t.tok)) {
                    (Some(name), Some(Tok::Punct(';'))) => {
                        info.file_mods.push((scope, name));
                        i += 3;
                    }
                    (Some(_), Some(Tok::Punct('{'))) if cfg_test(&toks, i) => {
                        // Unit tests are the module's clients, not part of its layer.
                        i = skip_block(&toks, i + 2);
                    }
                    (Some(name), Some(Tok::Punct('{'))) => {
                        let mut p = scope;
                        p.push(name);
                        info.inline_mods.push(p.clone());
                        depth += 1;
                        scopes.push((depth, p));
                        i += 3;
                    }
                    _ => i += 1,
                }
            }
            Tok::Ident(w) if w == "use" => {
                // `use<'a>` precise capturing in bounds is not an import.
                if is_punct(toks.get(i + 1), '<') {
                    i += 1;
                    continue;
                }
                let before = info.bindings.len();
                i = parse_use_tree(&toks, i + 1, Vec::new(), &scope, &mut info.bindings);
                let _ = before;
            }
            Tok::Ident(w) if w == "macro_rules" && is_punct(toks.get(i + 1), '!') => {
                if let Some(name) = ident(toks.get(i + 2)) {
                    info.macros.push(name.to_string());
                }
                i += 3;
            }
            Tok::Ident(first) => {
                // A path `a::b::c` (not preceded by `::`, which would make it the tail of one).
                let after_path = i > 0 && matches!(toks[i - 1].tok, Tok::Path);
                let line = toks[i].line;
                let mut segments = vec![first.clone()];
                let mut j = i + 1;
                while matches!(toks.get(j).map(|t| &t.tok), Some(Tok::Path)) {
                    match ident(toks.get(j + 1)) {
                        Some(s) => {
                            segments.push(s.to_string());
                            j += 2;
                        }
                        None => break,
                    }
                }
                let macro_call = is_punct(toks.get(j), '!') && !is_punct(toks.get(j + 1), '=');
                if !after_path && (segments.len() > 1 || macro_call) {
                    info.named.push(Named {
                        scope,
                        segments,
                        line,
                        macro_call,
                    });
                }
                i = j.max(i + 1);
            }
            _ => i += 1,
        }
    }
    info
}

/// One crate's modules.
#[derive(Default)]
struct Crate {
    /// Every module (file or inline) → the file that holds it.
    file_of: BTreeMap<ModPath, PathBuf>,
    /// Children (file or inline modules) of each module.
    children: HashMap<ModPath, BTreeSet<String>>,
    /// Named bindings of each module: name → (target as written, scope).
    bindings: HashMap<ModPath, Vec<(String, Vec<String>)>>,
    globs: HashMap<ModPath, Vec<Vec<String>>>,
    /// Macro name → file defining it.
    macros: HashMap<String, PathBuf>,
    files: BTreeMap<PathBuf, FileInfo>,
}

/// An edge's evidence: the file and line, and the path as written.
type Why = (usize, String);

impl Crate {
    /// Reads the crate rooted at `root` (`src/lib.rs` or a binary root) from `read`.
    fn load(root: &Path, read: &dyn Fn(&Path) -> Option<String>) -> Self {
        let mut c = Crate::default();
        let mut queue = vec![(root.to_path_buf(), ModPath::new())];
        while let Some((file, module)) = queue.pop() {
            let Some(src) = read(&file) else { continue };
            let info = parse_file(&src, &module);
            c.file_of.insert(module.clone(), file.clone());
            c.children.entry(module.clone()).or_default();
            for m in &info.inline_mods {
                c.file_of.insert(m.clone(), file.clone());
                let (name, parent) = m.split_last().unwrap();
                c.children
                    .entry(parent.to_vec())
                    .or_default()
                    .insert(name.clone());
                c.children.entry(m.clone()).or_default();
            }
            // Where `mod x;` files live: beside a mod.rs / lib.rs / main.rs, else in a folder
            // named after the file; inline modules add their names.
            let stem = file.file_stem().unwrap().to_string_lossy().to_string();
            let base = if module.is_empty() || stem == "mod" {
                file.parent().unwrap().to_path_buf()
            } else {
                file.parent().unwrap().join(&stem)
            };
            for (scope, name) in &info.file_mods {
                let mut dir = base.clone();
                for s in &scope[module.len()..] {
                    dir.push(s);
                }
                let flat = dir.join(format!("{name}.rs"));
                let nested = dir.join(name).join("mod.rs");
                let path = if read(&flat).is_some() { flat } else { nested };
                let mut m = scope.clone();
                m.push(name.clone());
                c.children
                    .entry(scope.clone())
                    .or_default()
                    .insert(name.clone());
                queue.push((path, m));
            }
            for b in &info.bindings {
                match &b.name {
                    Some(n) => c
                        .bindings
                        .entry(b.scope.clone())
                        .or_default()
                        .push((n.clone(), b.target.clone())),
                    None => c
                        .globs
                        .entry(b.scope.clone())
                        .or_default()
                        .push(b.target.clone()),
                }
            }
            for m in &info.macros {
                c.macros.insert(m.clone(), file.clone());
            }
            c.files.insert(file, info);
        }
        c
    }

    /// The absolute module-path form of `segments` written in `scope`, or None when the path
    /// leaves the crate (std, dependencies) or is not a path to an item (a generic, `Self`).
    fn absolute(&self, scope: &ModPath, segments: &[String], depth: usize) -> Option<Vec<String>> {
        self.absolute_with(scope, segments, depth, true)
    }

    /// [`Crate::absolute`], looking through the scope's glob imports only when `globs` (a glob
    /// import's own path is resolved without them, which keeps the search finite and cheap).
    fn absolute_with(
        &self,
        scope: &ModPath,
        segments: &[String],
        depth: usize,
        globs: bool,
    ) -> Option<Vec<String>> {
        if depth > 16 || segments.is_empty() {
            return None;
        }
        let first = segments[0].as_str();
        let rest = &segments[1..];
        let mut base = match first {
            "crate" | "$crate" => Vec::new(),
            "self" => scope.clone(),
            "super" => {
                let mut s = scope.clone();
                s.pop();
                let mut r = rest;
                while r.first().map(String::as_str) == Some("super") {
                    s.pop();
                    r = &r[1..];
                }
                s.extend(r.iter().cloned());
                return Some(s);
            }
            "::" | "Self" => return None,
            _ => {
                if self.children.get(scope).is_some_and(|c| c.contains(first)) {
                    let mut s = scope.clone();
                    s.push(first.to_string());
                    s.extend(rest.iter().cloned());
                    return Some(s);
                }
                if let Some((_, target)) = self
                    .bindings
                    .get(scope)
                    .and_then(|b| b.iter().find(|(n, _)| n == first))
                {
                    let mut t = self.absolute_with(scope, target, depth + 1, globs)?;
                    t.extend(rest.iter().cloned());
                    return Some(t);
                }
                if !globs {
                    return None;
                }
                for g in self.globs.get(scope).into_iter().flatten() {
                    if let Some(gabs) = self.absolute_with(scope, g, depth + 1, false) {
                        if self.has_name(&gabs, first) {
                            let mut t = gabs;
                            t.extend(segments.iter().cloned());
                            return Some(t);
                        }
                    }
                }
                return None;
            }
        };
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// True when module `m` has a child module or a binding called `name`.
    fn has_name(&self, m: &ModPath, name: &str) -> bool {
        self.children.get(m).is_some_and(|c| c.contains(name))
            || self
                .bindings
                .get(m)
                .is_some_and(|b| b.iter().any(|(n, _)| n == name))
    }

    /// The module defining the item at absolute path `abs`, following re-exports.
    fn resolve(&self, abs: &[String], depth: usize) -> ModPath {
        let mut cur = ModPath::new();
        for (k, seg) in abs.iter().enumerate() {
            if self.children.get(&cur).is_some_and(|c| c.contains(seg)) {
                cur.push(seg.clone());
                continue;
            }
            if depth < 16 {
                if let Some((_, target)) = self
                    .bindings
                    .get(&cur)
                    .and_then(|b| b.iter().find(|(n, _)| n == seg))
                {
                    if let Some(mut t) = self.absolute(&cur, target, 0) {
                        t.extend(abs[k + 1..].iter().cloned());
                        return self.resolve(&t, depth + 1);
                    }
                    // A re-export of another crate's item: defined outside this crate.
                    return cur;
                }
                for g in self.globs.get(&cur).into_iter().flatten() {
                    if let Some(gabs) = self.absolute_with(&cur, g, 0, false) {
                        if self.has_name(&gabs, seg) {
                            let mut t = gabs;
                            t.extend(abs[k..].iter().cloned());
                            return self.resolve(&t, depth + 1);
                        }
                    }
                }
            }
            break;
        }
        cur
    }

    /// The file holding module `m` (an inline module's file).
    fn file(&self, m: &ModPath) -> Option<&PathBuf> {
        let mut m = m.clone();
        loop {
            if let Some(f) = self.file_of.get(&m) {
                return Some(f);
            }
            m.pop()?;
        }
    }

    /// File-level edges with the first line that makes each.
    fn edges(&self) -> BTreeMap<(PathBuf, PathBuf), Why> {
        let mut edges = BTreeMap::new();
        let mut add = |from: &PathBuf, to: Option<&PathBuf>, why: Why| {
            if let Some(to) = to {
                if to != from {
                    edges.entry((from.clone(), to.clone())).or_insert(why);
                }
            }
        };
        for (file, info) in &self.files {
            for b in &info.bindings {
                if let Some(abs) = self.absolute(&b.scope, &b.target, 0) {
                    let m = self.resolve(&abs, 0);
                    add(
                        file,
                        self.file(&m),
                        (b.line, format!("use {}", b.target.join("::"))),
                    );
                }
            }
            for n in &info.named {
                if n.macro_call {
                    if let Some(def) = self.macros.get(n.segments.last().unwrap()) {
                        let shown = format!("{}!", n.segments.join("::"));
                        add(file, Some(def), (n.line, shown));
                        continue;
                    }
                }
                if n.segments.len() < 2 {
                    continue;
                }
                if let Some(abs) = self.absolute(&n.scope, &n.segments, 0) {
                    let m = self.resolve(&abs, 0);
                    add(file, self.file(&m), (n.line, n.segments.join("::")));
                }
            }
        }
        edges
    }
}

/// One cycle (each file with the evidence of its edge to the next) and every file of its
/// strongly connected component.
type Cycle = (Vec<(PathBuf, Why)>, Vec<PathBuf>);

/// Every cycle of the file graph, one per strongly connected component, each as the files in
/// order with the evidence of each edge.
fn cycles(edges: &BTreeMap<(PathBuf, PathBuf), Why>) -> Vec<Cycle> {
    let mut adj: BTreeMap<&PathBuf, Vec<&PathBuf>> = BTreeMap::new();
    for (a, b) in edges.keys() {
        adj.entry(a).or_default().push(b);
        adj.entry(b).or_default();
    }
    // Tarjan's strongly connected components.
    struct St<'a> {
        index: HashMap<&'a PathBuf, usize>,
        low: HashMap<&'a PathBuf, usize>,
        on: BTreeSet<&'a PathBuf>,
        stack: Vec<&'a PathBuf>,
        sccs: Vec<Vec<&'a PathBuf>>,
        next: usize,
    }
    fn visit<'a>(v: &'a PathBuf, adj: &BTreeMap<&'a PathBuf, Vec<&'a PathBuf>>, s: &mut St<'a>) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        s.on.insert(v);
        for &w in &adj[v] {
            if !s.index.contains_key(w) {
                visit(w, adj, s);
                let l = s.low[w].min(s.low[v]);
                s.low.insert(v, l);
            } else if s.on.contains(w) {
                let l = s.index[w].min(s.low[v]);
                s.low.insert(v, l);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(w);
                comp.push(w);
                if w == v {
                    break;
                }
            }
            s.sccs.push(comp);
        }
    }
    let mut s = St {
        index: HashMap::new(),
        low: HashMap::new(),
        on: BTreeSet::new(),
        stack: Vec::new(),
        sccs: Vec::new(),
        next: 0,
    };
    for &v in adj.keys() {
        if !s.index.contains_key(v) {
            visit(v, &adj, &mut s);
        }
    }
    let mut found = Vec::new();
    for comp in s.sccs.into_iter().filter(|c| c.len() > 1) {
        // A shortest cycle through the component's first file (breadth-first inside it).
        let members: BTreeSet<&PathBuf> = comp.iter().copied().collect();
        let start = *members.iter().next().unwrap();
        let mut prev: HashMap<&PathBuf, &PathBuf> = HashMap::new();
        let mut queue = std::collections::VecDeque::from([start]);
        let mut end = None;
        'bfs: while let Some(v) = queue.pop_front() {
            for &w in &adj[v] {
                if !members.contains(w) {
                    continue;
                }
                if w == start {
                    end = Some(v);
                    break 'bfs;
                }
                if !prev.contains_key(w) {
                    prev.insert(w, v);
                    queue.push_back(w);
                }
            }
        }
        let mut path = vec![end.unwrap()];
        while *path.last().unwrap() != start {
            path.push(prev[path.last().unwrap()]);
        }
        path.reverse();
        let cycle = path
            .iter()
            .enumerate()
            .map(|(k, &a)| {
                let b = path.get(k + 1).copied().unwrap_or(start);
                (a.clone(), edges[&(a.clone(), b.clone())].clone())
            })
            .collect();
        found.push((cycle, members.iter().map(|p| (*p).clone()).collect()));
    }
    found
}

/// The cycles of the crate rooted at `root`, as messages.
fn crate_cycles(root: &Path, read: &dyn Fn(&Path) -> Option<String>) -> Vec<String> {
    let c = Crate::load(root, read);
    cycles(&c.edges())
        .into_iter()
        .map(|(cycle, members)| {
            let mut msg = format!("import cycle in the crate of {}:\n", root.display());
            for (k, (file, (line, what))) in cycle.iter().enumerate() {
                let next = &cycle[(k + 1) % cycle.len()].0;
                msg.push_str(&format!(
                    "  {} uses {} ({}:{line}: {what})\n",
                    file.display(),
                    next.display(),
                    file.display()
                ));
            }
            if members.len() > cycle.len() {
                msg.push_str(&format!(
                    "  (one of the cycles among these {} files, which all reach each other: {})\n",
                    members.len(),
                    members
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
            msg
        })
        .collect()
}

/// The crate roots of the workspace, relative to it: each member's `src/lib.rs`, `src/main.rs`
/// and `src/bin/*.rs`.
fn workspace_roots(ws: &Path) -> Vec<PathBuf> {
    let manifest: toml::Table = std::fs::read_to_string(ws.join("Cargo.toml"))
        .expect("the workspace's Cargo.toml")
        .parse()
        .expect("Cargo.toml parses");
    let mut members = vec![PathBuf::new()];
    if let Some(list) = manifest
        .get("workspace")
        .and_then(|w| w.get("members"))
        .and_then(|m| m.as_array())
    {
        for m in list.iter().filter_map(|m| m.as_str()) {
            if let Some(prefix) = m.strip_suffix("/*") {
                let dir = ws.join(prefix);
                for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
                    members.push(e.path().strip_prefix(ws).unwrap().to_path_buf());
                }
            } else if m != "." {
                members.push(PathBuf::from(m));
            }
        }
    }
    let mut roots = BTreeSet::new();
    for m in members {
        let src = m.join("src");
        for f in ["lib.rs", "main.rs"] {
            if ws.join(&src).join(f).is_file() {
                roots.insert(src.join(f));
            }
        }
        for e in std::fs::read_dir(ws.join(&src).join("bin"))
            .into_iter()
            .flatten()
            .flatten()
        {
            let p = src.join("bin").join(e.file_name());
            if p.extension().is_some_and(|x| x == "rs") {
                roots.insert(p);
            } else if ws.join(&p).join("main.rs").is_file() {
                roots.insert(p.join("main.rs"));
            }
        }
    }
    roots.into_iter().collect()
}

#[test]
fn no_module_level_import_cycles() {
    let ws = Path::new(env!("CARGO_MANIFEST_DIR"));
    let roots = workspace_roots(ws);
    assert!(
        roots.iter().any(|r| r.ends_with("src/lib.rs")),
        "no library root found under {}",
        ws.display()
    );
    let read = |p: &Path| std::fs::read_to_string(ws.join(p)).ok();
    let mut problems = Vec::new();
    let mut files = 0;
    for root in &roots {
        files += Crate::load(root, &read).files.len();
        for cycle in crate_cycles(root, &read) {
            problems.push(cycle);
        }
    }
    assert!(
        files > 20,
        "only {files} files read: is the module walk broken?"
    );
    assert!(
        problems.is_empty(),
        "{} module-level import cycle(s) (see tests/module_cycles.rs for what counts):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// The checker on made-up crates: it finds cycles through `use`, inline paths, `super` and
/// macros, and it does not count `mod` declarations or paths through a facade's re-exports.
#[cfg(test)]
mod checker {
    use super::*;

    fn run(files: &[(&str, &str)]) -> Vec<String> {
        let map: HashMap<PathBuf, String> = files
            .iter()
            .map(|(p, s)| (PathBuf::from(p), s.to_string()))
            .collect();
        let read = |p: &Path| map.get(p).cloned();
        crate_cycles(Path::new("src/lib.rs"), &read)
    }

    #[test]
    fn a_use_cycle_is_found_and_named() {
        let found = run(&[
            ("src/lib.rs", "pub mod a;\npub mod b;\n"),
            ("src/a.rs", "use crate::b::B;\npub struct A;\n"),
            (
                "src/b.rs",
                "pub struct B;\nfn f() { let _ = crate::a::A; }\n",
            ),
        ]);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].contains("src/a.rs uses src/b.rs"), "{}", found[0]);
        assert!(found[0].contains("crate::a::A"), "{}", found[0]);
    }

    #[test]
    fn a_child_using_its_parents_own_item_while_the_parent_uses_it_is_a_cycle() {
        let found = run(&[
            ("src/lib.rs", "pub mod m;\n"),
            (
                "src/m/mod.rs",
                "pub mod c;\npub struct Shared;\npub fn build() { c::C::new(); }\n",
            ),
            ("src/m/c.rs", "use super::Shared;\npub struct C;\n"),
        ]);
        assert_eq!(found.len(), 1, "{found:?}");
    }

    #[test]
    fn a_facade_parent_and_mod_declarations_make_no_cycle() {
        let found = run(&[
            ("src/lib.rs", "pub mod m;\npub use m::C;\n"),
            (
                "src/m/mod.rs",
                "mod api;\nmod c;\npub use api::{Shared, helper};\npub use self::c::C;\n",
            ),
            ("src/m/api.rs", "pub struct Shared;\npub fn helper() {}\n"),
            (
                "src/m/c.rs",
                "use crate::m::Shared;\npub struct C;\nfn f() { super::helper(); crate::C; }\n",
            ),
        ]);
        assert!(found.is_empty(), "{found:?}");
    }

    #[test]
    fn macros_super_and_inline_modules_count() {
        let found = run(&[
            ("src/lib.rs", "pub mod a;\npub mod b;\n"),
            (
                "src/a.rs",
                "macro_rules! make { () => { $crate::b::g() } }\npub(crate) use make;\n\
                 pub mod out { pub const X: usize = 0; }\n",
            ),
            (
                "src/b.rs",
                "pub fn g() {}\nmod tests { fn t() { let _ = super::super::a::out::X; } }\n\
                 // crate::nothing::here in a comment\nconst S: &str = \"crate::a::x\";\n",
            ),
        ]);
        assert_eq!(found.len(), 1, "{found:?}");
        let only_macro = run(&[
            ("src/lib.rs", "pub mod a;\npub mod b;\n"),
            (
                "src/a.rs",
                "macro_rules! make { () => { 1 } }\npub(crate) use make;\nuse crate::b::g;\n",
            ),
            ("src/b.rs", "pub fn g() -> i32 { crate::a::make!() }\n"),
        ]);
        assert_eq!(only_macro.len(), 1, "{only_macro:?}");
    }

    #[test]
    fn unit_test_modules_do_not_count() {
        let found = run(&[
            ("src/lib.rs", "pub mod a;\npub mod b;\n"),
            ("src/a.rs", "use crate::b::B;\npub struct A;\n"),
            (
                "src/b.rs",
                "pub struct B;\n#[cfg(test)]\nmod tests { use crate::a::A; }\n",
            ),
        ]);
        assert!(found.is_empty(), "{found:?}");
    }

    #[test]
    fn the_tokenizer_skips_literals_and_comments() {
        let t =
            tokenize("let c = '\"'; /* crate::x /* nested */ */ let s = r#\"a\"b\"#; 'a: loop {}");
        let words: Vec<_> = t
            .iter()
            .filter_map(|t| match &t.tok {
                Tok::Ident(s) => Some(s.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(words, ["let", "c", "let", "s", "loop"]);
    }
}
