//! Resolve: spanned AST -> typed [`Scenario`].
//!
//! Names become ids, quantities become SI units, `use` files are inlined, poses are
//! composed into the world frame and grasp `repeat`s are expanded.

mod scenario;

pub use scenario::*;
