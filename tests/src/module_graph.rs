//! A crate's modules and what each one's shipped code names, read from the source the way the
//! compiler finds it: from `lib.rs` through every `mod` declaration, leaving out what only tests
//! compile (`#[cfg(test)]`).
//!
//! The walls test asks this graph whether one part of a crate can reach another, following
//! `use` declarations and paths in code through as many modules as it takes. Paths inside macro
//! bodies (`format!`, `json!`) are tokens, not paths, and are not followed; a module's name in a
//! macro's own path (`sqlx::query!`) is.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::{Path, PathBuf};

use syn::spanned::Spanned;
use syn::visit::Visit;

/// A module's place in its crate, such as `store::tokens` (the crate root is empty).
pub type ModulePath = Vec<String>;

/// One path that a module's shipped code names, resolved against the module.
#[derive(Debug, Clone)]
pub struct Named {
    /// `crate`-relative segments for the crate's own items (`["store", "tokens", "create"]`), or
    /// the segments as written for anything else (`["axum", "Router"]`).
    pub path: Vec<String>,
    /// Whether `path` starts inside this crate.
    pub internal: bool,
    pub line: usize,
}

/// One module: its file and what its shipped code names.
#[derive(Debug)]
pub struct Module {
    pub file: PathBuf,
    pub named: Vec<Named>,
}

/// Every module of one crate.
#[derive(Debug)]
pub struct ModuleGraph {
    pub modules: BTreeMap<ModulePath, Module>,
}

/// How a module was reached from where a search started: each step is a module and the line of
/// its file that names the next one.
#[derive(Debug, Clone)]
pub struct Chain(pub Vec<(ModulePath, PathBuf, usize)>);

impl std::fmt::Display for Chain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let steps: Vec<String> = self
            .0
            .iter()
            .map(|(module, file, line)| {
                format!("{} ({}:{line})", module.join("::"), file.display())
            })
            .collect();
        f.write_str(&steps.join(" → "))
    }
}

impl ModuleGraph {
    /// Reads the crate whose root file is `root` (`src/lib.rs`). Panics on a file that does not
    /// parse, naming it: the compiler would refuse it too.
    pub fn read(root: &Path) -> Self {
        let mut modules = BTreeMap::new();
        read_file(root, Vec::new(), &mut modules);
        Self { modules }
    }

    /// The module that `path` (crate-relative) lands in: its longest prefix that is a module.
    fn module_of(&self, path: &[String]) -> Option<ModulePath> {
        (0..=path.len()).rev().map(|n| path[..n].to_vec()).find(|p| self.modules.contains_key(p))
    }

    /// Each module that names what `forbidden` holds and that a module under any of `from`
    /// reaches, once, by the shortest way (breadth first) from the first start that reaches it.
    /// Panics when one of `from` names no module: a wall around a renamed module would
    /// otherwise hold nothing up.
    pub fn reach(
        &self,
        from: &[ModulePath],
        forbidden: impl Fn(&Named) -> bool,
    ) -> Vec<(Chain, Named)> {
        if let Some(missing) = from.iter().find(|f| !self.modules.contains_key(*f)) {
            panic!("no module {} in this crate: was it renamed?", missing.join("::"));
        }
        let mut found = Vec::new();
        let mut reported = BTreeSet::new();
        for start in self.modules.keys().filter(|m| from.iter().any(|f| m.starts_with(f))) {
            let mut seen = BTreeSet::from([start.clone()]);
            let mut queue = VecDeque::from([(start.clone(), Chain(Vec::new()))]);
            while let Some((module, chain)) = queue.pop_front() {
                let here = &self.modules[&module];
                for named in &here.named {
                    let mut step = chain.clone();
                    step.0.push((module.clone(), here.file.clone(), named.line));
                    if forbidden(named) {
                        if reported.insert(module.clone()) {
                            found.push((step, named.clone()));
                        }
                        continue;
                    }
                    if !named.internal {
                        continue;
                    }
                    if let Some(next) = self.module_of(&named.path)
                        && seen.insert(next.clone())
                    {
                        queue.push_back((next, step));
                    }
                }
            }
        }
        found
    }
}

fn read_file(file: &Path, module: ModulePath, into: &mut BTreeMap<ModulePath, Module>) {
    let text = std::fs::read_to_string(file)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
    let ast =
        syn::parse_file(&text).unwrap_or_else(|e| panic!("{} does not parse: {e}", file.display()));
    // `mod x;` in `a/lib.rs`, `a/mod.rs` or `a/main.rs` is `a/x.rs`; in `a/b.rs` it is `a/b/x.rs`.
    let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    let dir = file.parent().unwrap_or(Path::new("."));
    let children_dir =
        if matches!(stem, "lib" | "mod" | "main") { dir.to_path_buf() } else { dir.join(stem) };
    read_items(&ast.items, file, &children_dir, module, into);
}

