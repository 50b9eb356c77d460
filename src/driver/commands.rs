//! One function per CLI command. Each is filled in by the issue that builds its stage.

use std::path::Path;

use super::{CompileOptions, GlobalOptions, EXIT_INPUT};

fn not_yet(what: &str) -> u8 {
    eprintln!("error: `declutter {what}` is not built yet");
    EXIT_INPUT
}

pub fn check(file: &Path, g: &GlobalOptions) -> u8 {
    super::front::check(file, g)
}
pub fn resolve(file: &Path, g: &GlobalOptions) -> u8 {
    super::front::resolve(file, g)
}
pub fn compile(_file: &Path, _g: &GlobalOptions, _o: &CompileOptions) -> u8 {
    not_yet("compile")
}
pub fn verify(file: &Path, schedule: &Path, g: &GlobalOptions) -> u8 {
    super::verify_cmd::verify(file, schedule, g)
}
pub fn graph(_file: &Path, _g: &GlobalOptions, _seed: Option<u64>) -> u8 {
    not_yet("graph")
}
