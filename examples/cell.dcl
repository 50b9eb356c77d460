// examples/cell.dcl — the dual-arm cell, shared by several scenarios
hand sah {
    urdf "hands/sah.urdf"            // rigid collision model of the closed hand, in the flange frame
    tcp at (0, 0, 16cm)              // the grasp frame in the flange frame; its +z points into the object
}
hand sdh2 {
    urdf "hands/sdh2.urdf"
    tcp at (0, 0, 18cm) rot (0, 0, 90deg)
}
robot r1 {
    urdf "robots/tx90.urdf"          // paths are relative to the file that names them
    base at (0, -50cm, 0)
    hand sah                         // attached to the URDF's last link unless `flange "link_name"` says otherwise
    home [0, -20deg, 110deg, 0, 60deg, 0]
}
robot r2 {
    urdf "robots/tx90.urdf"
    base at (0, 50cm, 0) rot (0, 0, 0)
    hand sdh2
    home [0, -20deg, 110deg, 0, 60deg, 0]
    drop [90deg, 0, 90deg, 0, 45deg, 0]  // optional: where removed objects are released (default: home)
}
fixed table box(1.4m, 1.6m, 4cm) at (60cm, 0, -2cm)
planner {
    seed 1
    max_samples 5000
    resolution 2deg                  // largest joint step the local planner takes unchecked
    objective fewest_removals        // or fewest_vertices (the paper's rule)
}
