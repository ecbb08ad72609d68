//! How a model takes the plate to follow its command: exactly, or through
//! the rig's drives. A drive is a position servo per plate DoF (natural
//! frequency, damping) on the tick setpoints — position and velocity each
//! interpolated linearly through the tick — plus the feed-forward that
//! `next_command` sends (the tick's mean acceleration). The servo reacts
//! to the gap between that linear reference and the curved path the
//! feed-forward gives, so the plate strays from its command by a few
//! percent of the fast phase's push: enough to move a cycle's mean
//! friction by about 1 % (BENCHMARKS.md, "Forces and curls on extended
//! parts"). Small angles: the DoF are the pose's x, y, θ.

/// The plate's response to its command, as a model assumes it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PlateFollow {
    /// The plate is where the command says, at every instant.
    #[default]
    Exact,
    /// A position servo per DoF with the command's feed-forward.
    Servo { bandwidth_hz: f64, damping: f64 },
}
