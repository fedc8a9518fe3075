//! Holds the engine's module layering: a top-level module of
//! `crates/multibody/src` may use its own layer or lower ones, never a
//! higher one. The scan is textual (std only), so the bottom of this file
//! checks the scanner itself on small sources.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

/// The top-level modules and their layers, from the bottom. `lib.rs` holds
/// re-exports only and is exempt.
const LAYERS: &[(&str, usize)] = &[
    ("math", 0),
    ("files", 0),
    ("error", 1),
    ("model", 1),
    ("system", 2),
    ("dynamics", 3),
    ("components", 4),
    ("assembly", 5),
    ("outputs", 6),
    ("simulate", 7),
    ("linear", 8),
];

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().find(|(name, _)| *name == module).map(|&(_, layer)| layer)
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// If `c[i]` opens a raw string (`r"`, `r#"`, `br#"`, `cr"`…), the number
/// of `#`s it uses.
fn raw_string_start(c: &[char], i: usize) -> Option<usize> {
    let word_start = |k: usize| k == 0 || !is_ident(c[k - 1]);
    let prefixed = i >= 1 && matches!(c[i - 1], 'b' | 'c') && word_start(i - 1);
    if c[i] != 'r' || !(word_start(i) || prefixed) {
        return None;
    }
    let hashes = c[i + 1..].iter().take_while(|&&ch| ch == '#').count();
    (c.get(i + 1 + hashes) == Some(&'"')).then_some(hashes)
}

/// Blanks comments (doc comments too, and nested block comments) and the
/// insides of string and char literals, keeping newlines so that line
/// numbers still match the source.
fn strip(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < c.len() {
        if at(i) == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if at(i) == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if at(i) == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if at(i) == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
        } else if let Some(hashes) = raw_string_start(&c, i) {
            i += hashes + 2;
            while i < c.len() {
                if c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#') {
                    i += hashes + 1;
                    break;
                }
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '"' || (c[i] == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'')) {
            // A string or a char literal; a lone `'` is a lifetime or label.
            let quote = c[i];
            i += 1;
            while i < c.len() && c[i] != quote {
                if c[i] == '\\' {
                    blank(&mut out, c[i]);
                    i += 1;
                }
                if i < c.len() {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
            i += 1;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

struct Tok {
    text: String,
    line: usize,
}

/// Splits stripped code into identifiers (numbers land here too, harmlessly),
/// `::` and single punctuation characters.
fn tokens(code: &str) -> Vec<Tok> {
    let c: Vec<char> = code.chars().collect();
    let mut toks = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if is_ident(ch) {
            let mut start = i;
            while i < c.len() && is_ident(c[i]) {
                i += 1;
            }
            // A raw identifier `r#name` is just `name`.
            if i == start + 1 && ch == 'r' && c.get(i) == Some(&'#') && c.get(i + 1).is_some_and(|&n| is_ident(n)) {
                i += 1;
                start = i;
                while i < c.len() && is_ident(c[i]) {
                    i += 1;
                }
            }
            toks.push(Tok { text: c[start..i].iter().collect(), line });
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            toks.push(Tok { text: "::".into(), line });
            i += 2;
        } else {
            toks.push(Tok { text: ch.into(), line });
            i += 1;
        }
    }
    toks
}

/// One path of a use tree: each segment with its line, and any `as` name.
#[derive(Clone, Default)]
struct Leaf {
    segs: Vec<(String, usize)>,
    alias: Option<String>,
}

/// Parses the path tree at `toks[i]` (`a::b`, `a::{b, c::{d, e}}`, `*`,
/// `a as b`) after `prefix`, adding its leaves; returns the index after it.
fn parse_tree(toks: &[Tok], mut i: usize, prefix: &Leaf, leaves: &mut Vec<Leaf>) -> usize {
    let Some(tok) = toks.get(i) else { return i };
    if tok.text == "{" {
        i += 1;
        while let Some(t) = toks.get(i) {
            match t.text.as_str() {
                "}" => return i + 1,
                "," => i += 1,
                _ => {
                    let next = parse_tree(toks, i, prefix, leaves);
                    if next == i {
                        return i; // not a tree: give up rather than loop
                    }
                    i = next;
                }
            }
        }
        return i;
    }
    if tok.text != "*" && !tok.text.starts_with(|c: char| c.is_alphabetic() || c == '_') {
        return i;
    }
    let mut leaf = prefix.clone();
    leaf.segs.push((tok.text.clone(), tok.line));
    i += 1;
    if toks.get(i).is_some_and(|t| t.text == "::") {
        return parse_tree(toks, i + 1, &leaf, leaves);
    }
    if toks.get(i).is_some_and(|t| t.text == "as") {
        leaf.alias = toks.get(i + 1).map(|t| t.text.clone());
        i += 2;
    }
    leaves.push(leaf);
    i
}

/// The module path of a file under `src`: `assembly/links.rs` is
/// `[assembly, links]`, `assembly/mod.rs` is `[assembly]`, `lib.rs` is `[]`.
fn module_path(rel: &str) -> Vec<&str> {
    let mut parts: Vec<&str> = rel.split('/').collect();
    let stem = parts.pop().unwrap_or_default().trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem);
    }
    parts
}

/// Every name a file reaches at the crate root, with its line: the first
/// segment after `crate::` or `$crate::` (each branch of a grouped use),
/// or after a `super::` chain that climbs to the root.
fn root_refs(rel: &str, src: &str) -> Vec<(usize, String)> {
    let toks = tokens(&strip(src));
    let is_sep = |k: usize| toks.get(k).is_some_and(|t| t.text == "::");
    let file_depth = module_path(rel).len();
    // Brace depths at which inline `mod x {` blocks opened: each adds a level
    // that `super` must climb.
    let mut inline_mods: Vec<usize> = Vec::new();
    let mut braces = 0;
    let mut refs: Vec<(usize, String)> = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        let mut root_at = None;
        match toks[i].text.as_str() {
            "{" => braces += 1,
            "}" => {
                braces = usize::max(braces, 1) - 1;
                if inline_mods.last() == Some(&braces) {
                    inline_mods.pop();
                }
            }
            "mod" if toks.get(i + 2).is_some_and(|t| t.text == "{") => inline_mods.push(braces),
            "crate" if is_sep(i + 1) => root_at = Some(i + 2),
            "super" if !(i > 0 && is_sep(i - 1)) => {
                let mut j = i;
                while toks.get(j).is_some_and(|t| t.text == "super") && is_sep(j + 1) {
                    j += 2;
                }
                if (j - i) / 2 >= file_depth + inline_mods.len() {
                    root_at = Some(j);
                }
            }
            _ => {}
        }
        match root_at {
            Some(start) => {
                let mut leaves = Vec::new();
                let next = parse_tree(&toks, start, &Leaf::default(), &mut leaves);
                for leaf in leaves {
                    let (name, line) = leaf.segs[0].clone();
                    if name != "self" && !refs.contains(&(line, name.clone())) {
                        refs.push((line, name));
                    }
                }
                i = next.max(i + 1);
            }
            None => i += 1,
        }
    }
    refs
}

