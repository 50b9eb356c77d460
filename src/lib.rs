//! declutter compiles a robot-cell scenario into a verified schedule of obstacle
//! removals: which robot removes which blocking object, in what order, along which
//! joint paths, so that the target can finally be grasped.
//!
//! The modules are the pipeline, in order; a lower one never imports a higher one.

pub mod diag;
pub mod plan;
pub mod resolve;
pub mod syntax;
pub mod world;

pub mod driver;
