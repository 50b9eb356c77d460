// examples/cans_5.dcl — the paper's Example 3: a yellow can among five red cans
scenario "cans-5"
use "cell.dcl"

// O0, the yellow can: side grasps only. At the edge of r1's reach, r1 can take it only
// from the side facing r1.
object yellow cylinder(radius: 3.3cm, length: 11.5cm) at (70cm, 20cm, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
// O1–O5, red cans. O5 carries grasps for the SDH2 hand only: in the paper r1 cannot
// reach it although it lies on r1's path; on a flat table a can in r1's way is within
// r1's reach (see book/src/paper-examples-notes.md). The top grasps lift 14 cm, clear of
// the neighbours.
object red1 cylinder(radius: 3.3cm, length: 11.5cm) at (63cm, 24.9cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red2 cylinder(radius: 3.3cm, length: 11.5cm) at (52cm, 15.8cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red3 cylinder(radius: 3.3cm, length: 11.5cm) at (70.7cm, 28.5cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red4 cylinder(radius: 3.3cm, length: 11.5cm) at (66.6cm, 10.6cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object red5 cylinder(radius: 3.3cm, length: 11.5cm) at (60.9cm, 15.8cm, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z for sdh2
}

planner {
    objective fewest_vertices    // the paper's rule
}

target yellow
