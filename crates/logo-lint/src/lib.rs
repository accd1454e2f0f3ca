//! Rules that keep logo-rl's own source tree easy to work in, checked by its tests:
//! the modules of a crate import each other without a cycle, and the trainer's
//! functions stay short enough to read as the steps of Algorithm 1.
//!
//! The module graph is read with `syn`: a module depends on another when its code
//! names a path into it (`use` trees and paths in code alike, through `crate::`,
//! `super::`, `self::` or a child module's name). Re-exports are followed to the
//! module that defines the item, so `pub use` at a crate root adds no false circle.
//! `#[cfg(test)]` modules are left out: unit tests use their parent by design.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

use syn::visit::Visit;

/// A module's path inside its crate: empty for the crate root.
pub type ModPath = Vec<String>;

/// Something wrong with the source tree itself (unreadable, unparsable).
#[derive(Debug)]
pub struct LintError(pub String);

impl fmt::Display for LintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LintError {}

/// One reference from a module to a path, with where it was written.
#[derive(Debug, Clone)]
struct Reference {
    /// Absolute path from the crate root (segments after `crate`).
    path: Vec<String>,
    location: String,
}

#[derive(Debug, Default)]
struct Module {
    file: PathBuf,
    children: BTreeSet<String>,
    /// Names this module defines itself (types, functions, constants, macros).
    items: BTreeSet<String>,
    /// Names brought in by `use` (alias → absolute path), which other modules can reach.
    imports: BTreeMap<String, Vec<String>>,
    /// Absolute module paths of glob imports.
    globs: Vec<Vec<String>>,
    references: Vec<Reference>,
}

/// A dependency of one module on another, with one place that causes it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    pub from: ModPath,
    pub to: ModPath,
    /// `file:line` and the path written there.
    pub example: String,
}

/// The modules of one crate and what each one imports.
#[derive(Debug)]
pub struct ModuleGraph {
    pub crate_name: String,
    modules: BTreeMap<ModPath, Module>,
}

/// Human-readable module path: `crate` or `trainer::iteration`.
pub fn display(path: &[String]) -> String {
    if path.is_empty() {
        "crate".to_string()
    } else {
        path.join("::")
    }
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|attr| {
        attr.path().is_ident("cfg")
            && attr
                .parse_args::<syn::Meta>()
                .is_ok_and(|meta| meta.path().is_ident("test"))
    })
}

fn line_of(span: proc_macro2::Span) -> usize {
    span.start().line
}

impl ModuleGraph {
    /// Read a crate from its `src/` folder (root `lib.rs`, else `main.rs`).
    pub fn load(crate_name: &str, src: &Path) -> Result<Self, LintError> {
        let root = ["lib.rs", "main.rs"]
            .iter()
            .map(|name| src.join(name))
            .find(|path| path.is_file())
            .ok_or_else(|| LintError(format!("{}: no lib.rs or main.rs", src.display())))?;
        let mut graph = ModuleGraph {
            crate_name: crate_name.to_string(),
            modules: BTreeMap::new(),
        };
        graph.load_file(Vec::new(), &root, src.to_path_buf())?;
        Ok(graph)
    }

    fn load_file(&mut self, path: ModPath, file: &Path, dir: PathBuf) -> Result<(), LintError> {
        let text = std::fs::read_to_string(file)
            .map_err(|e| LintError(format!("{}: cannot read: {e}", file.display())))?;
        let parsed = syn::parse_file(&text)
            .map_err(|e| LintError(format!("{}: cannot parse: {e}", file.display())))?;
        self.load_items(path, file, dir, &parsed.items)
    }

