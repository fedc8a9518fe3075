//! A recursive-descent parser for Dyad model files: definitions,
//! declarations, relations (equations, `if`, `for`, `switch`, ...) and
//! expressions with Julia's precedence. Constructs we do not support are
//! recognised where they start and reported as "not supported yet",
//! pointing at them.

use crate::reports::diagnostics::Diagnostic;
use crate::syntax::ast::*;
use crate::syntax::lexer::{tokenize, Token, TokenKind};
use crate::syntax::source::{FileId, Span};

/// How deeply expressions and modifiers may nest; deeper input is refused
/// rather than risking the stack.
const MAX_DEPTH: usize = 64;
/// How deeply serde_json lets JSON (metadata) nest: its limit of 128
/// refuses the 128th level.
const MAX_JSON_DEPTH: usize = 127;

/// Parses one file.
pub fn parse(file: FileId, text: &str) -> Result<File, Diagnostic> {
    let tokens = tokenize(file, text)?;
    Parser { tokens, pos: 0, depth: 0, text }.file()
}

struct Parser<'a> {
    tokens: Vec<Token>,
    pos: usize,
    depth: usize,
    text: &'a str,
}

type PResult<T> = Result<T, Diagnostic>;

/// Words that start a section or end a definition inside a component.
const SECTION_WORDS: &[&str] = &["relations", "metadata", "end"];

fn unsupported(what: &str, span: Span) -> Diagnostic {
    Diagnostic::error(format!("{what} not supported yet")).primary(span, "not supported yet")
}

impl<'a> Parser<'a> {
    // ---- token helpers -------------------------------------------------

    fn peek(&self) -> &Token {
        &self.tokens[self.pos.min(self.tokens.len() - 1)]
    }

    fn nth(&self, k: usize) -> &TokenKind {
        &self.tokens[(self.pos + k).min(self.tokens.len() - 1)].kind
    }

    fn span(&self) -> Span {
        self.peek().span
    }

    fn prev_span(&self) -> Span {
        self.tokens[self.pos.saturating_sub(1)].span
    }

    fn at(&self, kind: &TokenKind) -> bool {
        &self.peek().kind == kind
    }

    fn at_word(&self, word: &str) -> bool {
        matches!(&self.peek().kind, TokenKind::Ident(w) if w == word)
    }

    fn word(&self) -> Option<&str> {
        match &self.peek().kind {
            TokenKind::Ident(w) => Some(w),
            _ => None,
        }
    }

    /// Whether the next tokens start a definition on a line of their own
    /// (`analysis Name`, `example component Name`, ...): where a block whose
    /// `end` was deleted stops, so that the message is about the `end`.
    fn at_definition(&self) -> bool {
        let previous = self.prev_span();
        let between = self.text.get(previous.end..self.span().start).unwrap_or("");
        if self.pos > 0 && !between.contains('\n') {
            return false;
        }
        // Doc strings before the definition are its own.
        let mut docs = 0;
        while matches!(self.nth(docs), TokenKind::Str(_) | TokenKind::TripleStr(_)) {
            docs += 1;
        }
        let word = |k: usize| match self.nth(docs + k) {
            TokenKind::Ident(w) => Some(w.as_str()),
            _ => None,
        };
        match (word(0), word(1)) {
            (Some("component" | "analysis" | "connector"), Some(_)) => true,
            (Some("example" | "partial" | "test"), Some("component" | "analysis")) => word(2).is_some(),
            _ => false,
        }
    }

    fn bump(&mut self) -> Token {
        let token = self.peek().clone();
        if token.kind != TokenKind::Eof {
            self.pos += 1;
        }
        token
    }

