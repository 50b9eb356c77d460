// examples/three_arm.dcl — the dual-arm cell plus a third TX-90 across the table: the target
// stands near r3, ringed by five cans
scenario "three-arm"
use "cell.dcl"

hand sah3 {
    urdf "hands/sah.urdf"
    tcp at (0, 0, 16cm)
}
robot r3 {
    urdf "robots/tx90.urdf"
    base at (1.2m, 0, 0) rot (0, 0, 180deg)   // across the table, facing −x
    hand sah3
    home [0, -20deg, 110deg, 0, 60deg, 0]
}

object target cylinder(radius: 3.3cm, length: 11.5cm) at (76cm, 0, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object left cylinder(radius: 3.3cm, length: 11.5cm) at (81.7cm, -5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object right cylinder(radius: 3.3cm, length: 11.5cm) at (81.7cm, 5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object middle cylinder(radius: 3.3cm, length: 11.5cm) at (85.5cm, 0, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object front_left cylinder(radius: 3.3cm, length: 11.5cm) at (70.3cm, -5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object front_right cylinder(radius: 3.3cm, length: 11.5cm) at (70.3cm, 5.7cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}

target target
