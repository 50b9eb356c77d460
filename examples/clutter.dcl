// examples/clutter.dcl — a cluttered table: a target can among 24 other objects
// (cans, boxes and balls on a 9 cm grid), reachable by either arm once its neighbours go
scenario "clutter"
use "cell.dcl"

// The target: side grasps only.
object target cylinder(radius: 3.3cm, length: 11.5cm) at (56cm, 0, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}

object can1 cylinder(radius: 3.3cm, length: 11.5cm) at (38cm, -18cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box2 box(6cm, 6cm, 8cm) at (38cm, -9cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball3 sphere(radius: 3cm) at (38cm, 0cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can4 cylinder(radius: 3.3cm, length: 11.5cm) at (38cm, 9cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box5 box(6cm, 6cm, 8cm) at (38cm, 18cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball6 sphere(radius: 3cm) at (47cm, -18cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can7 cylinder(radius: 3.3cm, length: 11.5cm) at (47cm, -9cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box8 box(6cm, 6cm, 8cm) at (47cm, 0cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball9 sphere(radius: 3cm) at (47cm, 9cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can10 cylinder(radius: 3.3cm, length: 11.5cm) at (47cm, 18cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box11 box(6cm, 6cm, 8cm) at (56cm, -18cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball12 sphere(radius: 3cm) at (56cm, -9cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box13 box(6cm, 6cm, 8cm) at (56cm, 9cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball14 sphere(radius: 3cm) at (56cm, 18cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can15 cylinder(radius: 3.3cm, length: 11.5cm) at (65cm, -18cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box16 box(6cm, 6cm, 8cm) at (65cm, -9cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball17 sphere(radius: 3cm) at (65cm, 0cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can18 cylinder(radius: 3.3cm, length: 11.5cm) at (65cm, 9cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box19 box(6cm, 6cm, 8cm) at (65cm, 18cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball20 sphere(radius: 3cm) at (74cm, -18cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can21 cylinder(radius: 3.3cm, length: 11.5cm) at (74cm, -9cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object box22 box(6cm, 6cm, 8cm) at (74cm, 0cm, 4cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object ball23 sphere(radius: 3cm) at (74cm, 9cm, 3cm) {
    grasp top at (0, 0, 3cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}
object can24 cylinder(radius: 3.3cm, length: 11.5cm) at (74cm, 18cm, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 14cm repeat 4 about z
}

target target
