//! The library's import structure, checked (a test only): its source files use one another
//! without a circle, and its top-level modules use only those below them in [`LAYERS`].
//!
//! The analysis reads `src/` (not the binary's `main.rs` and `cli/`) at `CARGO_MANIFEST_DIR`,
//! without comments and literals, and follows every path that names an item of this crate: `use`
//! trees (`crate::`, `super::`, `self::` and a child module's name), paths written in the code
//! (`crate::a::b`, `super::x`) and the names a `use` brings in where the code uses them
//! (`use super::geometry;` … `geometry::f`; `pub use model::Configuration;` … `Configuration`).
//! A path leads to the file that defines its item: through the `pub use` re-exports of a module
//! (explicit or glob) to the file behind them, so that importing a type from `contact` where
//! `contact/mod.rs` re-exports it from `contact/model.rs` is a use of `model.rs`. A module's
//! `pub use` of its own descendants is its table of contents, not a use. Inline modules
//! (`mod tests { … }`, test code included) belong to their file. Not seen: what macros expand to,
//! and a glob import (`use super::*`) counts as a use of the module's own file.
//!
//! `cargo test --release --lib layering` runs it and names every circle and every arrow up
//! (`LAYERING_EDGES=1 cargo test --release --lib layering -- --nocapture` prints every use found).

/// The library's top-level modules from the highest to the lowest (a line: modules on one level,
/// which use neither one another nor anything above them). `""` is the crate root (`lib.rs`:
/// `SCHEMA_VERSION`). The binary (`cli`) stands above them all.
const LAYERS: &[&[&str]] = &[
    &["bench"],
    &["inspect"],
    &["paper", "api"],
    &["compare", "study"],
    &["scenario"],
    &["dynamics"],
    &["contact"],
    &["profile"],
    &["track"],
    &["vehicle", "spline", "interpolation", "limits", "files"],
    &[""],
];

#[cfg(test)]
mod tests {
    use super::LAYERS;
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::{Path, PathBuf};

    #[derive(Debug, Clone, PartialEq)]
    enum Tok {
        Ident(String),
        Colons,
        Open,
        Close,
        Semi,
        Comma,
        Star,
        Other(char),
    }