fn read_items(
    items: &[syn::Item],
    file: &Path,
    children_dir: &Path,
    module: ModulePath,
    into: &mut BTreeMap<ModulePath, Module>,
) {
    let declared: BTreeSet<String> = items
        .iter()
        .filter_map(|item| match item {
            syn::Item::Mod(m) if !test_only(&m.attrs) => Some(m.ident.to_string()),
            _ => None,
        })
        .collect();
    let mut names = Names {
        module: &module,
        declared: &declared,
        imported: BTreeMap::new(),
        found: Vec::new(),
    };
    let shipped = || items.iter().filter(|item| !test_only(item_attrs(item)));
    for item in shipped() {
        if let syn::Item::Use(item) = item {
            names.import(item);
        }
    }
    for item in shipped() {
        match item {
            syn::Item::Mod(m) => {
                let mut child = module.clone();
                child.push(m.ident.to_string());
                match &m.content {
                    Some((_, inline)) => read_items(
                        inline,
                        file,
                        &children_dir.join(m.ident.to_string()),
                        child,
                        into,
                    ),
                    None => {
                        let name = m.ident.to_string();
                        let flat = children_dir.join(format!("{name}.rs"));
                        let nested = children_dir.join(&name).join("mod.rs");
                        read_file(if flat.exists() { &flat } else { &nested }, child, into);
                    }
                }
            }
            other => names.visit_item(other),
        }
    }
    let named = names.found;
    into.entry(module)
        .or_insert(Module { file: file.to_path_buf(), named: Vec::new() })
        .named
        .extend(named);
}

/// Whether `attrs` hold `#[cfg(test)]`.
fn test_only(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|attr| {
        attr.path().is_ident("cfg")
            && attr.parse_args::<syn::Ident>().is_ok_and(|ident| ident == "test")
    })
}

fn item_attrs(item: &syn::Item) -> &[syn::Attribute] {
    match item {
        syn::Item::Const(i) => &i.attrs,
        syn::Item::Enum(i) => &i.attrs,
        syn::Item::Fn(i) => &i.attrs,
        syn::Item::Impl(i) => &i.attrs,
        syn::Item::Macro(i) => &i.attrs,
        syn::Item::Mod(i) => &i.attrs,
        syn::Item::Static(i) => &i.attrs,
        syn::Item::Struct(i) => &i.attrs,
        syn::Item::Trait(i) => &i.attrs,
        syn::Item::Type(i) => &i.attrs,
        syn::Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

/// Collects the paths one module's items name.
struct Names<'a> {
    module: &'a ModulePath,
    declared: &'a BTreeSet<String>,
    /// What each name a `use` brings into this module stands for, resolved.
    imported: BTreeMap<String, (Vec<String>, bool)>,
    found: Vec<Named>,
}

impl Names<'_> {
    /// Resolves `segments` as written in this module: `crate::`, `super::` and `self::` paths,
    /// paths that start with a child module, and paths that start with a name a `use` brought
    /// in become crate-relative when they lead into the crate.
    fn resolve(&self, segments: &[String]) -> (Vec<String>, bool) {
        let Some(first) = segments.first() else { return (Vec::new(), false) };
        match first.as_str() {
            "crate" => (segments[1..].to_vec(), true),
            "self" => ([self.module.clone(), segments[1..].to_vec()].concat(), true),
            "super" => {
                let mut base = self.module.clone();
                let mut rest = segments;
                while rest.first().is_some_and(|s| s == "super") {
                    base.pop();
                    rest = &rest[1..];
                }
                ([base, rest.to_vec()].concat(), true)
            }
            name if self.declared.contains(name) => {
                ([self.module.clone(), segments.to_vec()].concat(), true)
            }
            name => match self.imported.get(name) {
                Some((path, internal)) => {
                    ([path.clone(), segments[1..].to_vec()].concat(), *internal)
                }
                None => (segments.to_vec(), false),
            },
        }
    }

    fn add(&mut self, segments: &[String], line: usize) {
        if segments.is_empty() {
            return;
        }
        let (path, internal) = self.resolve(segments);
        self.found.push(Named { path, internal, line });
    }

    /// Learns the names `item` brings into scope, before any path of the module is resolved.
    fn import(&mut self, item: &syn::ItemUse) {
        let mut paths = Vec::new();
        flatten(&item.tree, Vec::new(), &mut paths);
        for (path, alias) in paths {
            if let Some(alias) = alias {
                let resolved = self.resolve(&path);
                self.imported.insert(alias, resolved);
            }
        }
    }
}

impl<'ast> Visit<'ast> for Names<'_> {
    fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
        let mut paths = Vec::new();
        flatten(&item.tree, Vec::new(), &mut paths);
        for (path, _) in paths {
            self.add(&path, item.span().start().line);
        }
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        self.add(&segments, path.span().start().line);
        syn::visit::visit_path(self, path);
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        if !test_only(&f.attrs) {
            syn::visit::visit_impl_item_fn(self, f);
        }
    }
}

/// Every full path a `use` tree names, with the name it goes by here: `use a::{b, c::d as e}`
/// is `a::b` as `b` and `a::c::d` as `e`; a glob brings no one name.
fn flatten(
    tree: &syn::UseTree,
    prefix: Vec<String>,
    into: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let with = |name: &syn::Ident| [prefix.clone(), vec![name.to_string()]].concat();
    match tree {
        syn::UseTree::Path(p) => flatten(&p.tree, with(&p.ident), into),
        syn::UseTree::Name(n) if n.ident == "self" => {
            let alias = prefix.last().cloned();
            into.push((prefix, alias));
        }
        syn::UseTree::Name(n) => into.push((with(&n.ident), Some(n.ident.to_string()))),
        syn::UseTree::Rename(r) => into.push((with(&r.ident), Some(r.rename.to_string()))),
        syn::UseTree::Glob(_) => into.push((prefix, None)),
        syn::UseTree::Group(g) => {
            for tree in &g.items {
                flatten(tree, prefix.clone(), into);
            }
        }
    }
}
