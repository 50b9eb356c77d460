//! `check`'s output stays readable: past three warnings of one kind, the rest are
//! counted in one line unless `--verbose` asks for every one.

use std::path::Path;
use std::process::Command;

fn check(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter")).arg("--no-color").args(args).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn repeated_warnings_are_grouped_unless_verbose() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("check_output");
    std::fs::create_dir_all(&dir).unwrap();
    let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cell.dcl");
    // Five cans 3 m away, out of every arm's reach, and one the arms can grasp.
    let mut text = format!("scenario \"far\"\nuse \"{}\"\n", cell.display());
    for k in 0..5 {
        text.push_str(&format!(
            "object far{k} cylinder(radius: 3cm, length: 12cm) at (3m, {}cm, 6cm) {{\n    grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm\n}}\n",
            k * 10
        ));
    }
    text.push_str("object near cylinder(radius: 3cm, length: 12cm) at (60cm, 0, 6cm) {\n    grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z\n}\ntarget near\n");
    let file = dir.join("far.dcl");
    std::fs::write(&file, text).unwrap();

    let (code, grouped) = check(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{grouped}");
    assert_eq!(grouped.matches("declutter::world::ungraspable").count(), 3 + 1, "{grouped}");
    assert!(
        grouped.contains("note: 2 more `declutter::world::ungraspable` warnings not shown (--verbose shows them)"),
        "{grouped}"
    );

    let (code, all) = check(&["check", "--verbose", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{all}");
    assert_eq!(all.matches("declutter::world::ungraspable").count(), 5, "{all}");
    assert!(!all.contains("not shown"), "{all}");
}

#[test]
fn an_ungraspable_object_says_why_robot_by_robot() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("check_output");
    std::fs::create_dir_all(&dir).unwrap();
    let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cell.dcl");
    // A plate just over the can: every top grasp puts the hand into it.
    let text = format!(
        "scenario \"plate\"\nuse \"{}\"\nfixed plate box(30cm, 30cm, 2cm) at (60cm, 0, 15cm)\n\
         object can cylinder(radius: 3cm, length: 12cm) at (60cm, 0, 6cm) {{\n    \
         grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z\n}}\n\
         object far cylinder(radius: 3cm, length: 12cm) at (3m, 0, 6cm) {{\n    \
         grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm\n}}\ntarget far\n",
        cell.display()
    );
    let file = dir.join("plate.dcl");
    std::fs::write(&file, text).unwrap();
    let (code, out) = check(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
    let flat = out.split_whitespace().collect::<Vec<_>>().join(" ");
    for r in ["r1", "r2"] {
        assert!(flat.contains(&format!("{r}: every inverse-kinematics solution collides (link")), "{flat}");
        assert!(flat.contains(&format!("{r}: out of reach: the nearest grasp is 3.")), "{flat}");
    }
    assert!(flat.contains("hits fixed body `plate`"), "{flat}");
}
