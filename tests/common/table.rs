//! A generated scene shared by the tests and the benches: `n` red cans on a grid
//! around a yellow target that may only be grasped from the side, so its nearest
//! neighbours stand in the way. The gaps between cans (1.9 cm) are narrower than one
//! planner step at the arm's reach, which makes the scene a test of certification too.

use std::path::{Path, PathBuf};

/// The scenario text, using the cell at `cell` (an absolute path).
pub fn can_table_text(n: usize, cell: &Path) -> String {
    let mut text = format!("scenario \"table-{n}\"\nuse \"{}\"\n\n", cell.display());
    text.push_str(
        "object target cylinder(radius: 3.3cm, length: 11.5cm) at (60cm, 0, 5.75cm) {\n    \
         grasp side at (0, 0, 0) rot (0, 100deg, 0) approach 8cm repeat 8 about z\n}\n",
    );
    let spacing = 0.085;
    let mut cells: Vec<(i32, i32)> = (-8..=8).flat_map(|i| (-8..=8).map(move |j| (i, j))).collect();
    cells.retain(|&(i, j)| (i, j) != (0, 0));
    cells.sort_by_key(|&(i, j)| (i * i + j * j, i, j));
    for (k, (i, j)) in cells.into_iter().take(n).enumerate() {
        let (x, y) = (0.6 + i as f64 * spacing, j as f64 * spacing);
        text.push_str(&format!(
            "object can{k} cylinder(radius: 3.3cm, length: 11.5cm) at ({x:.3}, {y:.3}, 5.75cm) {{\n    \
             grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z\n}}\n"
        ));
    }
    text.push_str("target target\n");
    text
}

/// Writes the scene into `dir` and returns its path.
pub fn can_table(n: usize, dir: &Path) -> PathBuf {
    let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cell.dcl");
    let path = dir.join(format!("table_{n}.dcl"));
    std::fs::write(&path, can_table_text(n, &cell)).expect("scene written");
    path
}