    /// `dir` is where this module's child files live.
    fn load_items(
        &mut self,
        path: ModPath,
        file: &Path,
        dir: PathBuf,
        items: &[syn::Item],
    ) -> Result<(), LintError> {
        let mut module = Module {
            file: file.to_path_buf(),
            ..Module::default()
        };
        let mut children = Vec::new();
        for item in items {
            match item {
                syn::Item::Mod(m) if is_cfg_test(&m.attrs) => {}
                syn::Item::Mod(m) => {
                    module.children.insert(m.ident.to_string());
                    children.push(m);
                }
                syn::Item::Use(u) => {
                    let mut prefix = Vec::new();
                    collect_use(&path, &u.tree, &mut prefix, &mut module, file);
                }
                other => {
                    if let Some(name) = item_name(other) {
                        module.items.insert(name);
                    }
                }
            }
        }
        // Paths in code, once the module's children are known (so `child::x` resolves).
        for item in items {
            if matches!(item, syn::Item::Mod(_) | syn::Item::Use(_)) {
                continue;
            }
            let mut visitor = PathVisitor {
                module: &path,
                children: &module.children,
                found: Vec::new(),
            };
            visitor.visit_item(item);
            for (segments, line) in visitor.found {
                module.references.push(Reference {
                    path: segments.clone(),
                    location: format!("{}:{line} {}", file.display(), segments.join("::")),
                });
            }
        }
        self.modules.insert(path.clone(), module);
        for child in children {
            let name = child.ident.to_string();
            let mut child_path = path.clone();
            child_path.push(name.clone());
            match &child.content {
                Some((_, inline)) => self.load_items(child_path, file, dir.join(&name), inline)?,
                None => {
                    let flat = dir.join(format!("{name}.rs"));
                    let nested = dir.join(&name).join("mod.rs");
                    let child_file = if flat.is_file() {
                        flat
                    } else if nested.is_file() {
                        nested
                    } else {
                        return Err(LintError(format!(
                            "{}: module `{name}` has neither {} nor {}",
                            file.display(),
                            flat.display(),
                            nested.display()
                        )));
                    };
                    self.load_file(child_path, &child_file, dir.join(&name))?;
                }
            }
        }
        Ok(())
    }

    /// Resolve an absolute path to the module that defines what it names.
    fn resolve(&self, path: &[String], depth: usize) -> ModPath {
        let mut current: ModPath = Vec::new();
        for (index, segment) in path.iter().enumerate() {
            let Some(module) = self.modules.get(&current) else {
                break;
            };
            if module.children.contains(segment) {
                current.push(segment.clone());
                continue;
            }
            if module.items.contains(segment) || depth > 16 {
                break;
            }
            if let Some(target) = module.imports.get(segment) {
                let mut rest = target.clone();
                rest.extend_from_slice(&path[index + 1..]);
                return self.resolve(&rest, depth + 1);
            }
            // A name a glob brought in: the first glob module that knows it.
            for glob in &module.globs {
                let knows = self.modules.get(glob).is_some_and(|m| {
                    m.children.contains(segment)
                        || m.items.contains(segment)
                        || m.imports.contains_key(segment)
                });
                if knows {
                    let mut candidate = glob.clone();
                    candidate.extend_from_slice(&path[index..]);
                    return self.resolve(&candidate, depth + 1);
                }
            }
            break;
        }
        current
    }

    /// Every module-to-module dependency, one example each.
    pub fn edges(&self) -> Vec<Edge> {
        let mut edges: BTreeMap<(ModPath, ModPath), String> = BTreeMap::new();
        for (from, module) in &self.modules {
            for reference in &module.references {
                let to = self.resolve(&reference.path, 0);
                if to != *from && self.modules.contains_key(&to) {
                    edges
                        .entry((from.clone(), to))
                        .or_insert_with(|| reference.location.clone());
                }
            }
        }
        edges
            .into_iter()
            .map(|((from, to), example)| Edge { from, to, example })
            .collect()
    }

    /// Groups of modules that import each other (strongly connected, more than one
    /// module), each with the edges inside it.
    pub fn cycles(&self) -> Vec<Vec<Edge>> {
        let edges = self.edges();
        let nodes: Vec<&ModPath> = self.modules.keys().collect();
        let index_of: BTreeMap<&ModPath, usize> =
            nodes.iter().enumerate().map(|(i, n)| (*n, i)).collect();
        let mut adjacency = vec![Vec::new(); nodes.len()];
        for edge in &edges {
            adjacency[index_of[&edge.from]].push(index_of[&edge.to]);
        }
        let components = strongly_connected(&adjacency);
        components
            .into_iter()
            .filter(|component| component.len() > 1)
            .map(|component| {
                let members: BTreeSet<&ModPath> = component.iter().map(|&i| nodes[i]).collect();
                edges
                    .iter()
                    .filter(|e| members.contains(&e.from) && members.contains(&e.to))
                    .cloned()
                    .collect()
            })
            .collect()
    }

    /// The file each module was read from.
    pub fn file_of(&self, path: &[String]) -> Option<&Path> {
        self.modules.get(path).map(|m| m.file.as_path())
    }
}

