//! The controller every built-in planner shares: a part gets a desired
//! velocity towards its goal (speed-limited), and the requested force is
//! m·k_v·(v_desired − v), clamped to a fraction of μmg.

use ipc_types::PartState;
use serde::{Deserialize, Serialize};

/// `[planner.drive]`: the shared controller's gains and the planner's model
/// of the parts (their mass and friction force, to turn accelerations into
/// forces). The launcher fills `mu_m_g` from the rig's `[plate]` and
/// `part_mass` from the scenario's parts.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct DriveParams {
    /// Speed limit of the parts (m/s); keeps them well below the plate's
    /// speed, as the friction model assumes.
    pub max_speed: f64,
    /// Position gain: desired speed per metre of error (1/s).
    pub position_gain: f64,
    /// Velocity gain: desired acceleration per m/s of speed error (1/s).
    pub velocity_gain: f64,
    /// Largest requested force as a fraction of μmg.
    pub max_force_fraction: f64,
    /// The parts' μmg (N) and mass (kg).
    pub mu_m_g: f64,
    pub part_mass: f64,
    /// Learn each part's friction online and ask for what it needs
    /// (`adaptive`).
    pub adapt_friction: bool,
}

impl Default for DriveParams {
    fn default() -> Self {
        Self {
            max_speed: 0.03,
            position_gain: 1.0,
            velocity_gain: 8.0,
            max_force_fraction: 0.15,
            mu_m_g: 0.1,
            part_mass: 0.1 / (0.25 * 9.81),
            adapt_friction: false,
        }
    }
}

impl DriveParams {
    /// The message names the field.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let fields = [
            ("max_speed", self.max_speed),
            ("position_gain", self.position_gain),
            ("velocity_gain", self.velocity_gain),
            ("mu_m_g", self.mu_m_g),
            ("part_mass", self.part_mass),
        ];
        if let Some((name, v)) = fields.iter().find(|(_, v)| !pos(*v)) {
            return Err(format!("planner.drive.{name} must be positive, got {v}"));
        }
        if !(self.max_force_fraction > 0.0 && self.max_force_fraction <= 1.0) {
            return Err(format!(
                "planner.drive.max_force_fraction must be in (0, 1], got {}",
                self.max_force_fraction
            ));
        }
        Ok(())
    }

    /// Force that drives `part` to `goal` (with feed-forward velocity `vff`).
    pub fn force_to(&self, part: &PartState, goal: [f64; 2], vff: [f64; 2]) -> [f64; 2] {
        let mut vd = [
            vff[0] + self.position_gain * (goal[0] - part.x),
            vff[1] + self.position_gain * (goal[1] - part.y),
        ];
        let s = vd[0].hypot(vd[1]);
        if s > self.max_speed {
            vd = [vd[0] * self.max_speed / s, vd[1] * self.max_speed / s];
        }
        let mut f = [
            self.part_mass * self.velocity_gain * (vd[0] - part.vx),
            self.part_mass * self.velocity_gain * (vd[1] - part.vy),
        ];
        let fmax = self.max_force_fraction * self.mu_m_g;
        let n = f[0].hypot(f[1]);
        if n > fmax {
            f = [f[0] * fmax / n, f[1] * fmax / n];
        }
        f
    }
}

/// Points remembered per part id (a start, or where a part is held).
#[derive(Debug, Clone, Default)]
pub struct PartPoints(Vec<(u32, [f64; 2])>);

impl PartPoints {
    /// The point remembered for `part`, or its current position, remembered now.
    pub fn get_or_remember(&mut self, part: &PartState) -> [f64; 2] {
        if let Some((_, p)) = self.0.iter().find(|(id, _)| *id == part.id) {
            return *p;
        }
        self.0.push((part.id, [part.x, part.y]));
        [part.x, part.y]
    }

    pub fn set(&mut self, id: u32, at: [f64; 2]) {
        match self.0.iter_mut().find(|(i, _)| *i == id) {
            Some((_, a)) => *a = at,
            None => self.0.push((id, at)),
        }
    }
}
