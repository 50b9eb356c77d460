// examples/moveit/tx90_cell.dcl — one TX-90 with its SRDF, for importing MoveIt scenes
hand gripper {
    urdf "../hands/sah.urdf"
    tcp at (0, 0, 15cm)
}
robot arm {
    urdf "../robots/tx90.urdf"
    srdf "../robots/tx90.srdf"       // the package's own self-collision filters
    hand gripper
    home [0, -20deg, 110deg, 0, 60deg, 0]
}
fixed floor box(2m, 2m, 2cm) at (0, 0, -1cm)
