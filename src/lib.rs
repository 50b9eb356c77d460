//! declutter compiles a robot-cell scenario into a verified, timed schedule of obstacle
//! removals: which robot removes which blocking object, in what order, along which
//! joint trajectories, so that the target can finally be grasped.
//!
//! The pipeline, in order (a lower stage never imports a higher one):
//! `syntax` (text -> spanned AST) -> `resolve` (AST -> typed `Scenario`) -> `world`
//! (URDF, meshes, kinematics, labelled collision checks) -> `plan` (PRMwO roadmaps,
//! `findPath`, the AND/OR graph) -> `timing` (paths -> timed trajectories, robots at
//! once where safe) -> `schedule` (actions, trajectories, events; YAML/JSON/DOT) ->
//! `verify` (an independent replay in time); `show` draws a world and a schedule as a
//! 3-D page.
//! `diag` holds spans and rendering; `driver` runs the stages for the command line;
//! `import` turns a MoveIt scene into scenario text.

pub mod diag;
pub mod driver;
pub mod import;
pub mod plan;
pub mod resolve;
pub mod schedule;
pub mod show;
pub mod syntax;
pub mod timing;
pub mod verify;
pub mod world;
