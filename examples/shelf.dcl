// examples/shelf.dcl — a low shelf on the table: two cans in front hide a third at the back
scenario "shelf"
use "cell.dcl"

// Fixed boards: a top 26 cm above the table and two sides; open at the front (−x).
fixed shelf at (68cm, 0, 0) {
    box(30cm, 40cm, 2cm) at (0, 0, 27cm)      // the top board
    box(30cm, 2cm, 28cm) at (0, 21cm, 14cm)   // the sides
    box(30cm, 2cm, 28cm) at (0, -21cm, 14cm)
    box(2cm, 44cm, 28cm) at (16cm, 0, 14cm)   // the back
}

// The target, at the back. Under the top board only side grasps fit.
object back cylinder(radius: 3.3cm, length: 11.5cm) at (74cm, 0, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object front_left cylinder(radius: 3.3cm, length: 11.5cm) at (62cm, -5cm, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
object front_right cylinder(radius: 3.3cm, length: 11.5cm) at (62cm, 5cm, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}

target back
