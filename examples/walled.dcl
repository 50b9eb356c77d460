// examples/walled.dcl — infeasible on purpose: the target stands in a closed fixed cage
scenario "walled"
use "cell.dcl"

// A welded cage on the table: four walls and a roof, nothing removable about it.
fixed cage at (60cm, 0, 0) {
    box(20cm, 1cm, 20cm) at (0, 9.5cm, 10cm)
    box(20cm, 1cm, 20cm) at (0, -9.5cm, 10cm)
    box(1cm, 18cm, 20cm) at (9.5cm, 0, 10cm)
    box(1cm, 18cm, 20cm) at (-9.5cm, 0, 10cm)
    box(20cm, 20cm, 1cm) at (0, 0, 20.5cm)
}

object can cylinder(radius: 3.3cm, length: 11.5cm) at (60cm, 0, 5.75cm) {
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
    grasp side at (0, 0, 1.5cm) rot (0, 100deg, 0) approach 8cm repeat 8 about z
}
// A removable box beside the cage: removing it does not help.
object crate box(15cm, 15cm, 15cm) at (35cm, 0, 7.5cm) {
    grasp top at (0, 0, 7.5cm) rot (180deg, 0, 0) approach 5cm repeat 2 about z
}

target can
