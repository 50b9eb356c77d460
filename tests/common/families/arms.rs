//! The arms the families run on: each one's cell text (robot, hand, table), its home and
//! the size of what it reaches into a shelf or box with.

use std::path::Path;

/// The arms the families run on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Arm {
    /// The TX-90 (`tx90/tx90.urdf`) with the `sah` hand of the examples.
    Tx90,
    /// The Panda's sphere model (`panda/vamp/panda_spherized.urdf`), its own hand.
    Panda,
    /// The UR5 of `example-robot-data` (`ur5_joint_limited_robot.urdf`, joints within
    /// ±180°, its mesh collision model), no hand: the tool frame is its `tool0` flange.
    Ur5,
    /// The Panda's mesh model of `example-robot-data` with its SRDF and its own hand,
    /// the tool frame at `panda_hand_tcp` between the fingertips.
    PandaMesh,
}

/// Every arm, in the order the tables list them.
pub const ARMS: [Arm; 4] = [Arm::Tx90, Arm::Panda, Arm::Ur5, Arm::PandaMesh];

impl Arm {
    /// Mixed into every problem's seed: a new arm draws its own problems, and the old
    /// arms' stay as they were.
    pub fn key(self) -> u64 {
        match self {
            Arm::Tx90 => 0,
            Arm::Panda => 100,
            Arm::Ur5 => 200,
            Arm::PandaMesh => 300,
        }
    }

    /// The prefix of a problem's file name.
    pub fn prefix(self) -> &'static str {
        match self {
            Arm::Tx90 => "",
            Arm::Panda => "panda_",
            Arm::Ur5 => "ur5_",
            Arm::PandaMesh => "panda_mesh_",
        }
    }

    /// A collision-free, tucked home (`tests/families.rs` checks it on the table).
    pub fn home(self) -> &'static str {
        match self {
            Arm::Tx90 => "[0, -20deg, 110deg, 0, 60deg, 0]",
            Arm::Panda | Arm::PandaMesh => "[0, -45deg, 0, -135deg, 0, 90deg, 45deg]",
            Arm::Ur5 => "[0, -110deg, 100deg, -80deg, -90deg, 0]",
        }
    }

    /// Width of what enters a shelf or box (hand or wrist) across its approach, and its
    /// length from the wrist to the tool frame (metres): the new families' sizes scale
    /// with these.
    pub fn hand(self) -> (f64, f64) {
        match self {
            // The `sah` hand is 10 cm across and 16 cm long, on a 15 cm wrist.
            Arm::Tx90 => (0.15, 0.16),
            // The Panda's hand is 20 cm across its fingers' travel, 10 cm to the tcp.
            Arm::Panda | Arm::PandaMesh => (0.2, 0.11),
            // No hand: the UR5's wrist enters, 20 cm across its offset links, its
            // forearm some 6 cm above the flange when the flange points down.
            Arm::Ur5 => (0.2, 0.06),
        }
    }

    /// The robot, its hand and the table, as scenario text.
    pub fn cell(self, robots: &Path) -> String {
        let erd = "panda/example-robot-data/robots/panda_description";
        match self {
            Arm::Tx90 => {
                let hands = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hands/sah.urdf");
                format!(
                    "hand sah {{\n    urdf \"{}\"\n    tcp at (0, 0, 16cm)\n}}\n\
                     robot arm {{\n    urdf \"{}\"\n    hand sah\n    home [0, -20deg, 110deg, 0, 60deg, 0]\n}}\n\
                     fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
                    hands.display(),
                    robots.join("tx90/tx90.urdf").display()
                )
            }
            Arm::Panda => format!(
                "robot arm {{\n    urdf \"{}\"\n    home [0, -45deg, 0, -135deg, 0, 90deg, 45deg]\n}}\n\
                 fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
                robots.join("panda/vamp/panda_spherized.urdf").display()
            ),
            Arm::Ur5 => format!(
                "robot arm {{\n    urdf \"{}\"\n    home {}\n}}\n\
                 fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
                robots.join("ur5/example-robot-data/robots/ur_description/urdf/ur5_joint_limited_robot.urdf").display(),
                self.home()
            ),
            Arm::PandaMesh => format!(
                "robot arm {{\n    urdf \"{}\"\n    srdf \"{}\"\n    home {}\n}}\n\
                 fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
                robots.join(erd).join("urdf/panda.urdf").display(),
                robots.join(erd).join("srdf/panda.srdf").display(),
                self.home()
            ),
        }
    }
}