/// The items `lib.rs` brings into the crate root with `use`, mapped to the
/// top-level module each comes from (`Mechanism` -> `assembly`).
fn parse_exports(lib: &str) -> HashMap<String, String> {
    let toks = tokens(&strip(lib));
    let mut exports = HashMap::new();
    for (i, tok) in toks.iter().enumerate() {
        if tok.text != "use" {
            continue;
        }
        let mut leaves = Vec::new();
        parse_tree(&toks, i + 1, &Leaf::default(), &mut leaves);
        for leaf in leaves {
            let mut segs: Vec<&str> = leaf.segs.iter().map(|(s, _)| s.as_str()).collect();
            if matches!(segs.first(), Some(&"crate" | &"self")) {
                segs.remove(0);
            }
            let name = leaf.alias.as_deref().or(segs.last().copied()).unwrap_or("self");
            if segs.len() >= 2 && !matches!(name, "self" | "*" | "_") {
                exports.insert(name.to_string(), segs[0].to_string());
            }
        }
    }
    exports
}

/// The layering problems of one file, as `file:line: module -> target
/// (layer a -> layer b)` lines.
fn check_file(rel: &str, src: &str, exports: &HashMap<String, String>) -> Vec<String> {
    let module = module_path(rel).first().copied().unwrap_or("lib");
    let Some(from) = layer(module) else {
        return vec![format!("{rel}: module `{module}` has no layer: add it to LAYERS in tests/layers.rs")];
    };
    let mut problems = Vec::new();
    for (line, name) in root_refs(rel, src) {
        let (target, via) = match exports.get(&name) {
            Some(target) if layer(&name).is_none() => (target.as_str(), format!(" via crate::{name}")),
            _ => (name.as_str(), String::new()),
        };
        match layer(target) {
            Some(to) if to > from => {
                problems.push(format!("{rel}:{line}: {module} -> {target} (layer {from} -> layer {to}){via}"))
            }
            Some(_) => {}
            None => problems.push(format!(
                "{rel}:{line}: {module} -> unknown `crate::{name}`{via}: not a module in LAYERS (tests/layers.rs) \
                 nor an item lib.rs re-exports from one"
            )),
        }
    }
    problems
}

fn rs_files(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap_or_else(|e| panic!("reading {}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rs_files(&path, files);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            files.push(path);
        }
    }
}

