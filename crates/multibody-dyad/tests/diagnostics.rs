//! Every file in `bad/` is a model with a mistake. Its diagnostics (rendered
//! without colours) are compared with the snapshot in `snapshots/`: each
//! must name the place (file:line:col with a caret) and say what to do.

use multibody_dyad::diagnostics::render_all;
use multibody_dyad::{DefinitionKind, Diagnostic, Package};
use std::path::Path;

/// Reads, lowers and assembles a file like `multibody check` does, and
/// collects what it reports.
fn diagnose(path: &Path) -> (Package, Vec<Diagnostic>) {
    let text = std::fs::read_to_string(path).unwrap();
    let name = format!("bad/{}", path.file_name().unwrap().to_string_lossy());
    let mut package = Package::new();
    let mut reported = Vec::new();
    if let Err(d) = package.add_source(name, text) {
        reported.push(d);
        return (package, reported);
    }
    let analysis = package.definitions().into_iter().find(|d| d.kind == DefinitionKind::Analysis);
    let lowered = match analysis {
        Some(a) => package.lower_analysis(&a.name),
        None => {
            let top = package.top_components();
            let first = top.first().map(|d| d.name.clone()).unwrap_or_else(|| "Pendulum".into());
            package.lower_component(&first)
        }
    };
    match lowered {
        Err(d) => reported.push(d),
        Ok(l) => {
            reported.extend(l.warnings.iter().cloned());
            if let Err(d) = l.assemble() {
                reported.push(d);
            }
        }
    }
    (package, reported)
}

#[test]
fn bad_models_are_explained() {
    insta::glob!("bad/*.dyad", |path| {
        let (package, reported) = diagnose(path);
        let errors: Vec<&Diagnostic> = reported.iter().filter(|d| d.is_error()).collect();
        assert!(!errors.is_empty(), "{}: expected an error", path.display());
        for e in &errors {
            assert!(e.primary_span().is_some(), "{}: `{}` points nowhere", path.display(), e.message);
        }
        insta::assert_snapshot!(render_all(&reported, package.sources(), false));
    });
}

#[test]
fn there_are_enough_bad_models() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad");
    let count = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "dyad"))
        .count();
    assert!(count >= 25, "only {count} bad models");
}

/// Renders the first error of a file the way `multibody check` reads it.
fn render_file(name: &str, bytes: Vec<u8>) -> (Diagnostic, String) {
    let mut package = Package::new();
    let d = match package.add_source_bytes(name, bytes) {
        Err(d) => d,
        Ok(_) => {
            let top = package.top_components();
            match package.lower_component(&top[0].name) {
                Err(d) => d,
                Ok(l) => l.assemble().expect_err("expected an error"),
            }
        }
    };
    let text = d.render(package.sources(), false);
    (d, text)
}

/// A 2 MB line: the excerpt under the message is cut around the caret, and
/// the place is still the real line and column.
#[test]
fn a_long_line_is_cut_around_the_caret() {
    let padding = " ".repeat(1_000_000);
    let text = format!(
        "example component P\n  world = MultibodyComponents.World()\n  body = MultibodyComponents.Body({padding}m = -1,{padding}r_cm = [0.5, 0, 0])\nend\n"
    );
    assert!(text.len() > 2_000_000);
    let (_, rendered) = render_file("long.dyad", text.into_bytes());
    println!("{rendered}");
    assert!(rendered.len() < 2_000, "{} bytes rendered", rendered.len());
    let column = "  body = MultibodyComponents.Body(".len() + 1_000_000 + "m = ".len() + 1;
    assert!(rendered.contains(&format!("long.dyad:3:{column}")), "{rendered}");
    let source_line = rendered.lines().find(|l| l.starts_with("3 │")).expect("the source line");
    assert!(source_line.contains('…') && source_line.contains("m = -1"), "{source_line}");
    assert!(source_line.chars().count() <= multibody_dyad::diagnostics::MAX_LINE_CHARS + 10, "{source_line}");
    // The caret is under `-1`.
    let caret_line = rendered.lines().skip_while(|l| !l.starts_with("3 │")).nth(1).expect("the caret line");
    let caret = caret_line.chars().position(|c| c == '^').expect("a caret");
    let under: String = source_line.chars().skip(caret).take(2).collect();
    assert_eq!(under, "-1", "{source_line}\n{caret_line}");
}

/// A long name quoted in a message is cut too.
#[test]
fn a_long_name_in_a_message_is_cut() {
    let name = "x".repeat(100_000);
    let text = format!("example component P\n  world = MultibodyComponents.World()\n  body = MultibodyComponents.Body(m = {name})\nend\n");
    let (d, rendered) = render_file("name.dyad", text.into_bytes());
    assert!(d.message.len() > 100_000, "the diagnostic keeps the whole message: {}", d.message.len());
    assert!(rendered.len() < 5_000, "{} bytes rendered", rendered.len());
    assert!(rendered.contains('…'));
}

/// Control characters in the file are not sent to the terminal; the caret
/// still points at the character.
#[test]
fn control_characters_are_not_echoed() {
    let text = "example component P\n  world = MultibodyComponents.World()\n  x = \u{1b}[2J\nend\n";
    let (d, rendered) = render_file("escape.dyad", text.as_bytes().to_vec());
    println!("{rendered}");
    assert!(d.message.contains("unexpected character"), "{}", d.message);
    assert!(!rendered.contains('\u{1b}'), "{rendered:?}");
    assert!(rendered.contains("escape.dyad:3:7"), "{rendered}");
    assert!(rendered.contains("x = \u{fffd}[2J"), "{rendered}");
    assert!(rendered.contains('^'), "{rendered}");
}

/// A file that is not UTF-8: the message says where the first bad byte is
/// (line, column and byte offset), and points at it.
#[test]
fn bytes_that_are_not_utf8_are_pointed_at() {
    let mut bytes = b"example component P\n  world = MultibodyComponents.World()\n  x\xff\xfe = 1\nend\n".to_vec();
    let offset = bytes.iter().position(|&b| b == 0xff).unwrap();
    let (d, rendered) = render_file("binary.dyad", bytes.clone());
    println!("{rendered}");
    assert!(d.message.contains("binary.dyad is not UTF-8 text"), "{}", d.message);
    assert!(d.message.contains("0xFF") && d.message.contains("binary.dyad:3:4"), "{}", d.message);
    assert!(d.message.contains(&format!("byte offset {offset}")), "{}", d.message);
    assert!(rendered.contains("┌─ binary.dyad:3:4"), "{rendered}");
    assert!(rendered.contains('^'), "{rendered}");
    // A UTF-16 file says so.
    bytes = [0xFF, 0xFE].iter().copied().chain("example".encode_utf16().flat_map(u16::to_le_bytes)).collect();
    let (d, _) = render_file("utf16.dyad", bytes);
    assert!(d.help.iter().any(|h| h.contains("UTF-16")), "{:?}", d.help);
}
