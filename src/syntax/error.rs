//! Syntax errors: what the grammar expected at the first place the text departs from it.

use miette::Diagnostic;
use thiserror::Error;

use crate::diag::{Located, Span};

#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum SyntaxError {
    /// The text departs from the grammar here.
    #[error("expected {expected}, found {found}")]
    #[diagnostic(code(declutter::syntax::expected))]
    Expected {
        expected: String,
        found: String,
        #[label("{label}")]
        span: Span,
        label: String,
        /// The `{` still open where a `}` was expected.
        #[label("this `{{` is not closed")]
        open_brace: Option<Span>,
        #[help]
        help: Option<String>,
    },
    /// The parse tree did not have the shape the grammar promises (a bug in declutter).
    #[error("internal error: unexpected parse tree")]
    #[diagnostic(code(declutter::syntax::internal), help("this is a bug in declutter; please report it"))]
    Internal {
        #[label("while reading this")]
        span: Span,
    },
}

impl Located for SyntaxError {
    fn primary_span(&self) -> Option<Span> {
        match self {
            SyntaxError::Expected { span, .. } | SyntaxError::Internal { span } => Some(*span),
        }
    }
}
