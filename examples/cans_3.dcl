// examples/cans_3.dcl — the paper's Example 2: a yellow can among three red cans
scenario "cans-3"
use "cell.dcl"

// O0, the yellow can: side grasps only, eight around its axis. The TCP's +z points into the
// can, tilted 10° down so that the retreat lifts the can off the table.
object yellow cylinder(radius: 3.3cm, length: 11.5cm) at (60cm, 0, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
// O1–O3, red cans: four top grasps and eight side grasps each. O2 and O3 stand 8 cm from
// O0, towards r1 and towards r2; O1 behind it.
object red1 cylinder(radius: 3.3cm, length: 11.5cm) at (68cm, 0, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red2 cylinder(radius: 3.3cm, length: 11.5cm) at (54.3cm, -5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red3 cylinder(radius: 3.3cm, length: 11.5cm) at (54.3cm, 5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}

planner {
    objective fewest_vertices    // the paper's rule
}

target yellow
