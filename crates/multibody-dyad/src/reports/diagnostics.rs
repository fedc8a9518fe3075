//! Diagnostics: what went wrong, where, and what to do; rendered with
//! `codespan-reporting` as `file:line:col`, the source line and a caret.
//!
//! What is shown of the source is cut to a readable excerpt: a line longer
//! than [`MAX_LINE_CHARS`] is cut around the caret (with `…`), and control
//! characters are shown as `�`, so that a hostile file cannot flood or
//! drive the terminal. The `file:line:col` stays that of the real file.

use crate::syntax::source::{FileId, Sources, Span};
use codespan_reporting::diagnostic::{
    Diagnostic as Report, Label as ReportLabel, LabelStyle, Severity as ReportSeverity,
};
use codespan_reporting::files::{self, Files, SimpleFile};
use codespan_reporting::term::{self, termcolor, Config};
use std::collections::HashMap;
use std::ops::Range;

/// The longest source line shown under a diagnostic, in characters.
pub const MAX_LINE_CHARS: usize = 200;
/// How much of a cut line is shown before the caret, in characters.
const CHARS_BEFORE_CARET: usize = 80;
/// The longest message, label or note shown, in characters (they may quote
/// names from the file).
const MAX_TEXT_CHARS: usize = 1000;

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
        let view = Excerpts::new(sources, &self.labels);
        let report = self.to_report(&view);
        let config = Config::default();
        if color {
            let mut buffer = termcolor::Buffer::ansi();
            if term::emit_to_write_style(&mut buffer, &config, &view, &report).is_ok() {
                return String::from_utf8_lossy(buffer.as_slice()).into_owned();
            }
        } else if let Ok(text) = term::emit_into_string(&config, &view, &report) {
            return text;
        }
        // A span outside its file would be a bug of ours; still say what is wrong.
        format!("{}: {}\n", if self.is_error() { "error" } else { "warning" }, shorten(&self.message))
    }

    fn to_report(&self, view: &Excerpts) -> Report<usize> {
        let severity = match self.severity {
            Severity::Error => ReportSeverity::Error,
            Severity::Warning => ReportSeverity::Warning,
        };
        let labels = self
            .labels
            .iter()
            .map(|l| {
                let style = if l.primary { LabelStyle::Primary } else { LabelStyle::Secondary };
                ReportLabel::new(style, l.span.file, view.range(l.span)).with_message(shorten(&l.message))
            })
            .collect();
        let notes = self
            .notes
            .iter()
            .map(|n| format!("note: {}", shorten(n)))
            .chain(self.help.iter().map(|h| format!("help: {}", shorten(h))))
            .collect();
        Report::new(severity).with_message(shorten(&self.message)).with_labels(labels).with_notes(notes)
    }
}

/// `text` with control characters shown as `�`, and cut in the middle
/// (with `…`) when it is longer than [`MAX_TEXT_CHARS`].
fn shorten(text: &str) -> String {
    let shown = |c: char| if c == '\n' || !is_hidden(c) { c } else { '\u{fffd}' };
    let count = text.chars().count();
    if count <= MAX_TEXT_CHARS {
        return text.chars().map(shown).collect();
    }
    let (head, tail) = (MAX_TEXT_CHARS * 2 / 3, MAX_TEXT_CHARS / 3);
    let mut out: String = text.chars().take(head).map(shown).collect();
    out.push('…');
    out.extend(text.chars().skip(count - tail).map(shown));
    out
}

/// Characters that would act on the terminal rather than show: control
/// characters (but tabs) and the bidirectional overrides.
fn is_hidden(c: char) -> bool {
    (c.is_control() && c != '\t') || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// The source files as a diagnostic shows them: files with long lines or
/// control characters are replaced by an excerpt whose lines are cut around
/// the labels; line and column numbers stay those of the real file.
struct Excerpts<'a> {
    sources: &'a Sources,
    excerpts: HashMap<FileId, Excerpt>,
}

