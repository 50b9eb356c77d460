// examples/mesh_part.dcl — a machined bracket (an STL mesh in millimetres) behind a capsule-shaped post
scenario "mesh-part"
use "cell.dcl"

object bracket mesh("meshes/bracket.stl") scale 0.001 at (60cm, 0, 0) rot (0, 0, 45deg) {
    // From above, across the short leg (the mesh spans 60 x 40 x 30 mm from its origin).
    grasp web at (5mm, 25mm, 30mm) rot (180deg, 0, 0) approach 5cm
    grasp web_turned at (5mm, 25mm, 30mm) rot (180deg, 0, 90deg) approach 5cm
    grasp leg at (35mm, 5mm, 30mm) rot (180deg, 0, 90deg) approach 5cm
}
object post capsule(radius: 2cm, length: 26cm) at (54cm, 2cm, 15cm) {
    grasp top at (0, 0, 15cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z
}

target bracket
