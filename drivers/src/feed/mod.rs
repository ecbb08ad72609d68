//! A production feed cell around the simulator: parts of a recipe's
//! classes arrive at random in the infeed region, and a simulated robot
//! takes a part lying at a free pick pose of its class, within tolerance,
//! settled, with no other part in the gripper's clearance. The cell steps
//! where the simulator steps (every millisecond of simulated time), on a
//! pool of parts built once: arriving places a parked part, picking parks
//! it again, so nothing allocates.

mod cell;
mod changeover;
mod counts;
mod infeed;
mod pick_mailbox;
mod robot;
mod robot_mode;
mod status;
mod status_port;

pub use cell::{FeedCell, FeedError};
pub use changeover::RecipeMailbox;
pub use counts::{FeedCounts, PickRecord};
pub use pick_mailbox::PickMailbox;
pub use robot_mode::{RobotMode, ZONE_MARGIN_M};
pub use status::STUCK_AFTER_S;
