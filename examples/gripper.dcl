// examples/gripper.dcl — a parallel gripper that opens to go in and closes on what it
// carries. A can stands between two bottles; its one grasp closes across the row, and the
// open fingers (8.5 cm apart) do not fit between the bottles: both go first. With
// `open [3.6cm]` (the fingers 7.2 cm apart) nothing would need to move.
scenario "gripper"

hand pg {
    urdf "hands/parallel.urdf"             // one finger joint, 0 to 4.25 cm each side
    tcp at (0, 0, 8cm)                     // between the fingertips
}

robot arm {
    urdf "robots/tx90.urdf"
    hand pg
    home [0, -20deg, 110deg, 0, 60deg, 0]
    closed [1cm]                           // for a grasp without a width of its own
}

fixed table box(80cm, 1m, 4cm) at (70cm, 0, -2cm)

object can cylinder(radius: 3.3cm, length: 11.5cm) at (65cm, 0, 5.75cm) {
    // The fingers close along y, across the row, to the can's 6.6 cm.
    grasp top at (0, 0, 3.75cm) rot (180deg, 0, 0) approach 6cm width 6.6cm
}

object left cylinder(radius: 3cm, length: 20cm) at (65cm, 8cm, 10cm) {
    // Along x, clear of the can; no width: `closed` (1 cm) holds it.
    grasp top at (0, 0, 8cm) rot (180deg, 0, 90deg) approach 6cm repeat 2 about z
}

object right cylinder(radius: 3cm, length: 20cm) at (65cm, -8cm, 10cm) {
    grasp top at (0, 0, 8cm) rot (180deg, 0, 90deg) approach 6cm width 6cm repeat 2 about z
}

target can
