//! Source files and positions in them.

use codespan_reporting::files::{self, Files, SimpleFile};
use std::ops::Range;

/// A file of the package, by its position in [`Sources`].
pub type FileId = usize;

/// A range of bytes in one source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    pub file: FileId,
    pub start: usize,
    pub end: usize,
}

impl Span {
    pub fn new(file: FileId, start: usize, end: usize) -> Self {
        Self { file, start, end }
    }

    /// The span from the start of `self` to the end of `other` (same file).
    pub fn to(self, other: Span) -> Span {
        Span { file: self.file, start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    pub fn range(&self) -> Range<usize> {
        self.start..self.end
    }
}

/// Every source file read so far, with its name as the user gave it.
#[derive(Debug, Default, Clone)]
pub struct Sources {
    files: Vec<SimpleFile<String, String>>,
}

impl Sources {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        self.files.push(SimpleFile::new(name.into(), text.into()));
        self.files.len() - 1
    }

    pub fn name(&self, file: FileId) -> &str {
        self.files[file].name()
    }

    pub fn text(&self, file: FileId) -> &str {
        self.files[file].source()
    }

    /// The text a span covers.
    pub fn slice(&self, span: Span) -> &str {
        self.text(span.file).get(span.range()).unwrap_or("")
    }

    pub fn len(&self) -> usize {
        self.files.len()
    }

    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// `file:line:col` of the start of a span (1-based), for short messages.
    pub fn location(&self, span: Span) -> String {
        match self.line_column(span) {
            Some((line, col)) => format!("{}:{line}:{col}", self.name(span.file)),
            None => self.name(span.file).to_string(),
        }
    }

    /// Line and column (1-based) of the start of a span.
    pub fn line_column(&self, span: Span) -> Option<(usize, usize)> {
        let line = self.line_index(span.file, span.start).ok()?;
        Some((line + 1, self.column_number(span.file, line, span.start).ok()?))
    }
}

impl<'a> Files<'a> for Sources {
    type FileId = FileId;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: FileId) -> Result<&'a str, files::Error> {
        self.files.get(id).map(|f| f.name().as_str()).ok_or(files::Error::FileMissing)
    }

    fn source(&'a self, id: FileId) -> Result<&'a str, files::Error> {
        self.files.get(id).map(|f| f.source().as_str()).ok_or(files::Error::FileMissing)
    }

    fn line_index(&'a self, id: FileId, byte_index: usize) -> Result<usize, files::Error> {
        self.files.get(id).ok_or(files::Error::FileMissing)?.line_index((), byte_index)
    }

    fn line_range(&'a self, id: FileId, line_index: usize) -> Result<Range<usize>, files::Error> {
        self.files.get(id).ok_or(files::Error::FileMissing)?.line_range((), line_index)
    }
}
