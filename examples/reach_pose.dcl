// examples/reach_pose.dcl — bring r1 to a configuration (its hand pointing down just above
// the table, say to look with a wrist camera); a tote stands where the hand must go
scenario "reach-pose"
use "cell.dcl"

object tote box(30cm, 40cm, 20cm) at (66cm, -20cm, 10cm) {
    grasp top at (0, 0, 10cm) rot (180deg, 0, 0) approach 5cm repeat 2 about z
}
object ball sphere(radius: 6cm) at (40cm, 20cm, 6cm) {
    grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z for sah
}

// The TCP ends at about (68cm, -20cm, 16cm), pointing down.
target r1 at [20deg, 60deg, 70deg, 0, 50deg, 0]
