//! `multibody describe` and `multibody list`: the component library, from
//! the engine's registry.

use crate::exit::Failure;
use multibody::components::{lookup, registry, ComponentSpec, Shape};

pub fn list() -> Result<(), Failure> {
    let written = multibody_dyad::catalog::components();
    let width = registry().iter().map(|s| s.kind.len()).chain(written.iter().map(|(n, _)| n.len())).max().unwrap_or(0);
    let mut out = String::new();
    for spec in registry() {
        put!(out, "{:width$}  {}", spec.kind, first_sentence(spec.doc));
    }
    for (name, doc) in &written {
        let doc = doc.split_whitespace().collect::<Vec<_>>().join(" ");
        put!(out, "{name:width$}  {} (written in Dyad)", first_sentence(&doc));
    }
    crate::console::answer(&out)
}

pub fn describe(kind: &str) -> Result<(), Failure> {
    let path = std::path::Path::new(kind);
    if lookup(kind).is_none() && (path.is_file() || path.extension().is_some_and(|e| e == "dyad" || e == "urdf")) {
        return Err(Failure::Usage(format!(
            "`describe` shows a library component kind; `multibody check {kind}` describes a model file (its \
             states, loops and free parts)"
        )));
    }
    if lookup(kind).is_none() {
        // A kind written in Dyad may be named without its library when only one library has it.
        let suffix = format!(".{kind}");
        let mut in_libraries: Vec<String> = multibody_dyad::catalog::components()
            .into_iter()
            .map(|(n, _)| n)
            .filter(|n| n.ends_with(&suffix))
            .collect();
        let full = if in_libraries.len() == 1 { in_libraries.pop().unwrap() } else { kind.to_string() };
        if let Some(d) = multibody_dyad::catalog::describe(&full) {
            return crate::console::answer(&written_description(&d));
        }
    }
    let Some(spec) = lookup(kind) else {
        let canonical = multibody::components::canonical_kind(kind);
        let written: Vec<String> = multibody_dyad::catalog::components().into_iter().map(|(n, _)| n).collect();
        let close =
            multibody::closest(&canonical, registry().iter().map(|s| s.kind).chain(written.iter().map(String::as_str)));
        let hint = if close.is_empty() {
            "`multibody list` shows every kind".to_string()
        } else {
            format!("did you mean {}?", close.join(", "))
        };
        return Err(Failure::Usage(format!("there is no component kind `{kind}`; {hint}")));
    };
    crate::console::answer(&description(spec))
}

fn description(spec: &ComponentSpec) -> String {
    let mut out = format!("{}\n\n{}", spec.kind, wrap(spec.doc, 100, ""));
    let params = spec
        .params
        .iter()
        .map(|p| vec![p.name.to_string(), format!("= {}", p.default), unit(p.unit), p.doc.to_string()])
        .collect();
    table(&mut out, "Parameters (name, default, unit, description)", params);
    let connectors = spec
        .public_connectors()
        .map(|c| vec![c.name.to_string(), c.ty.name().to_string(), c.doc.to_string()])
        .collect();
    table(&mut out, "Connectors (name, type, description)", connectors);
    let variables = spec
        .variables
        .iter()
        .map(|v| {
            let shape = match v.shape {
                Shape::Scalar => String::new(),
                Shape::Vector(n) => format!("[{n}]"),
                Shape::Matrix(r, c) => format!("[{r}, {c}]"),
            };
            // A variable without a name is the component's own value (an Input's).
            let name = if v.name.is_empty() { "(its name)" } else { v.name };
            vec![format!("{name}{shape}"), unit(v.unit), v.doc.to_string()]
        })
        .collect();
    table(&mut out, "Variables (name, unit, description)", variables);
    out
}

/// A component written in Dyad: its parameters with their defaults as
/// written, its connectors, the parts it is made of, and its variables.
fn written_description(d: &multibody_dyad::catalog::Description) -> String {
    let doc = d.doc.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut out = format!("{} (written in Dyad)\n\n{}", d.name, wrap(&doc, 100, ""));
    let params = d
        .parameters
        .iter()
        .map(|[name, default, ty, doc]| {
            let default = if default.is_empty() { "(required)".to_string() } else { default.clone() };
            vec![name.clone(), format!("= {default}"), ty.clone(), doc.clone()]
        })
        .collect();
    table(&mut out, "Parameters (name, default, type, description)", params);
    let connectors = d.connectors.iter().map(|[n, t]| vec![n.clone(), t.clone()]).collect();
    table(&mut out, "Connectors (name, type)", connectors);
    if !d.parts.is_empty() {
        let parts = d.parts.iter().map(|[n, k]| vec![n.clone(), k.clone()]).collect();
        table(&mut out, "Made of (name, component)", parts);
    }
    let variables = d.variables.iter().map(|[n, t]| vec![n.clone(), t.clone()]).collect();
    table(&mut out, "Variables (name, type)", variables);
    out
}

/// Aligned columns; the last one (a description) is left ragged.
fn table(out: &mut String, title: &str, rows: Vec<Vec<String>>) {
    if rows.is_empty() {
        out.push_str(&format!("\n{title}: none\n"));
        return;
    }
    out.push_str(&format!("\n{title}:\n"));
    let columns = rows[0].len();
    let widths: Vec<usize> =
        (0..columns).map(|i| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0)).collect();
    for row in rows {
        let mut line = String::from(" ");
        for (i, cell) in row.iter().enumerate() {
            let width = if i + 1 == columns { 0 } else { widths[i] };
            line.push_str(&format!(" {cell:width$} "));
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
}

fn unit(u: &str) -> String {
    if u.is_empty() {
        "-".into()
    } else {
        u.to_string()
    }
}

/// The doc up to the end of its first sentence.
fn first_sentence(doc: &str) -> &str {
    let bytes = doc.as_bytes();
    for (i, _) in doc.match_indices(". ") {
        let next = bytes.get(i + 2).copied().unwrap_or(b'A');
        let before = &doc[..i];
        let abbreviation = before.ends_with("e.g") || before.ends_with("i.e") || before.ends_with("resp");
        if next.is_ascii_uppercase() && !abbreviation {
            return &doc[..=i];
        }
    }
    doc
}

fn wrap(text: &str, width: usize, indent: &str) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            out.push_str(&format!("{indent}{line}\n"));
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        out.push_str(&format!("{indent}{line}\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::first_sentence;

    #[test]
    fn first_sentences_skip_abbreviations() {
        assert_eq!(first_sentence("A body. With mass."), "A body.");
        assert_eq!(first_sentence("Springs, e.g. This one. Next."), "Springs, e.g. This one.");
        assert_eq!(first_sentence("No stop"), "No stop");
    }
}