/// A file as shown: its text, and how its bytes map to the real file's.
struct Excerpt {
    file: SimpleFile<String, String>,
    /// In order, covering the real text without gaps.
    segments: Vec<Segment>,
}

/// A run of the real text (`real`) and what is shown for it (`shown`):
/// the same text, or a replacement (`…` for a cut, `�` for a control character).
#[derive(Clone, Debug)]
struct Segment {
    real: Range<usize>,
    shown: Range<usize>,
    copied: bool,
}

impl<'a> Excerpts<'a> {
    fn new(sources: &'a Sources, labels: &[Label]) -> Self {
        let mut excerpts = HashMap::new();
        for label in labels {
            let file = label.span.file;
            if file >= sources.len() || excerpts.contains_key(&file) {
                continue;
            }
            let text = sources.text(file);
            if needs_excerpt(text) {
                let anchors: Vec<(usize, bool)> = labels
                    .iter()
                    .filter(|l| l.span.file == file)
                    .flat_map(|l| [(l.span.start, l.primary), (l.span.end, false)])
                    .collect();
                excerpts.insert(file, Excerpt::new(sources.name(file), text, &anchors));
            }
        }
        Self { sources, excerpts }
    }

    /// Where a span of the real file is in the shown one.
    fn range(&self, span: Span) -> Range<usize> {
        match self.excerpts.get(&span.file) {
            Some(e) => {
                let start = e.shown_offset(span.start);
                start..e.shown_offset(span.end).max(start)
            }
            None => span.range(),
        }
    }
}

/// Whether a file has a line too long to show whole, or characters that
/// would act on the terminal (other than the ends of lines).
fn needs_excerpt(text: &str) -> bool {
    text.split('\n').any(|line| {
        let line = line.strip_suffix('\r').unwrap_or(line);
        line.len() > MAX_LINE_CHARS || line.contains(is_hidden)
    })
}

impl Excerpt {
    /// The shown text of `text`: lines longer than [`MAX_LINE_CHARS`] are
    /// cut around the first anchor (a label's start or end) on them, the
    /// primary label's start first.
    fn new(name: &str, text: &str, anchors: &[(usize, bool)]) -> Self {
        let mut shown = String::with_capacity(text.len().min(1 << 16));
        let mut segments: Vec<Segment> = Vec::new();
        let mut push = |real: Range<usize>, with: Option<&str>, shown: &mut String| {
            let copied = with.is_none();
            if copied {
                if let Some(last) = segments.last_mut().filter(|s| s.copied && s.real.end == real.start) {
                    last.real.end = real.end;
                    shown.push_str(&text[real.clone()]);
                    last.shown.end = shown.len();
                    return;
                }
            }
            let start = shown.len();
            shown.push_str(with.unwrap_or(&text[real.clone()]));
            segments.push(Segment { real, shown: start..shown.len(), copied });
        };
        let mut line_start = 0;
        for line in text.split_inclusive('\n') {
            let line_end = line_start + line.trim_end_matches(['\n', '\r']).len();
            let window = window(text, line_start..line_end, anchors);
            if window.start > line_start {
                push(line_start..window.start, Some("…"), &mut shown);
            }
            let mut run = window.start;
            for (i, c) in text[window.clone()].char_indices() {
                let at = window.start + i;
                if is_hidden(c) {
                    if run < at {
                        push(run..at, None, &mut shown);
                    }
                    push(at..at + c.len_utf8(), Some("\u{fffd}"), &mut shown);
                    run = at + c.len_utf8();
                }
            }
            if run < window.end {
                push(run..window.end, None, &mut shown);
            }
            if window.end < line_end {
                push(window.end..line_end, Some("…"), &mut shown);
            }
            // The end of the line: `\r\n` or `\n` as they are; a lone `\r` (not at the end) was shown as `�`.
            let next = line_start + line.len();
            if line_end < next {
                push(line_end..next, None, &mut shown);
            }
            line_start = next;
        }
        Self { file: SimpleFile::new(name.to_string(), shown), segments }
    }

