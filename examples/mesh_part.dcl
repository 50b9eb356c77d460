// examples/mesh_part.dcl — a machined bracket (an STL mesh in millimetres) behind a capsule-shaped post
scenario "mesh-part"
use "cell.dcl"

object bracket mesh("meshes/bracket.stl") scale 0.001 at (60cm, 0, 0) rot (0, 0, 45deg) {
    grasp web at (5mm, 25mm, 15mm) rot (0, -90deg, 0) approach 5cm
}
object post capsule(radius: 2cm, length: 20cm) at (48cm, 0, 12cm) {
    grasp top at (0, 0, 12cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z
}

target bracket
