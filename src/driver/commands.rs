//! One function per CLI command. Each is filled in by the issue that builds its stage.

use std::path::Path;

use super::{CompileOptions, GlobalOptions, GraphOptions, ShowOptions};

pub fn check(file: &Path, g: &GlobalOptions) -> u8 {
    super::front::check(file, g)
}
pub fn resolve(file: &Path, g: &GlobalOptions) -> u8 {
    super::front::resolve(file, g)
}
pub fn compile(file: &Path, g: &GlobalOptions, o: &CompileOptions) -> u8 {
    super::compile::compile(file, g, o)
}
pub fn verify(file: &Path, schedule: &Path, g: &GlobalOptions, o: &super::VerifyOptions) -> u8 {
    super::verify_cmd::verify(file, schedule, g, o)
}
pub fn graph(file: &Path, g: &GlobalOptions, o: &GraphOptions) -> u8 {
    super::compile::graph(file, g, o)
}
pub fn show(file: &Path, g: &GlobalOptions, o: &ShowOptions) -> u8 {
    super::show_cmd::show(file, g, o)
}
