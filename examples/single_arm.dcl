// examples/single_arm.dcl — one arm, a shelf, and a mug hidden behind a cereal box
scenario "single-arm"

hand gripper {
    urdf "hands/sah.urdf"
    tcp at (0, 0, 15cm)
}

robot arm {
    urdf "robots/tx90.urdf"
    base at (0, 0, 40cm)                  // on a pedestal level with the shelf board
    hand gripper
    home [0, -30deg, 100deg, 0, 70deg, 0]
    allow_contact "base_link" "link_1"     // a pair the collision checker ignores
}

fixed shelf at (70cm, 0, 0) {
    box(40cm, 30cm, 2cm) at (0, 0, 40cm)      // the board, a narrow bay
    box(40cm, 2cm, 60cm) at (0, 16cm, 30cm)   // the two sides, 20 cm above the board
    box(40cm, 2cm, 60cm) at (0, -16cm, 30cm)
}

object cereal box(6cm, 20cm, 28cm) at (58cm, 0, 55cm) {
    grasp front at (-3cm, 0, 0) rot (0, 90deg, 0) approach 5cm
    grasp top at (0, 0, 14cm) rot (180deg, 0, 0) approach 5cm repeat 2 about z
}

object mug cylinder(radius: 4cm, length: 10cm) at (75cm, 0, 46cm) {
    grasp side at (-4cm, 0, 2cm) rot (0, 110deg, 0) approach 4cm repeat 8 about z
}

planner {
    seed 7
    objective fewest_vertices
    time_budget 30s
    first_path true
}

target mug
