// examples/split_lid.dcl — a crate closed by two half lids, one reached best by each arm:
// both must go before the can inside can be taken, and both arms reach over the crate.
scenario "split-lid"
use "cell.dcl"

fixed crate at (55cm, 0, 0) {
    box(30cm, 30cm, 1cm)  at (0, 0, 0.5cm)
    box(30cm, 1cm, 20cm)  at (0, 14.5cm, 10cm)
    box(30cm, 1cm, 20cm)  at (0, -14.5cm, 10cm)
    box(1cm, 30cm, 20cm)  at (14.5cm, 0, 10cm)
    box(1cm, 30cm, 20cm)  at (-14.5cm, 0, 10cm)
}

object can cylinder(radius: 3.3cm, length: 11.5cm) at (55cm, 0, 6.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
}

// Each half covers half the crate and rests on its rim.
object lid_a at (55cm, -8cm, 20.5cm) {
    box(32cm, 16cm, 1cm)
    box(12cm, 2cm, 2cm) at (0, 0, 1.5cm)                 // the handle
    grasp handle at (0, 0, 2.5cm) rot (180deg, 0, 0) approach 6cm repeat 2 about z
}
object lid_b at (55cm, 8cm, 20.5cm) {
    box(32cm, 16cm, 1cm)
    box(12cm, 2cm, 2cm) at (0, 0, 1.5cm)
    grasp handle at (0, 0, 2.5cm) rot (180deg, 0, 0) approach 6cm repeat 2 about z
}

target can
