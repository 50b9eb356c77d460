// examples/reach_pose.dcl — bring r1 to a configuration; two boxes sit in its way
scenario "reach-pose"
use "cell.dcl"

object tote box(30cm, 40cm, 15cm) at (45cm, -30cm, 7.5cm) {
    grasp top at (0, 0, 7.5cm) rot (180deg, 0, 0) approach 5cm repeat 2 about z
}
object ball sphere(radius: 6cm) at (40cm, -10cm, 6cm) {
    grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z for sah
}

target r1 at [-30deg, 40deg, 60deg, 0, 80deg, 0]
