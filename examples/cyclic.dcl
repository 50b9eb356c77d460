// examples/cyclic.dcl — infeasible on purpose: two crates that can only be gripped at their
// inner handles, which face each other, so each must go before the other; the target, in a
// fixed bay, is reachable only past one of them
scenario "cyclic"
use "cell.dcl"

// A bay open towards the robots (−x): back and side walls, too tall to reach over.
fixed bay at (68cm, 0, 0) {
    box(2cm, 20cm, 30cm) at (7cm, 0, 15cm)
    box(16cm, 2cm, 30cm) at (0, 9cm, 15cm)
    box(16cm, 2cm, 30cm) at (0, -9cm, 15cm)
    box(16cm, 20cm, 1cm) at (0, 0, 30.5cm)
}
object target_can cylinder(radius: 3.3cm, length: 11.5cm) at (68cm, 0, 5.75cm) {
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}

// Crate `a` closes the bay; crate `b` stands beside it. Each has one handle, on the face
// turned to the other crate, and the 1 cm gap between them is no room for a hand.
object a box(8cm, 16cm, 20cm) at (54cm, 0, 10cm) {
    grasp handle at (0, -8cm, 5cm) rot (-100deg, 0, 0) approach 8cm
}
object b box(8cm, 16cm, 20cm) at (54cm, -17cm, 10cm) {
    grasp handle at (0, 8cm, 5cm) rot (100deg, 0, 0) approach 8cm
}

target target_can
