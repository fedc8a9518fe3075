//! `multibody describe` and `multibody list`: the component library, from
//! the engine's registry.

use crate::exit::Failure;
use multibody::components::{lookup, registry, ComponentSpec};

pub fn list() -> Result<(), Failure> {
    let width = registry().iter().map(|s| s.kind.len()).max().unwrap_or(0);
    for spec in registry() {
        println!("{:width$}  {}", spec.kind, first_sentence(spec.doc));
    }
    Ok(())
}

pub fn describe(kind: &str) -> Result<(), Failure> {
    let Some(spec) = lookup(kind) else {
        let canonical = multibody::components::canonical_kind(kind);
        let close = multibody::closest(&canonical, registry().iter().map(|s| s.kind));
        let hint = if close.is_empty() {
            "`multibody list` shows every kind".to_string()
        } else {
            format!("did you mean {}?", close.join(", "))
        };
        return Err(Failure::Usage(format!("there is no component kind `{kind}`; {hint}")));
    };
    print!("{}", description(spec));
    Ok(())
}

fn description(spec: &ComponentSpec) -> String {
    let mut out = format!("{}\n\n{}", spec.kind, wrap(spec.doc, 100, ""));
    let mut table = |title: &str, rows: Vec<[String; 4]>| {
        if rows.is_empty() {
            out.push_str(&format!("\n{title}: none\n"));
            return;
        }
        out.push_str(&format!("\n{title}:\n"));
        let widths: Vec<usize> = (0..3).map(|i| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0)).collect();
        for r in rows {
            let line = format!(
                "  {:w0$}  {:w1$}  {:w2$}  {}",
                r[0],
                r[1],
                r[2],
                r[3],
                w0 = widths[0],
                w1 = widths[1],
                w2 = widths[2]
            );
            out.push_str(line.trim_end());
            out.push('\n');
        }
    };
    let params = spec
        .params
        .iter()
        .map(|p| [p.name.to_string(), format!("= {}", p.default), unit(p.unit), p.doc.to_string()])
        .collect();
    table("Parameters (name, default, unit, description)", params);
    let connectors = spec
        .connectors
        .iter()
        .map(|c| [c.name.to_string(), c.ty.name().to_string(), String::new(), c.doc.to_string()])
        .collect();
    table("Connectors", connectors);
    let variables = spec
        .variables
        .iter()
        .map(|v| {
            let shape = match v.shape {
                multibody::components::Shape::Scalar => String::new(),
                multibody::components::Shape::Vector(n) => format!("[{n}]"),
                multibody::components::Shape::Matrix(r, c) => format!("[{r}, {c}]"),
            };
            [format!("{}{shape}", v.name), unit(v.unit), String::new(), v.doc.to_string()]
        })
        .collect();
    table("Variables (name, unit, description)", variables);
    out
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
