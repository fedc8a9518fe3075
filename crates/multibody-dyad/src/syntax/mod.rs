//! Syntax: source files, their tokens, and the tree the parser reads from
//! them. Nothing here knows what a name means.

pub mod ast;
pub mod lexer;
pub mod parser;
pub mod source;