    /// The tokens of a Rust source that matter for paths: identifiers and path punctuation;
    /// comments, strings and character literals are dropped, lifetimes read as `'` + identifier.
    fn tokens(src: &str) -> Vec<Tok> {
        let c: Vec<char> = src.chars().collect();
        let n = c.len();
        let mut out = Vec::new();
        let mut i = 0;
        // Skips a quoted string starting at the quote `c[i]`; returns the index after it.
        let skip_string = |mut i: usize| -> usize {
            i += 1;
            while i < n && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i + 1
        };
        while i < n {
            let ch = c[i];
            if ch == '/' && i + 1 < n && c[i + 1] == '/' {
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
                        i += 1;
                    }
                }
            } else if ch == '"' {
                i = skip_string(i);
            } else if ch == '\'' {
                if i + 2 < n && c[i + 1] == '\\' {
                    i += 2;
                    while i < n && c[i] != '\'' {
                        i += 1;
                    }
                    i += 1;
                } else if i + 2 < n && c[i + 2] == '\'' {
                    i += 3;
                } else {
                    out.push(Tok::Other('\''));
                    i += 1;
                }
            } else if ch.is_alphanumeric() || ch == '_' {
                let start = i;
                while i < n && (c[i].is_alphanumeric() || c[i] == '_') {
                    i += 1;
                }
                let word: String = c[start..i].iter().collect();
                let raw = matches!(word.as_str(), "r" | "br" | "cr");
                if raw && i < n && (c[i] == '#' || c[i] == '"') {
                    let mut hashes = 0;
                    while i < n && c[i] == '#' {
                        hashes += 1;
                        i += 1;
                    }
                    if i < n && c[i] == '"' {
                        i += 1;
                        'raw: while i < n {
                            if c[i] == '"' && (0..hashes).all(|k| c.get(i + 1 + k) == Some(&'#')) {
                                i += 1 + hashes;
                                break 'raw;
                            }
                            i += 1;
                        }
                    } else {
                        out.push(Tok::Ident(word)); // `r#ident`
                    }
                } else if matches!(word.as_str(), "b" | "c") && i < n && c[i] == '"' {
                    i = skip_string(i);
                } else if word == "b" && i < n && c[i] == '\'' {
                    i += 1;
                    while i < n && c[i] != '\'' {
                        if c[i] == '\\' {
                            i += 1;
                        }
                        i += 1;
                    }
                    i += 1;
                } else if !word.starts_with(|d: char| d.is_ascii_digit()) {
                    out.push(Tok::Ident(word));
                }
            } else if ch == ':' && i + 1 < n && c[i + 1] == ':' {
                out.push(Tok::Colons);
                i += 2;
            } else {
                match ch {
                    '{' => out.push(Tok::Open),
                    '}' => out.push(Tok::Close),
                    ';' => out.push(Tok::Semi),
                    ',' => out.push(Tok::Comma),
                    '*' => out.push(Tok::Star),
                    w if w.is_whitespace() => {}
                    o => out.push(Tok::Other(o)),
                }
                i += 1;
            }
        }
        out
    }

    /// One leaf of a `use` tree: its path as written, its local name, whether it is a glob.
    #[derive(Debug, Clone)]
    struct UseLeaf {
        path: Vec<String>,
        alias: Option<String>,
        glob: bool,
    }

    fn ident(t: Option<&Tok>) -> Option<&str> {
        match t {
            Some(Tok::Ident(s)) => Some(s),
            _ => None,
        }
    }

    /// Parses a use tree at `toks[*i]` under `prefix` into `out`.
    fn use_tree(toks: &[Tok], i: &mut usize, prefix: &[String], out: &mut Vec<UseLeaf>) {
        let mut path = prefix.to_vec();
        if toks.get(*i) == Some(&Tok::Colons) {
            *i += 1;
        }
        loop {
            match toks.get(*i) {
                Some(Tok::Ident(s)) => {
                    path.push(s.clone());
                    *i += 1;
                    if toks.get(*i) == Some(&Tok::Colons) {
                        *i += 1;
                        continue;
                    }
                    let mut alias = None;
                    if ident(toks.get(*i)) == Some("as") {
                        alias = ident(toks.get(*i + 1)).map(str::to_string);
                        *i += 2;
                    }
                    out.push(UseLeaf {
                        path,
                        alias,
                        glob: false,
                    });
                    return;
                }
                Some(Tok::Star) => {
                    *i += 1;
                    out.push(UseLeaf {
                        path,
                        alias: None,
                        glob: true,
                    });
                    return;
                }
                Some(Tok::Open) => {
                    *i += 1;
                    while *i < toks.len() && toks[*i] != Tok::Close {
                        use_tree(toks, i, &path, out);
                        if toks.get(*i) == Some(&Tok::Comma) {
                            *i += 1;
                        }
                    }
                    *i += 1;
                    return;
                }
                _ => return,
            }
        }
    }

    /// A `use` found in a file: the module (path from the crate root) it stands in.
    #[derive(Debug, Clone)]
    struct Use {
        scope: Vec<String>,
        leaf: UseLeaf,
        public: bool,
    }

    /// A path written in the code, with the module it stands in.
    #[derive(Debug, Clone)]
    struct Written {
        scope: Vec<String>,
        path: Vec<String>,
    }

    #[derive(Debug, Default)]
    struct File {
        uses: Vec<Use>,
        written: Vec<Written>,
        /// Inline modules (path from the crate root) and the names defined in each module.
        defs: BTreeMap<Vec<String>, BTreeSet<String>>,
    }

    const KEYWORDS: &[&str] = &[
        "fn", "struct", "enum", "trait", "type", "const", "static", "union", "mod",
    ];

    fn read_file(module: &[String], src: &str) -> File {
        let toks = tokens(src);
        let mut file = File::default();
        file.defs.entry(module.to_vec()).or_default();
        // The braces open: for each, the inline module it opens, if any.
        let mut braces: Vec<Option<String>> = Vec::new();
        let scope = |braces: &[Option<String>]| -> Vec<String> {
            let mut s = module.to_vec();
            s.extend(braces.iter().flatten().cloned());
            s
        };
        let mut i = 0;
        while i < toks.len() {
            match &toks[i] {
                Tok::Open => {
                    let inline = match (
                        i.checked_sub(2).map(|k| &toks[k]),
                        i.checked_sub(1).map(|k| &toks[k]),
                    ) {
                        (Some(Tok::Ident(m)), Some(Tok::Ident(name))) if m == "mod" => Some(name.clone()),
                        _ => None,
                    };
                    braces.push(inline);
                    file.defs.entry(scope(&braces)).or_default();
                    i += 1;
                }
                Tok::Close => {
                    braces.pop();
                    i += 1;
                }
                Tok::Ident(w) if w == "use" => {
                    let public = ident(i.checked_sub(1).map(|k| &toks[k])) == Some("pub")
                        || (i >= 4
                            && ident(Some(&toks[i - 4])) == Some("pub")
                            && toks[i - 3] == Tok::Other('('));
                    let mut leaves = Vec::new();
                    i += 1;
                    use_tree(&toks, &mut i, &[], &mut leaves);
                    while i < toks.len() && toks[i] != Tok::Semi {
                        i += 1;
                    }
                    let s = scope(&braces);
                    for leaf in leaves {
                        file.uses.push(Use {
                            scope: s.clone(),
                            leaf,
                            public,
                        });
                    }
                }
                Tok::Ident(w) if KEYWORDS.contains(&w.as_str()) => {
                    if let Some(name) = ident(toks.get(i + 1)) {
                        file.defs
                            .entry(scope(&braces))
                            .or_default()
                            .insert(name.to_string());
                    }
                    i += 1;
                }
                Tok::Ident(w) if i == 0 || toks[i - 1] != Tok::Colons => {
                    // A path's start: `crate::`, `super::`, `self::`, or a name (an imported
                    // module or item, resolved later) alone or followed by `::` — not a field
                    // or a method (`.name`, `name:`).
                    let mut path = vec![w.clone()];
                    let mut k = i + 1;
                    while toks.get(k) == Some(&Tok::Colons) {
                        match ident(toks.get(k + 1)) {
                            Some(s) => path.push(s.to_string()),
                            None => break,
                        }
                        k += 2;
                    }
                    let member = (i > 0 && toks[i - 1] == Tok::Other('.'))
                        || (path.len() == 1 && toks.get(i + 1) == Some(&Tok::Other(':')));
                    if !member {
                        file.written.push(Written {
                            scope: scope(&braces),
                            path,
                        });
                    }
                    i = k.max(i + 1);
                }
                _ => i += 1,
            }
        }
        file
    }

    /// The module path of a source file (`src/a/b.rs`, `src/a/b/mod.rs` → `a::b`).
    fn module_of(rel: &Path) -> Vec<String> {
        let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
        let last = parts.pop().unwrap_or_default();
        let stem = last.trim_end_matches(".rs");
        if stem != "mod" && stem != "lib" {
            parts.push(stem.to_string());
        }
        parts
    }

    fn sources(dir: &Path, root: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .expect("src/ is readable")
            .map(|e| e.expect("a directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            if rel == Path::new("main.rs") || rel.starts_with("cli") {
                continue;
            }
            if p.is_dir() {
                sources(&p, root, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(rel);
            }
        }
    }

    struct Crate {
        files: Vec<(String, File)>,
        /// Every module (file or inline) → the index of its file.
        modules: BTreeMap<Vec<String>, usize>,
    }

    impl Crate {
        /// The library's sources under `src/`.
        fn read() -> Crate {
            let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
            let mut rels = Vec::new();
            sources(&root, &root, &mut rels);
            Crate::of(rels.into_iter().map(|rel| {
                let src = std::fs::read_to_string(root.join(&rel)).expect("a source file");
                (rel.to_string_lossy().replace('\\', "/"), src)
            }))
        }

        /// The crate of these (path under `src/`, source) files.
        fn of(sources: impl IntoIterator<Item = (String, String)>) -> Crate {
            let mut files = Vec::new();
            let mut modules = BTreeMap::new();
            for (rel, src) in sources {
                let file = read_file(&module_of(Path::new(&rel)), &src);
                for m in file.defs.keys() {
                    modules.insert(m.clone(), files.len());
                }
                files.push((rel, file));
            }
            Crate { files, modules }
        }

        /// A path as written in module `scope`, from the crate root; `None` outside the crate.
        fn absolute(&self, scope: &[String], path: &[String]) -> Option<Vec<String>> {
            let mut m = scope.to_vec();
            let mut rest = path;
            match path.first()?.as_str() {
                "crate" => {
                    m.clear();
                    rest = &path[1..];
                }
                "self" => rest = &path[1..],
                "super" => {
                    while rest.first().map(String::as_str) == Some("super") {
                        m.pop();
                        rest = &rest[1..];
                    }
                }
                first => {
                    let mut child = m.clone();
                    child.push(first.to_string());
                    if !self.modules.contains_key(&child) {
                        return None;
                    }
                }
            }
            m.extend(rest.iter().filter(|s| *s != "self").cloned());
            Some(m)
        }

        /// The file that defines what an absolute path names (a module names its own file).
        fn resolve(&self, abs: &[String], depth: usize) -> Option<usize> {
            let len = (0..=abs.len())
                .rev()
                .find(|&k| self.modules.contains_key(&abs[..k]))?;
            let module = &abs[..len];
            let file = self.modules[module];
            let Some(name) = abs.get(len) else {
                return Some(file);
            };
            if depth > 16 {
                return Some(file);
            }
            let f = &self.files[file].1;
            let rest = &abs[len + 1..];
            let reexports = f.uses.iter().filter(|u| u.public && u.scope == module);
            for u in reexports.clone().filter(|u| !u.leaf.glob) {
                let local = u.leaf.alias.as_ref().or(u.leaf.path.last());
                if local == Some(name) {
                    if let Some(mut target) = self.absolute(&u.scope, &u.leaf.path) {
                        target.extend(rest.iter().cloned());
                        return self.resolve(&target, depth + 1).or(Some(file));
                    }
                }
            }
            if f.defs.get(module).is_some_and(|d| d.contains(name)) {
                return Some(file);
            }
            for u in reexports.filter(|u| u.leaf.glob) {
                if let Some(mut target) = self.absolute(&u.scope, &u.leaf.path) {
                    let len = target.len();
                    target.push(name.clone());
                    let defined = self.modules.get(&target[..len]).is_some_and(|&g| {
                        self.files[g]
                            .1
                            .defs
                            .get(&target[..len])
                            .is_some_and(|d| d.contains(name))
                    });
                    if defined {
                        target.extend(rest.iter().cloned());
                        return self.resolve(&target, depth + 1);
                    }
                }
            }
            Some(file)
        }

        /// The file → file uses.
        fn edges(&self) -> BTreeSet<(usize, usize)> {
            let mut edges = BTreeSet::new();
            for (from, (_, f)) in self.files.iter().enumerate() {
                // Names imported in this file (a module or an item) → their absolute paths.
                let mut aliases: BTreeMap<String, Vec<String>> = BTreeMap::new();
                for u in &f.uses {
                    let Some(abs) = self.absolute(&u.scope, &u.leaf.path) else {
                        continue;
                    };
                    if !u.leaf.glob {
                        let local = u
                            .leaf
                            .alias
                            .clone()
                            .or_else(|| u.leaf.path.iter().rev().find(|s| *s != "self").cloned());
                        if let Some(local) = local {
                            aliases.insert(local, abs.clone());
                        }
                    }
                    let names_module = self.modules.contains_key(&abs);
                    if names_module && !u.leaf.glob {
                        continue; // the uses through it are counted where they are written
                    }
                    let Some(to) = self.resolve(&abs, 0) else {
                        continue;
                    };
                    // A module's re-export of its own descendants is its table of contents.
                    let descendant = abs.len() > u.scope.len() && abs.starts_with(&u.scope);
                    if u.public && descendant {
                        continue;
                    }
                    edges.insert((from, to));
                }
                for w in &f.written {
                    let abs = match w.path[0].as_str() {
                        "crate" | "super" | "self" if w.path.len() > 1 => self.absolute(&w.scope, &w.path),
                        name => aliases.get(name).map(|a| {
                            let mut a = a.clone();
                            a.extend(w.path[1..].iter().cloned());
                            a
                        }),
                    };
                    if let Some(to) = abs.and_then(|a| self.resolve(&a, 0)) {
                        edges.insert((from, to));
                    }
                }
            }
            edges.retain(|(a, b)| a != b);
            edges
        }
    }

    /// The strongly connected components with more than one file (Tarjan).
    fn circles(n: usize, edges: &BTreeSet<(usize, usize)>) -> Vec<Vec<usize>> {
        struct T<'a> {
            adj: Vec<Vec<usize>>,
            index: Vec<Option<usize>>,
            low: Vec<usize>,
            on: Vec<bool>,
            stack: Vec<usize>,
            next: usize,
            out: &'a mut Vec<Vec<usize>>,
        }
        fn visit(t: &mut T, v: usize) {
            t.index[v] = Some(t.next);
            t.low[v] = t.next;
            t.next += 1;
            t.stack.push(v);
            t.on[v] = true;
            for w in t.adj[v].clone() {
                match t.index[w] {
                    None => {
                        visit(t, w);
                        t.low[v] = t.low[v].min(t.low[w]);
                    }
                    Some(iw) if t.on[w] => t.low[v] = t.low[v].min(iw),
                    _ => {}
                }
            }
            if Some(t.low[v]) == t.index[v] {
                let mut comp = Vec::new();
                while let Some(w) = t.stack.pop() {
                    t.on[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    t.out.push(comp);
                }
            }
        }
        let mut adj = vec![Vec::new(); n];
        for &(a, b) in edges {
            adj[a].push(b);
        }
        let mut out = Vec::new();
        let mut t = T {
            adj,
            index: vec![None; n],
            low: vec![0; n],
            on: vec![false; n],
            stack: Vec::new(),
            next: 0,
            out: &mut out,
        };
        for v in 0..n {
            if t.index[v].is_none() {
                visit(&mut t, v);
            }
        }
        out
    }

    fn top(path: &str) -> String {
        match path.split_once('/') {
            Some((dir, _)) => dir.to_string(),
            None if path == "lib.rs" => String::new(),
            None => path.trim_end_matches(".rs").to_string(),
        }
    }

    #[test]
    fn the_tokens_skip_comments_and_literals() {
        let t = tokens("use a::b; // crate::x\n let s = \"crate::y\"; let c = '\"'; r#\"crate::z\"#");
        let words: Vec<_> = t.iter().filter_map(|t| ident(Some(t))).collect();
        assert_eq!(words, ["use", "a", "b", "let", "s", "let", "c"]);
    }

    /// The circles and the arrows up or across between top-level modules, in words.
    fn problems(krate: &Crate, layers: &[&[&str]]) -> Vec<String> {
        let edges = krate.edges();
        let name = |i: usize| krate.files[i].0.clone();
        if std::env::var_os("LAYERING_EDGES").is_some() {
            for &(a, b) in &edges {
                eprintln!("{} → {}", name(a), name(b));
            }
        }
        let mut problems = Vec::new();
        for comp in circles(krate.files.len(), &edges) {
            let files: Vec<String> = comp.iter().map(|&i| name(i)).collect();
            let inner: Vec<String> = edges
                .iter()
                .filter(|(a, b)| comp.contains(a) && comp.contains(b))
                .map(|&(a, b)| format!("{} → {}", name(a), name(b)))
                .collect();
            problems.push(format!(
                "circle: {}\n    {}",
                files.join(", "),
                inner.join("\n    ")
            ));
        }
        let level = |m: &str| layers.iter().position(|l| l.contains(&m));
        for &(a, b) in &edges {
            let (ma, mb) = (top(&name(a)), top(&name(b)));
            let (Some(la), Some(lb)) = (level(&ma), level(&mb)) else {
                problems.push(format!("not in LAYERS: {} → {}", name(a), name(b)));
                continue;
            };
            if ma != mb && lb <= la {
                problems.push(format!("arrow up or across: {} → {}", name(a), name(b)));
            }
        }
        problems
    }

    #[test]
    fn the_library_has_no_circle_and_no_arrow_up() {
        let krate = Crate::read();
        assert!(
            krate.edges().len() > 100,
            "the analysis found only {} uses",
            krate.edges().len()
        );
        let problems = problems(&krate, LAYERS);
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }

    /// The analysis on a made-up crate: a circle through a re-export, an arrow up, an inline
    /// module's `use super::*`, and a module's table of contents (not a use).
    #[test]
    fn the_analysis_finds_circles_and_arrows_up() {
        let files = |v: &[(&str, &str)]| Crate::of(v.iter().map(|(p, s)| (p.to_string(), s.to_string())));
        let layers: &[&[&str]] = &[&["high"], &["low"], &[""]];
        let sources = [
            ("lib.rs", "pub mod high; pub mod low;"),
            (
                "low/mod.rs",
                "pub mod a; pub mod b; pub use a::A; pub use b::B; // crate::high::H",
            ),
            ("low/a.rs", "use super::B; pub struct A(B);"),
            (
                "low/b.rs",
                "pub struct B; fn f() { let _ = crate::low::A::new; } \
                 #[cfg(test)] mod tests { use super::*; }",
            ),
            (
                "high.rs",
                "use crate::low::{self, A}; pub struct H; fn g() { low::b::B; }",
            ),
        ];
        let found = problems(&files(&sources), layers);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].starts_with("circle: low/a.rs, low/b.rs"), "{found:?}");
        let mut up = sources;
        up[2].1 = "pub struct A(crate::high::H);";
        // (high.rs uses a.rs: the arrow up closes a circle too.)
        let found = problems(&files(&up), layers);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(
            found[0].starts_with("circle: low/a.rs, low/b.rs, high.rs"),
            "{found:?}"
        );
        assert_eq!(found[1], "arrow up or across: low/a.rs → high.rs");
    }
}
