//! Diagnostics: what went wrong, where, and what to do; rendered with
//! `codespan-reporting` as `file:line:col`, the source line and a caret.

use crate::source::{Sources, Span};
use codespan_reporting::diagnostic::{
    Diagnostic as Report, Label as ReportLabel, LabelStyle, Severity as ReportSeverity,
};
use codespan_reporting::term::{self, termcolor, Config};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    Error,
    Warning,
}

/// A span with a short text shown under it.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub span: Span,
    pub message: String,
    pub primary: bool,
}

/// One message about the model files.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub message: String,
    pub labels: Vec<Label>,
    /// Further facts (`= note: ...`).
    pub notes: Vec<String>,
    /// What to do (`= help: ...`).
    pub help: Vec<String>,
}

impl Diagnostic {
    pub fn error(message: impl Into<String>) -> Self {
        Self { severity: Severity::Error, message: message.into(), labels: vec![], notes: vec![], help: vec![] }
    }

    pub fn warning(message: impl Into<String>) -> Self {
        Self { severity: Severity::Warning, ..Self::error(message) }
    }

    /// Points at the place the message is about.
    pub fn primary(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label { span, message: message.into(), primary: true });
        self
    }

    /// Points at a related place.
    pub fn secondary(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label { span, message: message.into(), primary: false });
        self
    }

    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help.push(help.into());
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The place the message is about, if it has one.
    pub fn primary_span(&self) -> Option<Span> {
        self.labels.iter().find(|l| l.primary).map(|l| l.span)
    }

    /// The diagnostic as text: plain, or with ANSI colours for a terminal.
    pub fn render(&self, sources: &Sources, color: bool) -> String {
        let report = self.to_report();
        let config = Config::default();
        if color {
            let mut buffer = termcolor::Buffer::ansi();
            if term::emit_to_write_style(&mut buffer, &config, sources, &report).is_ok() {
                return String::from_utf8_lossy(buffer.as_slice()).into_owned();
            }
        } else if let Ok(text) = term::emit_into_string(&config, sources, &report) {
            return text;
        }
        // A span outside its file would be a bug of ours; still say what is wrong.
        format!("{}: {}\n", if self.is_error() { "error" } else { "warning" }, self.message)
    }

    fn to_report(&self) -> Report<usize> {
        let severity = match self.severity {
            Severity::Error => ReportSeverity::Error,
            Severity::Warning => ReportSeverity::Warning,
        };
        let labels = self
            .labels
            .iter()
            .map(|l| {
                let style = if l.primary { LabelStyle::Primary } else { LabelStyle::Secondary };
                ReportLabel::new(style, l.span.file, l.span.range()).with_message(&l.message)
            })
            .collect();
        let notes = self
            .notes
            .iter()
            .map(|n| format!("note: {n}"))
            .chain(self.help.iter().map(|h| format!("help: {h}")))
            .collect();
        Report::new(severity).with_message(&self.message).with_labels(labels).with_notes(notes)
    }
}

/// Renders several diagnostics, one after the other.
pub fn render_all(diagnostics: &[Diagnostic], sources: &Sources, color: bool) -> String {
    diagnostics.iter().map(|d| d.render(sources, color)).collect::<Vec<_>>().join("\n")
}

/// "`a`, `b` or `c`", for suggestions.
pub fn one_of(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.len() {
        0 => String::new(),
        1 => quoted[0].clone(),
        n => format!("{} or {}", quoted[..n - 1].join(", "), quoted[n - 1]),
    }
}

/// "did you mean `x`?" from the closest names, or nothing.
pub fn did_you_mean<'a>(wanted: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let best = multibody::closest(wanted, candidates);
    (!best.is_empty()).then(|| format!("did you mean {}?", one_of(&best)))
}
