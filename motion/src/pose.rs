//! Plate pose, twist and one sample of the motion.

/// (sin θ, cos θ), by Taylor polynomials for the angles plate motion uses
/// (|θ| < 0.25: truncation < 1e-20 relative, so the result is within an ulp
/// or two of libm's, several times faster and without a call); exactly
/// (0, 1) at θ = 0. Horner form with the reciprocal factorials as constants:
/// a division per term would cost more than the whole polynomial.
#[inline(always)]
pub fn sin_cos(theta: f64) -> (f64, f64) {
    const S: [f64; 6] =
        [-1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362_880.0, -1.0 / 39_916_800.0, 1.0 / 6_227_020_800.0];
    const C: [f64; 7] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
    ];
    if theta.abs() < 0.25 {
        let t2 = theta * theta;
        let ps = S.iter().rev().fold(0.0, |acc, &k| acc * t2 + k);
        let pc = C.iter().rev().fold(0.0, |acc, &k| acc * t2 + k);
        (theta + theta * t2 * ps, 1.0 + t2 * pc)
    } else {
        libm_sin_cos(theta)
    }
}

/// Out of line and cold: LLVM treats `f64::sin_cos` as speculatable and
/// otherwise evaluates it on every call, alongside the polynomial.
#[cold]
#[inline(never)]
fn libm_sin_cos(theta: f64) -> (f64, f64) {
    theta.sin_cos()
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

#[cfg(test)]
mod tests {
    use super::sin_cos;

    /// The polynomials agree with libm to an ulp or two over their whole
    /// range, on both sides of the switch, and are exact at 0.
    #[test]
    fn sin_cos_matches_libm() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let mut worst: f64 = 0.0;
        for i in -30_000..=30_000 {
            let theta = i as f64 * 1e-5 + 1.234_567e-7;
            let (s, c) = sin_cos(theta);
            let (sl, cl) = theta.sin_cos();
            worst = worst.max((s - sl).abs() / sl.abs().max(f64::MIN_POSITIVE)).max((c - cl).abs());
        }
        assert!(worst <= 4.0 * f64::EPSILON, "worst relative error {worst:e}");
    }
}