    /// The segment holding byte `at` of the real text (its end: the last segment).
    fn segment_of_real(&self, at: usize) -> &Segment {
        let i = self.segments.partition_point(|s| s.real.end <= at);
        &self.segments[i.min(self.segments.len().saturating_sub(1))]
    }

    fn shown_offset(&self, real: usize) -> usize {
        if self.segments.is_empty() {
            return 0;
        }
        let s = self.segment_of_real(real);
        if real >= s.real.end {
            s.shown.end
        } else if s.copied {
            s.shown.start + (real - s.real.start)
        } else {
            s.shown.start
        }
    }

    fn real_offset(&self, shown: usize) -> usize {
        let i = self.segments.partition_point(|s| s.shown.end <= shown);
        match self.segments.get(i) {
            Some(s) if s.copied => s.real.start + (shown - s.shown.start).min(s.real.len()),
            Some(s) => s.real.start,
            None => self.segments.last().map_or(0, |s| s.real.end),
        }
    }
}

/// The part of the line `line` shown: all of it when it is short enough,
/// else [`MAX_LINE_CHARS`] characters around its first anchor.
fn window(text: &str, line: Range<usize>, anchors: &[(usize, bool)]) -> Range<usize> {
    let body = &text[line.clone()];
    if body.len() <= MAX_LINE_CHARS || body.chars().count() <= MAX_LINE_CHARS {
        return line;
    }
    let on_line = |&&(at, _): &&(usize, bool)| at >= line.start && at <= line.end;
    let anchor = anchors
        .iter()
        .filter(on_line)
        .find(|(_, primary)| *primary)
        .or_else(|| anchors.iter().filter(on_line).min_by_key(|(at, _)| *at))
        .map_or(line.start, |(at, _)| *at);
    // Character positions on the line: the anchor's, then the window's.
    let anchor_char = text[line.start..anchor].chars().count();
    let total = body.chars().count();
    let first = anchor_char.saturating_sub(CHARS_BEFORE_CARET).min(total - MAX_LINE_CHARS);
    let byte_of = |n: usize| body.char_indices().nth(n).map_or(body.len(), |(i, _)| i);
    line.start + byte_of(first)..line.start + byte_of(first + MAX_LINE_CHARS)
}

impl<'a> Files<'a> for Excerpts<'_> {
    type FileId = FileId;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: FileId) -> Result<&'a str, files::Error> {
        Files::name(self.sources, id)
    }

    fn source(&'a self, id: FileId) -> Result<&'a str, files::Error> {
        match self.excerpts.get(&id) {
            Some(e) => Ok(e.file.source().as_str()),
            None => Files::source(self.sources, id),
        }
    }

    fn line_index(&'a self, id: FileId, byte_index: usize) -> Result<usize, files::Error> {
        match self.excerpts.get(&id) {
            Some(e) => e.file.line_index((), byte_index),
            None => self.sources.line_index(id, byte_index),
        }
    }

    fn line_range(&'a self, id: FileId, line_index: usize) -> Result<Range<usize>, files::Error> {
        match self.excerpts.get(&id) {
            Some(e) => e.file.line_range((), line_index),
            None => self.sources.line_range(id, line_index),
        }
    }

    /// The column in the real file, also where the line is cut.
    fn column_number(&'a self, id: FileId, line_index: usize, byte_index: usize) -> Result<usize, files::Error> {
        match self.excerpts.get(&id) {
            Some(e) => {
                let real = e.real_offset(byte_index);
                let text = self.sources.text(id);
                let range = self.sources.line_range(id, line_index)?;
                Ok(files::column_index(text, range, real) + 1)
            }
            None => self.sources.column_number(id, line_index, byte_index),
        }
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
