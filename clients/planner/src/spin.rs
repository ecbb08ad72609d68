//! `spin` (paper §3.3): one part turns in place to an angle; every part,
//! that one included, holds its start position. With a `goal` the turning
//! part moves there while it turns (orienting parts on the way, as a
//! feeder does): force and curl asked of it together.

use ipc_types::{ForceEntry, ForceRequest, PartStates};
use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::drive::{DriveParams, PartPoints};

/// `[planner]` with `name = "spin"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SpinParams {
    pub drive: DriveParams,
    /// The part that turns, and the angle (rad) it turns to.
    pub part: u32,
    pub angle: f64,
    /// Where the turning part goes while it turns (m); None: it holds its
    /// start.
    pub goal: Option<[f64; 2]>,
    /// Curl per radian of angle error (N/m/rad), and its limit.
    pub gain: f64,
    pub max_curl: f64,
    /// Curl per rad/s of the part's spin, taken off (N/m·s/rad): the damping
    /// a core that corrects for the part's own spin (`[motion.part_dynamics]`)
    /// no longer gives by itself. 0: none.
    pub damping: f64,
}

impl Default for SpinParams {
    fn default() -> Self {
        Self {
            drive: DriveParams::default(),
            part: 1,
            angle: std::f64::consts::FRAC_PI_2,
            goal: None,
            gain: 0.2,
            max_curl: 0.05,
            damping: 0.0,
        }
    }
}

#[derive(Debug)]
pub struct SpinPlanner {
    p: SpinParams,
    starts: PartPoints,
}

impl SpinPlanner {
    pub fn new(p: SpinParams) -> Result<Self, String> {
        p.drive.validate()?;
        if !(p.angle.is_finite()
            && p.gain.is_finite()
            && p.gain > 0.0
            && p.max_curl.is_finite()
            && p.max_curl > 0.0
            && p.damping.is_finite()
            && p.damping >= 0.0)
        {
            return Err(
                "planner: spin needs a finite angle, a positive gain and max_curl, and a damping ≥ 0".into(),
            );
        }
        if let Some(g) = p.goal
            && !g.iter().all(|x| x.is_finite())
        {
            return Err(format!("planner.goal must be finite, got {g:?}"));
        }
        Ok(Self { p, starts: PartPoints::default() })
    }
}

impl Planner for SpinPlanner {
    fn name(&self) -> &'static str {
        "spin"
    }

    fn plan(&mut self, parts: &PartStates, _t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        for part in parts.parts() {
            let start = self.starts.get_or_remember(part);
            let turning = part.id == self.p.part;
            let target = match self.p.goal {
                Some(goal) if turning => goal,
                _ => start,
            };
            let f = self.p.drive.force_to(part, target, [0.0; 2]);
            let entry = if turning {
                let err = self.p.angle - part.theta;
                let curl = (self.p.gain * err - self.p.damping * part.omega)
                    .clamp(-self.p.max_curl, self.p.max_curl);
                ForceEntry::force_and_curl(part.id, f, curl)
            } else {
                ForceEntry::force(part.id, f)
            };
            if out.push(entry).is_err() {
                break;
            }
        }
        !out.is_empty()
    }
}