fn item_name(item: &syn::Item) -> Option<String> {
    let ident = match item {
        syn::Item::Const(i) => &i.ident,
        syn::Item::Enum(i) => &i.ident,
        syn::Item::Fn(i) => &i.sig.ident,
        syn::Item::Static(i) => &i.ident,
        syn::Item::Struct(i) => &i.ident,
        syn::Item::Trait(i) => &i.ident,
        syn::Item::Type(i) => &i.ident,
        syn::Item::Union(i) => &i.ident,
        syn::Item::Macro(i) => i.ident.as_ref()?,
        _ => return None,
    };
    Some(ident.to_string())
}

/// Turn the first segment(s) of a path written in `module` into an absolute path,
/// or `None` when it leaves the crate (another crate, a local name, a type parameter).
fn absolute(
    module: &[String],
    children: &BTreeSet<String>,
    segments: &[String],
) -> Option<Vec<String>> {
    let mut base: Vec<String> = module.to_vec();
    let mut rest = segments;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &rest[1..];
        }
        Some("super") | Some("self") => {
            while let Some(first) = rest.first() {
                match first.as_str() {
                    "super" => {
                        base.pop()?;
                    }
                    "self" => {}
                    _ => break,
                }
                rest = &rest[1..];
            }
        }
        Some(first) if children.contains(first) => {}
        _ => return None,
    }
    base.extend_from_slice(rest);
    Some(base)
}

fn collect_use(
    module: &[String],
    tree: &syn::UseTree,
    prefix: &mut Vec<String>,
    into: &mut Module,
    file: &Path,
) {
    let mut record = |segments: Vec<String>, alias: Option<String>, glob: bool, line: usize| {
        let import = UseImport {
            segments,
            alias,
            glob,
            line,
        };
        import.record(module, into, file);
    };
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            collect_use(module, &p.tree, prefix, into, file);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            let mut segments = prefix.clone();
            // `use a::b::{self}` names the module `b` itself.
            let alias = if name == "self" {
                prefix.last().cloned()
            } else {
                Some(name.clone())
            };
            if name != "self" {
                segments.push(name);
            }
            record(segments, alias, false, line_of(n.ident.span()));
        }
        syn::UseTree::Rename(r) => {
            let mut segments = prefix.clone();
            if r.ident != "self" {
                segments.push(r.ident.to_string());
            }
            let alias = Some(r.rename.to_string());
            record(segments, alias, false, line_of(r.ident.span()));
        }
        syn::UseTree::Glob(g) => {
            record(prefix.clone(), None, true, line_of(g.star_token.spans[0]));
        }
        syn::UseTree::Group(g) => {
            for tree in &g.items {
                collect_use(module, tree, prefix, into, file);
            }
        }
    }
}

/// One name a `use` item brings in: its path, the name it is known by, and whether it
/// is a glob.
struct UseImport {
    segments: Vec<String>,
    alias: Option<String>,
    glob: bool,
    line: usize,
}

impl UseImport {
    /// Adds the import to `into`, the module `module` of `file`.
    fn record(self, module: &[String], into: &mut Module, file: &Path) {
        let UseImport {
            segments,
            alias,
            glob,
            line,
        } = self;
        // Child modules are not known yet while `use` items are read: treat a first
        // segment that is not crate/super/self as a child and let resolution drop it if
        // no such module exists.
        let mut children = BTreeSet::new();
        if let Some(first) = segments.first() {
            children.insert(first.clone());
        }
        let Some(path) = absolute(module, &children, &segments) else {
            return;
        };
        if glob {
            into.globs.push(path.clone());
        } else if let Some(alias) = alias.filter(|a| a != "_") {
            into.imports.insert(alias, path.clone());
        }
        into.references.push(Reference {
            location: format!(
                "{}:{line} use {}{}",
                file.display(),
                segments.join("::"),
                if glob { "::*" } else { "" }
            ),
            path,
        });
    }
}

/// Collects the crate-internal paths written in code (not in `use` items).
struct PathVisitor<'a> {
    module: &'a [String],
    children: &'a BTreeSet<String>,
    found: Vec<(Vec<String>, usize)>,
}

impl<'ast> Visit<'ast> for PathVisitor<'_> {
    fn visit_path(&mut self, path: &'ast syn::Path) {
        let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        let crate_internal = (path.leading_colon.is_none() && segments.len() > 1)
            .then(|| absolute(self.module, self.children, &segments))
            .flatten();
        if let Some(absolute) = crate_internal {
            let line = path.segments.first().map_or(0, |s| line_of(s.ident.span()));
            self.found.push((absolute, line));
        }
        syn::visit::visit_path(self, path);
    }

    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {
        // Inline modules are read as modules of their own.
    }
}