    fn eat(&mut self, kind: &TokenKind) -> bool {
        if self.at(kind) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn eat_word(&mut self, word: &str) -> bool {
        if self.at_word(word) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn skip_semicolons(&mut self) {
        while self.eat(&TokenKind::Semicolon) {}
    }

    /// "expected X, found Y" at the current token, or just after the
    /// previous one when the current token is on a later line (a missing
    /// `)` at the end of a line is reported there).
    fn expected(&self, what: &str) -> Diagnostic {
        let found = self.peek().kind.describe();
        let d = Diagnostic::error(format!("expected {what}, found {found}"));
        let previous = self.prev_span();
        let between = self.text.get(previous.end..self.span().start).unwrap_or("");
        if self.pos > 0 && between.contains('\n') {
            let after = Span::new(previous.file, previous.end, previous.end);
            d.primary(after, format!("expected {what} here")).secondary(self.span(), format!("found {found}"))
        } else {
            d.primary(self.span(), format!("expected {what}"))
        }
    }

    fn expect(&mut self, kind: TokenKind, what: &str) -> PResult<Token> {
        if self.at(&kind) {
            Ok(self.bump())
        } else {
            Err(self.expected(what))
        }
    }

    fn expect_word(&mut self, word: &str) -> PResult<Span> {
        if self.at_word(word) {
            Ok(self.bump().span)
        } else {
            Err(self.expected(&format!("`{word}`")))
        }
    }

    fn ident(&mut self, what: &str) -> PResult<Ident> {
        match &self.peek().kind {
            TokenKind::Ident(name) => {
                let ident = Ident { name: name.clone(), span: self.span() };
                self.bump();
                Ok(ident)
            }
            _ => Err(self.expected(what)),
        }
    }

    fn path(&mut self, what: &str) -> PResult<Path> {
        let first = self.ident(what)?;
        let mut span = first.span;
        let mut parts = vec![first];
        while self.at(&TokenKind::Dot) && matches!(self.nth(1), TokenKind::Ident(_)) {
            self.bump();
            let part = self.ident("a name")?;
            span = span.to(part.span);
            parts.push(part);
        }
        Ok(Path { parts, span })
    }

    fn enter(&mut self) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Diagnostic::error(format!(
                "this is nested more than {MAX_DEPTH} levels deep (parentheses, brackets, calls or modifiers inside each other)"
            ))
            .primary(self.span(), "too deep")
            .help("split the expression, or compute part of the value in a parameter"));
        }
        Ok(())
    }

    fn leave(&mut self, levels: usize) {
        self.depth -= levels;
    }

    /// Doc strings before a definition or declaration.
    fn doc(&mut self) -> Option<String> {
        let mut doc: Option<String> = None;
        while let TokenKind::Str(s) | TokenKind::TripleStr(s) = &self.peek().kind {
            let s = s.trim().to_string();
            doc = Some(match doc {
                Some(d) => format!("{d}\n{s}"),
                None => s,
            });
            self.bump();
        }
        doc
    }

    // ---- metadata ------------------------------------------------------

    /// `{ json }` or the older `[{ json }]` after a declaration or relation.
    fn optional_annotation(&mut self) -> PResult<()> {
        if self.at(&TokenKind::LBrace) && self.nth(1) == &TokenKind::Caret {
            // `{^name}`: a link into the definition's `_links` metadata.
            self.bump();
            self.bump();
            self.ident("the name of a metadata link")?;
            self.expect(TokenKind::RBrace, "`}` after the link")?;
            Ok(())
        } else if self.at(&TokenKind::LBrace) {
            self.json_object().map(|_| ())
        } else if self.at(&TokenKind::LBracket) && self.nth(1) == &TokenKind::LBrace {
            self.bump();
            self.json_object()?;
            self.expect(TokenKind::RBracket, "`]` after the metadata")?;
            Ok(())
        } else {
            Ok(())
        }
    }

    /// A JSON object: skipped by matching brackets, then checked as JSON;
    /// its span.
    fn json_object(&mut self) -> PResult<Span> {
        let open = self.expect(TokenKind::LBrace, "`{`")?.span;
        let mut stack = vec![TokenKind::RBrace];
        while let Some(closer) = stack.last().cloned() {
            let token = self.bump();
            match token.kind {
                TokenKind::LBrace => stack.push(TokenKind::RBrace),
                TokenKind::LBracket => stack.push(TokenKind::RBracket),
                TokenKind::RBrace | TokenKind::RBracket if token.kind == closer => {
                    stack.pop();
                }
                TokenKind::RBrace | TokenKind::RBracket => {
                    return Err(Diagnostic::error("mismatched bracket in metadata")
                        .primary(token.span, format!("expected {}", closer.describe()))
                        .secondary(open, "the metadata starts here"));
                }
                TokenKind::Eof => {
                    return Err(Diagnostic::error("this metadata `{` is never closed")
                        .primary(open, "opened here")
                        .help("metadata is a JSON object: close every `{` and `[`"));
                }
                _ => {}
            }
        }
        let span = open.to(self.prev_span());
        let json = &self.text[span.range()];
        if let Err(e) = serde_json::from_str::<serde_json::Value>(json) {
            let offset = json_error_offset(json, e.line(), e.column());
            let mut at = span.start + offset;
            while at < span.end && !self.text.is_char_boundary(at) {
                at += 1;
            }
            let end = (at + 1..=span.end).find(|&i| self.text.is_char_boundary(i)).unwrap_or(span.end);
            let message = e.to_string();
            let what = message.split(" at line").next().unwrap_or(&message).to_string();
            let place = Span::new(span.file, at.min(span.end), end);
            if what == "recursion limit exceeded" {
                // serde_json refuses JSON nested deeper than this.
                return Err(Diagnostic::error(format!(
                    "the metadata is nested more than {MAX_JSON_DEPTH} levels deep"
                ))
                .primary(place, format!("level {}", MAX_JSON_DEPTH + 1))
                .secondary(open, "in this metadata")
                .help(format!(
                    "nest objects and arrays at most {MAX_JSON_DEPTH} levels deep; the simulation does not read metadata, so it may also be removed"
                )));
            }
            return Err(Diagnostic::error("the metadata is not valid JSON")
                .primary(place, what)
                .secondary(open, "in this metadata")
                .help("metadata is JSON: keys in double quotes, no trailing commas, e.g. {\"Dyad\": {\"tags\": []}}"));
        }
        Ok(span)
    }

    /// `metadata { json }` before `end`.
    fn metadata_section(&mut self) -> PResult<Span> {
        self.expect_word("metadata")?;
        if !self.at(&TokenKind::LBrace) {
            return Err(self.expected("`{` to start the metadata object"));
        }
        let span = self.json_object()?;
        self.skip_semicolons();
        Ok(span)
    }

    /// The engine connector a connector's metadata names
    /// (`{"Multibody": {"engine": "Frame3D"}}`), if any.
    fn engine_of(&self, metadata: Span) -> Option<(String, Span)> {
        let json: serde_json::Value = serde_json::from_str(&self.text[metadata.range()]).ok()?;
        let name = json.get("Multibody")?.get("engine")?.as_str()?;
        Some((name.to_string(), metadata))
    }

    // ---- definitions ---------------------------------------------------

    fn file(mut self) -> PResult<File> {
        let mut items = Vec::new();
        loop {
            self.skip_semicolons();
            let doc_span = self.span();
            let doc = self.doc();
            if self.at(&TokenKind::Eof) {
                if doc.is_some() {
                    return Err(Diagnostic::error("a doc string must be followed by what it documents")
                        .primary(doc_span, "documents nothing")
                        .help("put the doc string right before a `component` or `analysis`, or remove it"));
                }
                break;
            }
            items.push(self.definition(doc)?);
        }
        Ok(File { items, package: None })
    }

    fn definition(&mut self, doc: Option<String>) -> PResult<Item> {
        let start = self.span();
        let Some(word) = self.word().map(str::to_string) else {
            return Err(self.expected("a definition (`component`, `example component` or `analysis`)"));
        };
        let prefix = match word.as_str() {
            "partial" => Some(ComponentKind::Partial),
            "example" => Some(ComponentKind::Example),
            "test" => Some(ComponentKind::Test),
            "external" => {
                return Err(unsupported("`external` components are", start)
                    .help("define the component with sub-components and connections instead"))
            }
            _ => None,
        };
        if prefix.is_some() {
            self.bump();
        }
        if self.at_word("component") {
            return self.component(prefix.unwrap_or(ComponentKind::Component), doc, start).map(Item::Component);
        }
        if self.at_word("analysis") {
            return self.analysis(doc, start).map(|a| Item::Analysis(Box::new(a)));
        }
        if prefix.is_some() {
            return Err(self.expected("`component` or `analysis`"));
        }
        match word.as_str() {
            "type" => self.type_alias().map(Item::TypeAlias),
            "connector" => self.connector(doc, start).map(Item::Connector),
            "enum" => Err(unsupported("`enum` definitions are", start)
                .help("use the library's enumerations, e.g. `orientation_state = OrientationState.Quaternion()`")),
            "using" | "import" => Err(unsupported(&format!("`{word}` is"), start).help(
                "write library names in full, e.g. `MultibodyComponents.Body()`, or without the library: `Body()`",
            )),
            "struct" => Err(unsupported("`struct` definitions are", start)),
            "function" | "func" => Err(unsupported("function definitions are", start)),
            _ => Err(self.expected("a definition (`component`, `example component` or `analysis`)")),
        }
    }

    /// `connector Name potential v::Voltage flow i::Current [metadata {...}] end`,
    /// or a signal connector `connector Name = input Real [metadata {...}]`.
    fn connector(&mut self, doc: Option<String>, start: Span) -> PResult<ConnectorDef> {
        self.expect_word("connector")?;
        let name = self.ident("the name of the connector")?;
        let header = start.to(name.span);
        let mut def =
            ConnectorDef { name, doc, header, fields: Vec::new(), parameters: Vec::new(), signal: None, engine: None };
        if self.eat(&TokenKind::Eq) {
            let causality = match self.word() {
                Some("input") => Causality::Input,
                Some("output") => Causality::Output,
                _ => {
                    return Err(self
                        .expected("`input` or `output`")
                        .help(format!("a signal connector is written `connector {} = input Real`", def.name.name)))
                }
            };
            self.bump();
            def.signal = Some((causality, self.type_ref()?));
            if self.at_word("metadata") {
                let metadata = self.metadata_section()?;
                def.engine = self.engine_of(metadata);
            } else {
                self.optional_annotation()?;
            }
            self.skip_semicolons();
            return Ok(def);
        }
        loop {
            self.skip_semicolons();
            let doc_span = self.span();
            let doc = self.doc();
            if self.word().is_some_and(|w| SECTION_WORDS.contains(&w)) || self.at(&TokenKind::Eof) {
                if doc.is_some() {
                    return Err(Diagnostic::error("a doc string must be followed by what it documents")
                        .primary(doc_span, "documents nothing")
                        .help("put the doc string right before a field, or remove it"));
                }
                break;
            }
            let field_start = self.span();
            let kind = match self.word() {
                Some("potential") => FieldKind::Potential,
                Some("flow") => FieldKind::Flow,
                Some("input") => FieldKind::Input,
                Some("output") => FieldKind::Output,
                Some("parameter" | "structural" | "final" | "constant") => {
                    def.parameters.push(self.parameter(doc)?);
                    continue;
                }
                Some(w @ ("stream" | "path")) => {
                    return Err(unsupported(&format!("`{w}` fields of connectors are"), field_start)
                        .help("declare the connector's quantities as `potential` or `flow`"))
                }
                _ => {
                    return Err(self
                        .expected("a field of the connector (`potential v::Voltage`, `flow i::Current`) or `end`")
                        .secondary(header, "in this connector"))
                }
            };
            self.bump();
            let name = self.ident("the field's name")?;
            if !self.at(&TokenKind::ColonColon) {
                return Err(self.expected("`::` and a type").help(format!(
                    "fields have a type: `{} {}::Real`",
                    kind.keyword(),
                    name.name
                )));
            }
            self.bump();
            let ty = self.type_ref()?;
            let span = field_start.to(self.prev_span());
            self.optional_annotation()?;
            self.skip_semicolons();
            def.fields.push(ConnectorField { doc, kind, name, ty, span });
        }
        if self.at_word("relations") {
            return Err(Diagnostic::error("a connector has no relations")
                .primary(self.span(), "relations in a connector")
                .secondary(header, "in this connector")
                .help("connectors declare only fields; write the equations in the components that use them"));
        }
        if self.at_word("metadata") {
            let metadata = self.metadata_section()?;
            def.engine = self.engine_of(metadata);
        }
        if !self.at_word("end") {
            return Err(self.expected("`end`").secondary(header, "this connector is not closed"));
        }
        self.bump();
        self.skip_semicolons();
        Ok(def)
    }

    fn component(&mut self, kind: ComponentKind, doc: Option<String>, start: Span) -> PResult<ComponentDef> {
        self.expect_word("component")?;
        let name = self.ident("the name of the component")?;
        let header = start.to(name.span);
        let mut declarations = Vec::new();
        loop {
            self.skip_semicolons();
            let doc_span = self.span();
            let before_doc = self.pos;
            let doc = self.doc();
            if self.at_definition() {
                // A doc string there is the next definition's.
                self.pos = before_doc;
                break;
            }
            if self.word().is_some_and(|w| SECTION_WORDS.contains(&w)) || self.at(&TokenKind::Eof) {
                if doc.is_some() {
                    return Err(Diagnostic::error("a doc string must be followed by what it documents")
                        .primary(doc_span, "documents nothing")
                        .help("put the doc string right before a declaration, or remove it"));
                }
                break;
            }
            declarations.push(self.declaration(doc)?);
        }
        let mut relations = Vec::new();
        if self.eat_word("relations") {
            relations = self.relations()?;
        }
        if self.at_word("metadata") {
            self.metadata_section()?;
        }
        if !self.at_word("end") {
            let mut d = self.expected("`end`");
            if self.at(&TokenKind::Eof) {
                d = d.secondary(header, "this component is not closed").help("end the component with `end`");
            } else if self.at_definition() {
                d = d
                    .secondary(header, "this component is not closed")
                    .help("end the component with `end` before the next definition");
            }
            return Err(d);
        }
        self.bump();
        self.skip_semicolons();
        Ok(ComponentDef { kind, name, doc, header, declarations, relations })
    }

    fn declaration(&mut self, doc: Option<String>) -> PResult<Declaration> {
        let start = self.span();
        let Some(word) = self.word().map(str::to_string) else {
            return Err(self.expected("a declaration (`name = Kind(...)` or `parameter ...`), `relations` or `end`"));
        };
        let next_is_name = matches!(self.nth(1), TokenKind::Ident(_));
        match word.as_str() {
            "final" if matches!(self.nth(1), TokenKind::Ident(w) if w == "variable") => {
                self.bump();
                return self.variable(doc, start).map(Declaration::Variable);
            }
            "parameter" | "structural" | "final" | "constant" if next_is_name => {
                return self.parameter(doc).map(Declaration::Parameter)
            }
            "extends" if next_is_name => return self.extends().map(Declaration::Extends),
            "variable" | "input" | "output" if next_is_name => {
                return self.variable(doc, start).map(Declaration::Variable)
            }
            "path" | "potential" | "flow" | "stream" if next_is_name => {
                return Err(unsupported(&format!("`{word}` declarations in components are"), start)
                    .help("declare variables with `variable x::Real`, and connectors with the library's types: `frame_a = Frame3D()`"))
            }
            _ => {}
        }
        if matches!(self.nth(1), TokenKind::Eq | TokenKind::ColonColon) {
            return self.component_decl(doc).map(Declaration::Component);
        }
        Err(self.expected("a declaration (`name = Kind(...)` or `parameter ...`), `relations` or `end`"))
    }

    /// `name = Kind(modifiers) [if condition] {metadata}`, or an array
    /// `name = [Kind(modifiers) for i in range]`.
    fn component_decl(&mut self, doc: Option<String>) -> PResult<ComponentDecl> {
        let name = self.ident("a name")?;
        if self.at(&TokenKind::ColonColon) {
            return Err(unsupported("type constraints on sub-components (`name::Type = ...`) are", self.span())
                .help(format!("write `{} = Kind(...)`", name.name)));
        }
        self.expect(TokenKind::Eq, "`=`")?;
        let bracket = self.eat(&TokenKind::LBracket);
        let kind = self.path("a component kind, e.g. `MultibodyComponents.Body`")?;
        if !self.at(&TokenKind::LParen) {
            return Err(self.expected("`(`").help(format!("write `{} = {}()`", name.name, kind.text())));
        }
        let modifiers = self.modifiers()?;
        let mut array = None;
        if bracket {
            if !self.eat_word("for") {
                return Err(self.expected("`for`").help(format!(
                    "an array of components is written `{} = [{}(...) for i in 1:N]`",
                    name.name,
                    kind.text()
                )));
            }
            let var = self.ident("the index of the array")?;
            self.expect_word("in")?;
            let range = self.range_or_expr()?;
            self.expect(TokenKind::RBracket, "`]`")?;
            array = Some((var, range));
        }
        let span = name.span.to(self.prev_span());
        let condition = if self.eat_word("if") { Some(self.expr()?) } else { None };
        self.optional_annotation()?;
        self.skip_semicolons();
        Ok(ComponentDecl { doc, name, kind, modifiers, condition, array, span })
    }

    /// `extends Base(modifiers)`.
    fn extends(&mut self) -> PResult<ExtendsDecl> {
        let start = self.expect_word("extends")?;
        let base = self.path("the component to extend")?;
        let modifiers = if self.at(&TokenKind::LParen) { self.modifiers()? } else { Vec::new() };
        let span = start.to(self.prev_span());
        self.optional_annotation()?;
        self.skip_semicolons();
        Ok(ExtendsDecl { base, modifiers, span })
    }

    /// `variable x::Type[dims] [= expr] [initial expr]`, `input u::Real`,
    /// `output y::Real[3]`.
    fn variable(&mut self, doc: Option<String>, start: Span) -> PResult<VariableDecl> {
        let causality = match self.word() {
            Some("input") => Causality::Input,
            Some("output") => Causality::Output,
            _ => Causality::Internal,
        };
        self.bump();
        let name = self.ident("the variable's name")?;
        if !self.at(&TokenKind::ColonColon) {
            return Err(self.expected("`::` and a type").help(format!(
                "variables have a type: `variable {}::Real` or `variable {}::Real[3]`",
                name.name, name.name
            )));
        }
        self.bump();
        let ty = self.type_ref()?;
        let (mut binding, mut initial) = (None, None);
        if self.eat(&TokenKind::Eq) {
            if self.eat_word("initial") {
                initial = Some(self.expr()?);
            } else {
                binding = Some(self.expr()?);
                if self.eat_word("initial") {
                    initial = Some(self.expr()?);
                }
            }
        }
        let span = start.to(self.prev_span());
        if self.at_word("if") {
            return Err(unsupported("conditional variables (`... if condition`) are", self.span())
                .help("declare the variable unconditionally"));
        }
        self.optional_annotation()?;
        self.skip_semicolons();
        Ok(VariableDecl { doc, causality, name, ty, binding, initial, span })
    }

    /// `(a = 1, b(initial = 2), final c = 3)`.
    fn modifiers(&mut self) -> PResult<Vec<Modifier>> {
        self.enter()?;
        self.expect(TokenKind::LParen, "`(`")?;
        let mut modifiers = Vec::new();
        while !self.at(&TokenKind::RParen) {
            modifiers.push(self.modifier()?);
            if !self.eat(&TokenKind::Comma) {
                break;
            }
        }
        if !self.at(&TokenKind::RParen) {
            return Err(self.expected("`,` or `)`"));
        }
        self.bump();
        self.leave(1);
        Ok(modifiers)
    }

    fn modifier(&mut self) -> PResult<Modifier> {
        let start = self.span();
        let is_final = self.at_word("final") && matches!(self.nth(1), TokenKind::Ident(_));
        if is_final {
            self.bump();
        }
        if self.at_word("each") || self.at_word("redeclare") {
            return Err(unsupported(&format!("`{}` modifiers are", self.word().unwrap_or_default()), self.span()));
        }
        let TokenKind::Ident(_) = self.peek().kind else {
            return Err(self
                .expected("a modifier `name = value`")
                .help("arguments are written by name, e.g. `Body(m = 1, r_cm = [0.5, 0, 0])`"));
        };
        let name = self.ident("a name")?;
        let mut nested = None;
        if self.at(&TokenKind::LParen) {
            nested = Some(self.modifiers()?);
        }
        let mut value = None;
        if self.eat(&TokenKind::Eq) {
            value = Some(self.expr()?);
        }
        if nested.is_none() && value.is_none() {
            return Err(self
                .expected("`=` or `(`")
                .help(format!("give a value, `{} = ...`, or attributes, `{}(initial = ...)`", name.name, name.name)));
        }
        Ok(Modifier { is_final, name, value, nested, span: start.to(self.prev_span()) })
    }

    /// `[final | structural] parameter name::Type[dims] = default`.
    fn parameter(&mut self, doc: Option<String>) -> PResult<ParameterDecl> {
        let start = self.span();
        let variability = if self.eat_word("constant") {
            Variability::Final
        } else if self.eat_word("final") {
            self.eat_word("structural");
            self.expect_word("parameter")?;
            Variability::Final
        } else if self.eat_word("structural") {
            self.expect_word("parameter")?;
            Variability::Structural
        } else {
            self.expect_word("parameter")?;
            Variability::Parameter
        };
        let name = self.ident("the parameter's name")?;
        if !self.at(&TokenKind::ColonColon) {
            return Err(self.expected("`::` and a type").help(format!(
                "parameters have a type: `parameter {}::Real = 1` or `parameter {}::Length[3] = [0, 0, 0]`",
                name.name, name.name
            )));
        }
        self.bump();
        let ty = self.type_ref()?;
        let default = if self.eat(&TokenKind::Eq) { Some(self.expr()?) } else { None };
        let span = start.to(self.prev_span());
        if self.at_word("if") {
            return Err(unsupported("conditional declarations (`... if condition`) are", self.span()));
        }
        self.optional_annotation()?;
        self.skip_semicolons();
        Ok(ParameterDecl { doc, variability, name, ty, default, span })
    }

    fn type_ref(&mut self) -> PResult<TypeRef> {
        let name = self.path("a type, e.g. `Real` or `Length`")?;
        let attributes = if self.at(&TokenKind::LParen) { self.modifiers()? } else { Vec::new() };
        let mut dims = Vec::new();
        if self.at(&TokenKind::LBracket) && self.nth(1) != &TokenKind::LBrace {
            self.bump();
            loop {
                if self.at(&TokenKind::Colon) {
                    dims.push(Dim::Any(self.bump().span));
                } else {
                    dims.push(Dim::Size(self.expr()?));
                }
                if !self.eat(&TokenKind::Comma) {
                    break;
                }
            }
            self.expect(TokenKind::RBracket, "`]`")?;
        }
        let span = name.span.to(self.prev_span());
        Ok(TypeRef { name, attributes, dims, span })
    }

    fn relations(&mut self) -> PResult<Vec<Relation>> {
        self.block(&["metadata", "end"])
    }

    /// Relations up to (not including) one of the words `stops`, or the
    /// end of the file.
    fn block(&mut self, stops: &[&str]) -> PResult<Vec<Relation>> {
        let mut relations = Vec::new();
        loop {
            self.skip_semicolons();
            let doc_span = self.span();
            let before_doc = self.pos;
            let doc = self.doc();
            if self.at_definition() {
                // A doc string there is the next definition's.
                self.pos = before_doc;
                return Ok(relations);
            }
            if self.word().is_some_and(|w| stops.contains(&w)) || self.at(&TokenKind::Eof) {
                if doc.is_some() {
                    return Err(Diagnostic::error("a doc string must be followed by what it documents")
                        .primary(doc_span, "documents nothing"));
                }
                return Ok(relations);
            }
            relations.push(self.relation()?);
            self.optional_annotation()?;
            self.skip_semicolons();
        }
    }

    fn relation(&mut self) -> PResult<Relation> {
        let start = self.span();
        let word = self.word().unwrap_or_default().to_string();
        let call = self.nth(1) == &TokenKind::LParen;
        match word.as_str() {
            "connect" if call => return self.connect(),
            "assert" if call => return self.assert(),
            "initial" if self.nth(1) != &TokenKind::Eq => {
                self.bump();
                let (lhs, rhs, span) = self.equation(start)?;
                return Ok(Relation::Initial { lhs, rhs, span });
            }
            "guess" if self.nth(1) != &TokenKind::Eq => {
                self.bump();
                let (lhs, rhs, span) = self.equation(start)?;
                return Ok(Relation::Guess { lhs, rhs, span });
            }
            "if" => return self.if_relation(),
            "for" => return self.for_relation(),
            "switch" => return self.switch_relation(),
            "when" => return self.when_relation(),
            "reinit" if call => return self.reinit(),
            "transition" | "continuity" | "analysis_point" | "state" => {
                return Err(unsupported(&format!("`{word}` is"), start))
            }
            _ => {}
        }
        if word.is_empty()
            && !matches!(
                self.peek().kind,
                TokenKind::Number(_) | TokenKind::LParen | TokenKind::Minus | TokenKind::LBracket
            )
        {
            return Err(self.expected("a relation (an equation, `connect(...)`, `initial ...`), `metadata` or `end`"));
        }
        if !word.is_empty() && self.nth(1) == &TokenKind::Colon {
            return Err(unsupported("named relations (`name: ...`) are", start));
        }
        let (lhs, rhs, span) = self.equation(start)?;
        Ok(Relation::Equation { lhs, rhs, span })
    }

    /// `lhs = rhs`.
    fn equation(&mut self, start: Span) -> PResult<(Expr, Expr, Span)> {
        let lhs = self.expr()?;
        if !self.at(&TokenKind::Eq) {
            if self.at(&TokenKind::EqEq) {
                return Err(self.expected("`=`").help("an equation is written with one `=`; `==` compares"));
            }
            return Err(Diagnostic::error("expected `=`: a relation here is an equation `lhs = rhs`")
                .primary(lhs.span, "this is not an equation")
                .secondary(self.span(), format!("found {}", self.peek().kind.describe())));
        }
        self.bump();
        let rhs = self.expr()?;
        let span = start.to(rhs.span);
        Ok((lhs, rhs, span))
    }

    fn connect(&mut self) -> PResult<Relation> {
        let start = self.expect_word("connect")?;
        self.expect(TokenKind::LParen, "`(`")?;
        let mut ends = Vec::new();
        loop {
            if !matches!(self.peek().kind, TokenKind::Ident(_)) {
                return Err(self.expected("a connector, e.g. `joint.frame_a`"));
            }
            ends.push(self.postfix()?);
            if !self.eat(&TokenKind::Comma) {
                break;
            }
        }
        if !self.at(&TokenKind::RParen) {
            return Err(self.expected("`,` or `)`"));
        }
        self.bump();
        let span = start.to(self.prev_span());
        if ends.len() < 2 {
            return Err(Diagnostic::error("`connect` needs at least two connectors")
                .primary(span, "only one connector")
                .help("connect two or more connectors: `connect(a.frame_b, b.frame_a)`"));
        }
        Ok(Relation::Connect { ends, span })
    }

    /// `assert(condition, "message")`.
    fn assert(&mut self) -> PResult<Relation> {
        let start = self.expect_word("assert")?;
        self.expect(TokenKind::LParen, "`(`")?;
        let condition = self.expr()?;
        self.expect(TokenKind::Comma, "`,` and a message")?;
        let message = match self.peek().kind.clone() {
            TokenKind::Str(s) | TokenKind::TripleStr(s) => {
                self.bump();
                s
            }
            _ => return Err(self.expected("a message in quotes")),
        };
        self.expect(TokenKind::RParen, "`)`")?;
        Ok(Relation::Assert { condition, message, span: start.to(self.prev_span()) })
    }

    /// `if c ... elseif c ... else ... end`.
    fn if_relation(&mut self) -> PResult<Relation> {
        let start = self.expect_word("if")?;
        self.enter()?;
        let mut branches = Vec::new();
        let condition = self.expr()?;
        let body = self.block(&["elseif", "else", "end"])?;
        branches.push((condition, body));
        let mut otherwise = None;
        loop {
            if self.eat_word("elseif") {
                let condition = self.expr()?;
                let body = self.block(&["elseif", "else", "end"])?;
                branches.push((condition, body));
            } else if self.eat_word("else") {
                otherwise = Some(self.block(&["end"])?);
            } else {
                break;
            }
        }
        self.close_block(start, "if")?;
        self.leave(1);
        Ok(Relation::If { branches, otherwise, span: start.to(self.prev_span()) })
    }

    /// `when c ... elsewhen c ... end`.
    fn when_relation(&mut self) -> PResult<Relation> {
        let start = self.expect_word("when")?;
        self.enter()?;
        let mut branches = Vec::new();
        let condition = self.expr()?;
        let body = self.block(&["elsewhen", "end"])?;
        branches.push((condition, body));
        while self.eat_word("elsewhen") {
            let condition = self.expr()?;
            let body = self.block(&["elsewhen", "end"])?;
            branches.push((condition, body));
        }
        if self.at_word("else") || self.at_word("elseif") {
            return Err(self
                .expected("`elsewhen` or `end`")
                .help("a `when` has no `else`: its branches are `when c1 ... elsewhen c2 ... end`"));
        }
        self.close_block(start, "when")?;
        self.leave(1);
        Ok(Relation::When { branches, span: start.to(self.prev_span()) })
    }

    /// `reinit(state, value)`.
    fn reinit(&mut self) -> PResult<Relation> {
        let start = self.expect_word("reinit")?;
        self.expect(TokenKind::LParen, "`(`")?;
        let state = self.expr()?;
        self.expect(TokenKind::Comma, "`,` and the new value")?;
        let value = self.expr()?;
        self.expect(TokenKind::RParen, "`)`")?;
        Ok(Relation::Reinit { state, value, span: start.to(self.prev_span()) })
    }

    /// `for i in range ... end`.
    fn for_relation(&mut self) -> PResult<Relation> {
        let start = self.expect_word("for")?;
        self.enter()?;
        let var = self.ident("the loop variable")?;
        self.expect_word("in")?;
        let range = self.range_or_expr()?;
        let body = self.block(&["end"])?;
        self.close_block(start, "for")?;
        self.leave(1);
        Ok(Relation::For { var, range, body, span: start.to(self.prev_span()) })
    }

    /// `switch subject case A ... end ... [default ... end] end`.
    fn switch_relation(&mut self) -> PResult<Relation> {
        let start = self.expect_word("switch")?;
        self.enter()?;
        let subject = self.expr()?;
        let mut cases = Vec::new();
        let mut default = None;
        loop {
            self.skip_semicolons();
            if self.eat_word("case") {
                let case = self.path("an enumeration case")?;
                if self.at(&TokenKind::LParen) && self.nth(1) == &TokenKind::RParen {
                    self.bump();
                    self.bump();
                }
                let body = self.block(&["end"])?;
                self.close_block(start, "case")?;
                cases.push((case, body));
            } else if self.eat_word("default") {
                let body = self.block(&["end"])?;
                self.close_block(start, "default")?;
                default = Some(body);
            } else {
                break;
            }
        }
        self.close_block(start, "switch")?;
        self.leave(1);
        Ok(Relation::Switch { subject, cases, default, span: start.to(self.prev_span()) })
    }

    /// The `end` of a block that `start` opened.
    fn close_block(&mut self, start: Span, what: &str) -> PResult<()> {
        if self.eat_word("end") {
            return Ok(());
        }
        let mut d = self.expected("`end`");
        if self.at(&TokenKind::Eof) || self.at_definition() {
            d = d
                .secondary(start, format!("this `{what}` is not closed"))
                .help(format!("close the `{what}` with `end`"));
        }
        Err(d)
    }

    fn analysis(&mut self, doc: Option<String>, start: Span) -> PResult<AnalysisDef> {
        self.expect_word("analysis")?;
        let name = self.ident("the name of the analysis")?;
        let header = start.to(name.span);
        let mut base: Option<(Path, Vec<Modifier>, Span)> = None;
        let mut parameters = Vec::new();
        let mut model: Option<ComponentDecl> = None;
        loop {
            self.skip_semicolons();
            let doc = self.doc();
            if self.word().is_some_and(|w| SECTION_WORDS.contains(&w)) || self.at(&TokenKind::Eof) {
                break;
            }
            let here = self.span();
            match self.word() {
                Some("extends") => {
                    self.bump();
                    let path = self.path("the analysis to extend, e.g. `TransientAnalysis`")?;
                    let modifiers = if self.at(&TokenKind::LParen) { self.modifiers()? } else { Vec::new() };
                    let span = here.to(self.prev_span());
                    if let Some((_, _, first)) = &base {
                        return Err(Diagnostic::error("an analysis extends exactly one base")
                            .primary(span, "second `extends`")
                            .secondary(*first, "first `extends`"));
                    }
                    self.optional_annotation()?;
                    base = Some((path, modifiers, span));
                }
                Some("parameter" | "structural" | "final") => parameters.push(self.parameter(doc)?),
                Some(_) if matches!(self.nth(1), TokenKind::Eq | TokenKind::ColonColon) => {
                    let decl = self.component_decl(doc)?;
                    if decl.name.name != "model" {
                        return Err(unsupported("components other than `model` in an analysis are", decl.name.span)
                            .help("an analysis simulates one model: `model = MyModel()`"));
                    }
                    if let Some(first) = &model {
                        return Err(Diagnostic::error("the analysis declares `model` twice")
                            .primary(decl.name.span, "second declaration")
                            .secondary(first.name.span, "first declaration"));
                    }
                    model = Some(decl);
                }
                _ => {
                    return Err(self.expected("`extends TransientAnalysis(...)`, `model = ...`, a parameter, or `end`"))
                }
            }
        }
        if self.eat_word("relations") {
            self.skip_semicolons();
            if !self.at_word("metadata") && !self.at_word("end") {
                return Err(unsupported("relations in an analysis are", self.span())
                    .help("put the relations in the model's component"));
            }
        }
        if self.at_word("metadata") {
            self.metadata_section()?;
        }
        if !self.at_word("end") {
            return Err(self.expected("`end`"));
        }
        self.bump();
        self.skip_semicolons();
        let Some((base, base_modifiers, base_span)) = base else {
            return Err(Diagnostic::error(format!("the analysis `{}` extends no analysis", name.name))
                .primary(header, "no `extends`")
                .help("add `extends TransientAnalysis(stop = 10)` to simulate the model"));
        };
        Ok(AnalysisDef { name, doc, header, base, base_modifiers, base_span, parameters, model })
    }

    fn type_alias(&mut self) -> PResult<TypeAlias> {
        let start = self.expect_word("type")?;
        let name = self.ident("the type's name")?;
        self.expect(TokenKind::Eq, "`=`")?;
        if self.at_word("func") {
            return Err(unsupported("function types are", self.span()));
        }
        let base = self.type_ref()?;
        let span = start.to(self.prev_span());
        if self.at_word("metadata") {
            self.metadata_section()?;
        } else {
            self.optional_annotation()?;
        }
        self.skip_semicolons();
        Ok(TypeAlias { name, base, span })
    }

    // ---- expressions ---------------------------------------------------

    pub fn expr(&mut self) -> PResult<Expr> {
        self.enter()?;
        let e = if self.at_word("if") { self.if_expr()? } else { self.ternary()? };
        self.leave(1);
        Ok(e)
    }

    /// An expression, or a range `start:stop`, `start:step:stop`.
    fn range_or_expr(&mut self) -> PResult<Expr> {
        let start = self.expr()?;
        if !self.eat(&TokenKind::Colon) {
            return Ok(start);
        }
        let second = self.expr()?;
        let (step, stop) = if self.eat(&TokenKind::Colon) { (Some(second), self.expr()?) } else { (None, second) };
        let span = start.span.to(stop.span);
        Ok(Expr {
            kind: ExprKind::Range { start: Box::new(start), step: step.map(Box::new), stop: Box::new(stop) },
            span,
        })
    }

    /// `c ? a : b`.
    fn ternary(&mut self) -> PResult<Expr> {
        let condition = self.or_expr()?;
        if !self.eat(&TokenKind::Question) {
            return Ok(condition);
        }
        let then = self.or_expr()?;
        self.expect(TokenKind::Colon, "`:`")?;
        let otherwise = self.expr()?;
        let span = condition.span.to(otherwise.span);
        Ok(Expr {
            kind: ExprKind::If { condition: Box::new(condition), then: Box::new(then), otherwise: Box::new(otherwise) },
            span,
        })
    }

    /// `if c then a elseif d then b else e`.
    fn if_expr(&mut self) -> PResult<Expr> {
        let start = self.expect_word("if")?;
        let condition = self.or_expr()?;
        self.expect_word("then")?;
        let then = self.expr()?;
        let otherwise = if self.at_word("elseif") {
            // `elseif` reads as a nested `if`.
            self.tokens[self.pos].kind = TokenKind::Ident("if".into());
            self.if_expr()?
        } else {
            self.expect_word("else")?;
            self.expr()?
        };
        let span = start.to(otherwise.span);
        Ok(Expr {
            kind: ExprKind::If { condition: Box::new(condition), then: Box::new(then), otherwise: Box::new(otherwise) },
            span,
        })
    }

    /// A chain `a op b op c ...` of one precedence level: one level of
    /// nesting however long it is.
    fn chain(
        &mut self,
        next: fn(&mut Self) -> PResult<Expr>,
        op_of: fn(&TokenKind) -> Option<Result<BinaryOp, &'static str>>,
    ) -> PResult<Expr> {
        let mut first = next(self)?;
        let mut rest: Vec<(BinaryOp, Expr)> = Vec::new();
        let mut entered = false;
        while let Some(op) = op_of(&self.peek().kind) {
            if !entered {
                self.enter()?;
                entered = true;
            }
            self.bump();
            let rhs = next(self)?;
            match op {
                Ok(op) => rest.push((op, rhs)),
                Err(what) => {
                    let lhs = chain_expr(first, std::mem::take(&mut rest));
                    let span = lhs.span.to(rhs.span);
                    first = Expr { kind: ExprKind::Unsupported(what), span };
                }
            }
        }
        if entered {
            self.leave(1);
        }
        Ok(chain_expr(first, rest))
    }

    fn or_expr(&mut self) -> PResult<Expr> {
        self.chain(Self::and_expr, |k| match k {
            TokenKind::Ident(w) if w == "or" => Some(Ok(BinaryOp::Or)),
            TokenKind::OrOr => Some(Ok(BinaryOp::Or)),
            _ => None,
        })
    }

    fn and_expr(&mut self) -> PResult<Expr> {
        self.chain(Self::comparison, |k| match k {
            TokenKind::Ident(w) if w == "and" => Some(Ok(BinaryOp::And)),
            TokenKind::AndAnd => Some(Ok(BinaryOp::And)),
            _ => None,
        })
    }

    /// `a < b`: one comparison (they do not chain).
    fn comparison(&mut self) -> PResult<Expr> {
        let lhs = self.additive()?;
        let op = match self.peek().kind {
            TokenKind::EqEq => BinaryOp::Eq,
            TokenKind::NotEq => BinaryOp::Ne,
            TokenKind::Lt => BinaryOp::Lt,
            TokenKind::Le => BinaryOp::Le,
            TokenKind::Gt => BinaryOp::Gt,
            TokenKind::Ge => BinaryOp::Ge,
            _ => return Ok(lhs),
        };
        self.bump();
        let rhs = self.additive()?;
        if matches!(
            self.peek().kind,
            TokenKind::EqEq | TokenKind::NotEq | TokenKind::Lt | TokenKind::Le | TokenKind::Gt | TokenKind::Ge
        ) {
            return Err(
                unsupported("chained comparisons (`a < b < c`) are", self.span()).help("write `a < b and b < c`")
            );
        }
        let span = lhs.span.to(rhs.span);
        Ok(Expr { kind: ExprKind::Binary { op, lhs: Box::new(lhs), rhs: Box::new(rhs) }, span })
    }

    fn additive(&mut self) -> PResult<Expr> {
        self.chain(Self::multiplicative, |k| match k {
            TokenKind::Plus => Some(Ok(BinaryOp::Add)),
            TokenKind::Minus => Some(Ok(BinaryOp::Sub)),
            TokenKind::DotPlus => Some(Ok(BinaryOp::ElemAdd)),
            TokenKind::DotMinus => Some(Ok(BinaryOp::ElemSub)),
            _ => None,
        })
    }

    fn multiplicative(&mut self) -> PResult<Expr> {
        self.chain(Self::unary, |k| match k {
            TokenKind::Star => Some(Ok(BinaryOp::Mul)),
            TokenKind::Slash => Some(Ok(BinaryOp::Div)),
            TokenKind::DotStar => Some(Ok(BinaryOp::ElemMul)),
            TokenKind::DotSlash => Some(Ok(BinaryOp::ElemDiv)),
            TokenKind::Percent => Some(Err("`%` is")),
            _ => None,
        })
    }

    fn unary(&mut self) -> PResult<Expr> {
        let start = self.span();
        let op = match self.peek().kind {
            TokenKind::Minus => Some(Ok(UnaryOp::Neg)),
            TokenKind::Plus => Some(Ok(UnaryOp::Plus)),
            TokenKind::Bang => Some(Ok(UnaryOp::Not)),
            _ => None,
        };
        let Some(op) = op else { return self.power() };
        self.enter()?;
        self.bump();
        let operand = self.unary()?;
        self.leave(1);
        let span = start.to(operand.span);
        Ok(match op {
            Ok(op) => Expr { kind: ExprKind::Unary { op, operand: Box::new(operand) }, span },
            Err(what) => Expr { kind: ExprKind::Unsupported(what), span },
        })
    }

    fn power(&mut self) -> PResult<Expr> {
        let base = self.postfix()?;
        let op = match self.peek().kind {
            TokenKind::Caret => BinaryOp::Pow,
            TokenKind::DotCaret => BinaryOp::ElemPow,
            _ => return Ok(base),
        };
        self.enter()?;
        self.bump();
        // Right-associative, and `2^-1` is allowed.
        let exponent = self.unary()?;
        self.leave(1);
        let span = base.span.to(exponent.span);
        Ok(Expr { kind: ExprKind::Binary { op, lhs: Box::new(base), rhs: Box::new(exponent) }, span })
    }

    fn postfix(&mut self) -> PResult<Expr> {
        let mut e = self.primary()?;
        let mut levels = 0;
        // Indexing follows a name or a call; `[{` after a value starts
        // metadata. A field follows an index: `links[2].frame_a`.
        loop {
            if self.at(&TokenKind::LBracket)
                && self.nth(1) != &TokenKind::LBrace
                && matches!(
                    e.kind,
                    ExprKind::Name(_) | ExprKind::Call { .. } | ExprKind::Index { .. } | ExprKind::Field { .. }
                )
            {
                self.enter()?;
                levels += 1;
                self.bump();
                let mut indices = Vec::new();
                loop {
                    indices.push(self.range_or_expr()?);
                    if !self.eat(&TokenKind::Comma) {
                        break;
                    }
                }
                self.expect(TokenKind::RBracket, "`,` or `]`")?;
                let span = e.span.to(self.prev_span());
                e = Expr { kind: ExprKind::Index { base: Box::new(e), indices }, span };
            } else if self.at(&TokenKind::Dot)
                && matches!(e.kind, ExprKind::Index { .. } | ExprKind::Field { .. })
                && matches!(self.nth(1), TokenKind::Ident(_))
            {
                self.bump();
                let name = self.ident("a name")?;
                let span = e.span.to(name.span);
                e = Expr { kind: ExprKind::Field { base: Box::new(e), name }, span };
            } else {
                break;
            }
        }
        self.leave(levels);
        Ok(e)
    }

    fn primary(&mut self) -> PResult<Expr> {
        let token = self.peek().clone();
        match &token.kind {
            TokenKind::Number(x) => {
                self.bump();
                Ok(Expr { kind: ExprKind::Number(*x), span: token.span })
            }
            TokenKind::Str(s) => {
                self.bump();
                Ok(Expr { kind: ExprKind::Str(s.clone()), span: token.span })
            }
            TokenKind::LParen => {
                self.bump();
                let inner = self.expr()?;
                self.expect(TokenKind::RParen, "`)`")?;
                Ok(Expr { kind: inner.kind, span: token.span.to(self.prev_span()) })
            }
            TokenKind::LBracket => self.array(),
            TokenKind::Ident(w) if w == "true" || w == "false" => {
                self.bump();
                Ok(Expr { kind: ExprKind::Bool(w == "true"), span: token.span })
            }
            TokenKind::Ident(_) => {
                let path = self.path("a name")?;
                if !self.at(&TokenKind::LParen) {
                    let span = path.span;
                    return Ok(Expr { kind: ExprKind::Name(path), span });
                }
                self.bump();
                let mut args = Vec::new();
                while !self.at(&TokenKind::RParen) {
                    if matches!(self.peek().kind, TokenKind::Ident(_)) && self.nth(1) == &TokenKind::Eq {
                        return Err(unsupported("named arguments in function calls are", self.span()));
                    }
                    args.push(self.expr()?);
                    if !self.eat(&TokenKind::Comma) {
                        break;
                    }
                }
                self.expect(TokenKind::RParen, "`,` or `)`")?;
                let span = path.span.to(self.prev_span());
                Ok(Expr { kind: ExprKind::Call { callee: path, args }, span })
            }
            _ => Err(self.expected("a value (a number, a name, `[...]` or `(...)`)")),
        }
    }

    /// `[a, b, c]`, or a matrix by rows, `[a, b; c, d]` (rows of one
    /// element each, `[a; b]`, make a vector).
    fn array(&mut self) -> PResult<Expr> {
        let open = self.expect(TokenKind::LBracket, "`[`")?.span;
        let mut rows: Vec<Vec<Expr>> = Vec::new();
        let mut items = Vec::new();
        while !self.at(&TokenKind::RBracket) {
            items.push(self.expr()?);
            if self.at_word("for") {
                return Err(unsupported("array comprehensions (`[... for i in ...]`) are", self.span())
                    .help("write the elements out: `[1, 2, 3]`"));
            }
            if self.eat(&TokenKind::Semicolon) {
                rows.push(std::mem::take(&mut items));
                continue;
            }
            if !self.eat(&TokenKind::Comma) {
                break;
            }
        }
        self.expect(TokenKind::RBracket, "`,`, `;` or `]`")?;
        let span = open.to(self.prev_span());
        if rows.is_empty() {
            return Ok(Expr { kind: ExprKind::Array(items), span });
        }
        if !items.is_empty() {
            rows.push(items);
        }
        if rows.iter().all(|row| row.len() == 1) {
            let items = rows.into_iter().flatten().collect();
            return Ok(Expr { kind: ExprKind::Array(items), span });
        }
        let row_span = |row: &[Expr]| row.first().map_or(span, |first| first.span.to(row[row.len() - 1].span));
        let width = rows[0].len();
        if let Some(row) = rows.iter().find(|row| row.len() != width) {
            let n = row.len();
            return Err(Diagnostic::error(format!("the rows of this matrix differ in length: {width} and {n}"))
                .primary(row_span(row), format!("{n} element{}", if n == 1 { "" } else { "s" }))
                .help("give every row (between `;`) the same number of elements"));
        }
        let rows = rows.into_iter().map(|row| Expr { span: row_span(&row), kind: ExprKind::Array(row) }).collect();
        Ok(Expr { kind: ExprKind::Array(rows), span })
    }
}

