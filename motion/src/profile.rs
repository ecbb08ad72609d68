//! Piecewise-linear angular-velocity profile of one slot.
//!
//! Every knot lies on a motor tick except the mid-slot reversal, which lies
//! inside one straight segment between two ticks. So a plate that holds a
//! constant acceleration over each tick (zero-order-held force, or a driver
//! interpolating the 10 kHz setpoints linearly) reproduces the profile
//! exactly: the same angles and velocities at every tick and the reversal at
//! exactly t_s.

/// Most knots of one slot profile.
pub const MAX_KNOTS: usize = 12;

/// Knots (time, angular velocity) and the angle swept up to each knot.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Profile {
    pub t: [f64; MAX_KNOTS],
    pub w: [f64; MAX_KNOTS],
    pub theta: [f64; MAX_KNOTS],
    pub n: usize,
    /// dω/dt of the segment starting at each knot, computed once here
    /// rather than divided out at every sample.
    alpha: [f64; MAX_KNOTS],
}

/// Angle, angular velocity and angular acceleration at one instant.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ProfilePoint {
    pub theta: f64,
    pub omega: f64,
    pub alpha: f64,
}

impl Profile {
    /// Build from knots; angles are integrated exactly (trapezoids).
    pub(crate) fn from_knots(knots: &[(f64, f64)]) -> Self {
        let mut p = Profile { n: knots.len().min(MAX_KNOTS), ..Profile::default() };
        for (i, &(t, w)) in knots.iter().take(MAX_KNOTS).enumerate() {
            p.t[i] = t;
            p.w[i] = w;
            if i > 0 {
                p.theta[i] = p.theta[i - 1] + 0.5 * (p.w[i - 1] + w) * (t - p.t[i - 1]);
                let span = t - p.t[i - 1];
                p.alpha[i - 1] = if span > 0.0 { (w - p.w[i - 1]) / span } else { 0.0 };
            }
        }
        p
    }

    /// Largest |dω/dt| over the segments.
    pub fn max_acceleration(&self) -> f64 {
        (1..self.n)
            .filter(|&i| self.t[i] > self.t[i - 1])
            .map(|i| ((self.w[i] - self.w[i - 1]) / (self.t[i] - self.t[i - 1])).abs())
            .fold(0.0, f64::max)
    }

    pub fn max_velocity(&self) -> f64 {
        self.w[..self.n].iter().fold(0.0, |a, w| a.max(w.abs()))
    }

    /// Evaluate at `t` (clamped to the knot range). Exactly 0 at t = 0.
    #[inline(always)]
    pub fn eval(&self, t: f64) -> ProfilePoint {
        if self.n < 2 {
            return ProfilePoint::default();
        }
        let t = t.clamp(self.t[0], self.t[self.n - 1]);
        let mut i = 0;
        while i + 2 < self.n && t >= self.t[i + 1] {
            i += 1;
        }
        let alpha = self.alpha[i];
        let dt = t - self.t[i];
        ProfilePoint {
            theta: self.theta[i] + self.w[i] * dt + 0.5 * alpha * dt * dt,
            omega: self.w[i] + alpha * dt,
            alpha,
        }
    }
}
