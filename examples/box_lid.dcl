// examples/box_lid.dcl — the paper's Example 1: a can in a crate whose lid blocks every top grasp
scenario "box-lid"
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

object lid at (55cm, 0, 20.5cm) {
    box(32cm, 32cm, 1cm)
    box(12cm, 2cm, 2cm) at (0, 0, 1.5cm)                 // the handle
    grasp middle at (0, 0, 2.5cm) rot (180deg, 0, 0) approach 6cm repeat 2 about z
    grasp left   at (-4cm, 0, 2.5cm) rot (180deg, 0, 0) approach 6cm repeat 2 about z for sah, sdh2
    grasp right  at (4cm, 0, 2.5cm) rot (180deg, 0, 0) approach 6cm repeat 2 about z
}

target can