/// `first op e ...` as one expression: a binary one for one operator, a
/// chain for more.
fn chain_expr(first: Expr, mut rest: Vec<(BinaryOp, Expr)>) -> Expr {
    let Some((_, last)) = rest.last() else { return first };
    let span = first.span.to(last.span);
    let kind = if rest.len() == 1 {
        let (op, rhs) = rest.pop().expect("one operator");
        ExprKind::Binary { op, lhs: Box::new(first), rhs: Box::new(rhs) }
    } else {
        ExprKind::Chain { first: Box::new(first), rest }
    };
    Expr { kind, span }
}

/// The byte offset in `json` of serde_json's 1-based line and column.
fn json_error_offset(json: &str, line: usize, column: usize) -> usize {
    let line_start: usize = json.split_inclusive('\n').take(line.saturating_sub(1)).map(str::len).sum();
    (line_start + column.saturating_sub(1)).min(json.len().saturating_sub(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_a_pendulum_with_metadata_and_an_analysis() {
        let text = r#"
"A pendulum"
example component Pend
  world = MultibodyComponents.World() {"Dyad": {"placement": {"x1": -50}}}
  # a comment
  "the joint"
  joint = MultibodyComponents.Revolute(phi(initial = pi / 3), w(initial = 0)) [{"JuliaSim": {}}]
  parameter L::Length[3] = [1, 0, 0]
relations
  connect(world.frame_b, joint.frame_a) {"Dyad": {"edges": [{"S": 1, "M": [], "E": 2}]}}
  initial joint.phi = 0.3
metadata {}
end

analysis PendSim
  extends Dyad.TransientAnalysis(stop = 5, alg = ODEAlg.Auto())
  model = Pend()
relations
end
"#;
        let file = parse(0, text).unwrap();
        assert_eq!(file.items.len(), 2);
        let Item::Component(c) = &file.items[0] else { panic!() };
        assert_eq!(c.kind, ComponentKind::Example);
        assert_eq!(c.doc.as_deref(), Some("A pendulum"));
        assert_eq!(c.declarations.len(), 3);
        assert_eq!(c.relations.len(), 2);
        let Item::Analysis(a) = &file.items[1] else { panic!() };
        assert_eq!(a.base.text(), "Dyad.TransientAnalysis");
        assert_eq!(a.model.as_ref().unwrap().kind.text(), "Pend");
    }

    #[test]
    fn power_binds_tighter_than_unary_minus() {
        let mut p = Parser { tokens: tokenize(0, "-2^2").unwrap(), pos: 0, depth: 0, text: "-2^2" };
        let e = p.expr().unwrap();
        assert!(matches!(e.kind, ExprKind::Unary { op: UnaryOp::Neg, .. }));
    }

    #[test]
    fn metadata_nests_as_deep_as_json_allows() {
        let metadata = |levels: usize| {
            let json = format!("{}1{}", "{\"a\": ".repeat(levels - 1), "}".repeat(levels - 1));
            format!("component A\n  world = MultibodyComponents.World() {{\"Dyad\": {json}}}\nend\n")
        };
        assert!(parse(0, &metadata(MAX_JSON_DEPTH)).is_ok());
        let d = parse(0, &metadata(MAX_JSON_DEPTH + 1)).unwrap_err();
        assert_eq!(d.message, format!("the metadata is nested more than {MAX_JSON_DEPTH} levels deep"));
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let text = format!("component A\n parameter x::Real = {}1{}\nend", "(".repeat(5000), ")".repeat(5000));
        assert!(parse(0, &text).unwrap_err().message.contains("nested"));
        // A long flat sum nests no deeper than a short one.
        let long = format!("component A\n parameter x::Real = 1{}\nend", " + 1".repeat(100_000));
        assert!(parse(0, &long).is_ok());
        let unary = format!("component A\n parameter x::Real = {}1\nend", "-".repeat(100_000));
        assert!(parse(0, &unary).is_err());
    }
}
