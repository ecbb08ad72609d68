//! Plate pose, twist and one sample of the motion.

/// (sin θ, cos θ), with a short Taylor series for the small angles of plate
/// motion (|θ| < 0.02: truncation < 1e-20, about 5× faster than libm);
/// exactly (0, 1) at θ = 0.
#[inline]
pub fn sin_cos(theta: f64) -> (f64, f64) {
    if theta.abs() < 0.02 {
        let t2 = theta * theta;
        let s = theta * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0)));
        let c = 1.0 - t2 / 2.0 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0)));
        (s, c)
    } else {
        theta.sin_cos()
    }
}

/// Plate pose: translation of the plate origin (its center of mass) and
/// rotation, relative to home. Home is all zeros.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

/// Rate of a pose (velocity) or its second derivative (acceleration):
/// linear part of the plate origin and angular part.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Twist {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

impl Pose {
    pub const HOME: Pose = Pose { x: 0.0, y: 0.0, theta: 0.0 };

    /// World position of a point given in plate coordinates.
    #[inline]
    pub fn to_world(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = sin_cos(self.theta);
        [self.x + c * p[0] - s * p[1], self.y + s * p[0] + c * p[1]]
    }

    /// Plate coordinates of a world point.
    #[inline]
    pub fn to_plate(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = sin_cos(self.theta);
        let (dx, dy) = (p[0] - self.x, p[1] - self.y);
        [c * dx + s * dy, -s * dx + c * dy]
    }

    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.theta.is_finite()
    }
}

impl Twist {
    /// Velocity of the plate material at world point `p` when the plate is at
    /// `pose` and moves with this twist: v_O + ω·R90(p − O).
    #[inline]
    pub fn at(&self, pose: &Pose, p: [f64; 2]) -> [f64; 2] {
        [self.x - self.theta * (p[1] - pose.y), self.y + self.theta * (p[0] - pose.x)]
    }

    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.theta.is_finite()
    }
}

/// The motion at one instant.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlateSample {
    pub pose: Pose,
    pub velocity: Twist,
    pub acceleration: Twist,
    /// Slot index in play order (0 when the motion is empty).
    pub slot: u16,
    /// True on the first tick of a cycle (pose exactly home there).
    pub cycle_start: bool,
}