/// Tarjan's strongly connected components over an adjacency list.
fn strongly_connected(adjacency: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        adjacency: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        components: Vec<Vec<usize>>,
    }
    fn visit(state: &mut State<'_>, node: usize) {
        state.index[node] = Some(state.next);
        state.low[node] = state.next;
        state.next += 1;
        state.stack.push(node);
        state.on_stack[node] = true;
        for &next in &state.adjacency[node] {
            match state.index[next] {
                None => {
                    visit(state, next);
                    state.low[node] = state.low[node].min(state.low[next]);
                }
                Some(index) if state.on_stack[next] => state.low[node] = state.low[node].min(index),
                Some(_) => {}
            }
        }
        if Some(state.low[node]) == state.index[node] {
            let mut component = Vec::new();
            while let Some(top) = state.stack.pop() {
                state.on_stack[top] = false;
                component.push(top);
                if top == node {
                    break;
                }
            }
            state.components.push(component);
        }
    }
    let n = adjacency.len();
    let mut state = State {
        adjacency,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        components: Vec::new(),
    };
    for node in 0..n {
        if state.index[node].is_none() {
            visit(&mut state, node);
        }
    }
    state.components
}

/// A function longer than the limit: where, its name and its length in lines, and the
/// reason its doc comment gives for being long (a line starting [`LONG_BY_DESIGN`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LongFunction {
    pub file: PathBuf,
    pub name: String,
    pub line: usize,
    pub lines: usize,
    pub reason: Option<String>,
}

/// How a function's doc comment states why it is clearer whole than split.
pub const LONG_BY_DESIGN: &str = "Long by design:";

/// The doc comment's line that starts with [`LONG_BY_DESIGN`], if any.
fn stated_reason(attrs: &[syn::Attribute]) -> Option<String> {
    attrs.iter().find_map(|attr| {
        let syn::Meta::NameValue(doc) = &attr.meta else {
            return None;
        };
        if !doc.path.is_ident("doc") {
            return None;
        }
        let syn::Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Str(text),
            ..
        }) = &doc.value
        else {
            return None;
        };
        let line = text.value();
        let reason = line.trim().strip_prefix(LONG_BY_DESIGN)?.trim().to_string();
        (!reason.is_empty()).then_some(reason)
    })
}

/// Every function (free, in an impl or a trait) in `files` longer than `max_lines`,
/// counting from its signature's first line to its closing brace.
pub fn long_functions(files: &[PathBuf], max_lines: usize) -> Result<Vec<LongFunction>, LintError> {
    struct Lengths {
        file: PathBuf,
        max_lines: usize,
        found: Vec<LongFunction>,
    }
    impl Lengths {
        fn check(
            &mut self,
            attrs: &[syn::Attribute],
            name: &syn::Ident,
            first: proc_macro2::Span,
            block: &syn::Block,
        ) {
            let start = line_of(first);
            let end = block.brace_token.span.close().end().line;
            let lines = end + 1 - start;
            if lines > self.max_lines {
                self.found.push(LongFunction {
                    file: self.file.clone(),
                    name: name.to_string(),
                    line: start,
                    lines,
                    reason: stated_reason(attrs),
                });
            }
        }
    }
    impl<'ast> Visit<'ast> for Lengths {
        fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
            self.check(&f.attrs, &f.sig.ident, f.sig.fn_token.span, &f.block);
            syn::visit::visit_item_fn(self, f);
        }
        fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
            self.check(&f.attrs, &f.sig.ident, f.sig.fn_token.span, &f.block);
            syn::visit::visit_impl_item_fn(self, f);
        }
        fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
            if let Some(block) = &f.default {
                self.check(&f.attrs, &f.sig.ident, f.sig.fn_token.span, block);
            }
            syn::visit::visit_trait_item_fn(self, f);
        }
        fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
            if !is_cfg_test(&m.attrs) {
                syn::visit::visit_item_mod(self, m);
            }
        }
    }
    let mut found = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(file)
            .map_err(|e| LintError(format!("{}: cannot read: {e}", file.display())))?;
        let parsed = syn::parse_file(&text)
            .map_err(|e| LintError(format!("{}: cannot parse: {e}", file.display())))?;
        let mut lengths = Lengths {
            file: file.clone(),
            max_lines,
            found: Vec::new(),
        };
        lengths.visit_file(&parsed);
        found.extend(lengths.found);
    }
    Ok(found)
}
