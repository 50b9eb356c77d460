//! Syntax: the text of one `.dcl` file -> a spanned AST ([`ast::File`]).
//!
//! No I/O: `use` files are read by `resolve`. The grammar (`grammar/declutter.pest`) is
//! flat, so no input can exhaust the stack; the parser stops at the first place the
//! text departs from the grammar and says, in words, what it expected there.

pub mod ast;
mod error;
mod expected;
mod names;
mod parser;
mod recover;

pub use error::SyntaxError;
pub use names::did_you_mean;
pub use recover::{parse, parse_recovering};