#[test]
fn modules_import_only_from_their_own_or_lower_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let exports = parse_exports(&fs::read_to_string(src.join("lib.rs")).unwrap());
    assert!(!exports.is_empty(), "found no re-exports in src/lib.rs: the scanner no longer understands it");
    let mut files = Vec::new();
    rs_files(&src, &mut files);
    files.sort();
    let (mut problems, mut seen) = (Vec::new(), 0);
    for path in &files {
        let rel: Vec<String> = path
            .strip_prefix(&src)
            .unwrap()
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        let rel = rel.join("/");
        if rel == "lib.rs" {
            continue;
        }
        let text = fs::read_to_string(path).unwrap();
        seen += root_refs(&rel, &text).len();
        problems.extend(check_file(&rel, &text, &exports));
    }
    // A scanner that finds nothing would pass vacuously.
    assert!(seen > 0, "found no `crate::` paths in {} files: the scanner is broken", files.len());
    assert!(
        problems.is_empty(),
        "{} import(s) in crates/multibody/src break the layering {LAYERS:?}:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// The scanner on small sources, so that the test above can fail.
mod scanner {
    use super::*;

    const LIB: &str = "pub mod assembly;\n\
        pub use assembly::{LoopInfo, Mechanism};\n\
        pub use error::{closest, Error};\n\
        pub use simulate::Solution as Run;\n";

    fn check(rel: &str, src: &str) -> Vec<String> {
        check_file(rel, src, &parse_exports(LIB))
    }

    #[test]
    fn reads_the_re_exports_of_lib_rs() {
        let exports = parse_exports(LIB);
        assert_eq!(exports.get("Mechanism").map(String::as_str), Some("assembly"));
        assert_eq!(exports.get("closest").map(String::as_str), Some("error"));
        assert_eq!(exports.get("Run").map(String::as_str), Some("simulate"));
        assert_eq!(exports.len(), 5);
    }

    #[test]
    fn reports_an_upward_use() {
        let src = "use crate::math::Vec3;\nuse crate::assembly::Mechanism;\n";
        assert_eq!(check("dynamics/aba.rs", src), ["dynamics/aba.rs:2: dynamics -> assembly (layer 3 -> layer 5)"]);
    }

    #[test]
    fn ignores_comments_and_literals() {
        let src = r####"
            // use crate::assembly::Mechanism;
            /// See [`crate::assembly::Mechanism`].
            //! crate::simulate
            /* outer /* nested */ crate::assembly::Mechanism */
            const A: &str = "crate::assembly::Mechanism \" crate::outputs";
            const B: &str = r#"crate::assembly::Mechanism " crate::outputs"#;
            const C: char = '"';
            fn f<'a>(x: &'a str) -> &'a str { x }
            pub(crate) fn g() {}
        "####;
        assert_eq!(check("dynamics/aba.rs", src), Vec::<String>::new());
        // The char literal and lifetimes above must not hide real code after them.
        let late = format!("{src}\nuse crate::assembly::Mechanism;\n");
        assert_eq!(check("dynamics/aba.rs", &late), ["dynamics/aba.rs:12: dynamics -> assembly (layer 3 -> layer 5)"]);
    }

    #[test]
    fn parses_grouped_and_inline_paths() {
        let src = "use crate::{system::{A, B}, math::Vec3};\n\
                   use crate::{\n    Error,\n    outputs::{self, Out},\n};\n\
                   fn f() { let m = crate::Mechanism::new(); $crate::simulate::run(); }\n";
        let refs = root_refs("dynamics/aba.rs", src);
        let names: Vec<(usize, &str)> = refs.iter().map(|(l, n)| (*l, n.as_str())).collect();
        assert_eq!(
            names,
            [(1, "system"), (1, "math"), (3, "Error"), (4, "outputs"), (6, "Mechanism"), (6, "simulate")]
        );
        assert_eq!(
            check("dynamics/aba.rs", src),
            [
                "dynamics/aba.rs:4: dynamics -> outputs (layer 3 -> layer 6)",
                "dynamics/aba.rs:6: dynamics -> assembly (layer 3 -> layer 5) via crate::Mechanism",
                "dynamics/aba.rs:6: dynamics -> simulate (layer 3 -> layer 7)",
            ]
        );
    }

    #[test]
    fn follows_super_to_the_root() {
        // `super::` stays in assembly; `super::super::` from a leaf file or
        // `super::` from mod.rs reaches the root.
        assert_eq!(check("assembly/links.rs", "use super::outputs::X;\n"), Vec::<String>::new());
        assert_eq!(
            check("assembly/links.rs", "use super::super::outputs::X;\n"),
            ["assembly/links.rs:1: assembly -> outputs (layer 5 -> layer 6)"]
        );
        assert_eq!(check("assembly/mod.rs", "use super::{Run, math::Vec3};\n").len(), 1);
        assert_eq!(check("components/blocks/ramp.rs", "use super::super::Part;\n"), Vec::<String>::new());
        // Inside an inline `mod tests`, one more `super` is needed.
        let inline = "mod tests {\n    use super::super::simulate::X;\n}\nuse super::super::simulate::Y;\n";
        assert_eq!(
            check("assembly/links.rs", inline),
            ["assembly/links.rs:4: assembly -> simulate (layer 5 -> layer 7)"]
        );
    }

    #[test]
    fn reports_unknown_modules() {
        let problems = check("system/mod.rs", "use crate::nowhere::X;\n");
        assert_eq!(problems.len(), 1);
        assert!(problems[0].starts_with("system/mod.rs:1: system -> unknown `crate::nowhere`"), "{problems:?}");
        let problems = check("nowhere.rs", "use crate::math::Vec3;\n");
        assert!(problems[0].contains("module `nowhere` has no layer"), "{problems:?}");
    }
}
