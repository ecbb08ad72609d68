//! What the simulated robot takes: UPM's presented parts, or the
//! feeders' any part lying still in the zone.

use serde::{Deserialize, Serialize};

/// What the robot takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RobotMode {
    /// A part presented at a pick pose of its class (UPM's way).
    #[default]
    AtPose,
    /// Any part lying still and isolated in the pick zone (the pick poses'
    /// bounding box grown by [`ZONE_MARGIN_M`]), at whatever angle: the
    /// flexible feeders' shake-and-pick.
    AnyInZone,
    /// The robot is outside the simulator (e.g. on OPC UA through `upm
    /// line`): a part ready at a pose leaves when a pick of it is posted
    /// ([`crate::feed::PickMailbox`]).
    External,
}

/// How far the pick zone reaches beyond the pick poses.
pub const ZONE_MARGIN_M: f64 = 0.1;
