//! `track` (paper §4.1): parts 1, 2, … each follow their own rectangle at
//! constant speed; parts without a rectangle hold their start.

use ipc_types::{ForceEntry, ForceRequest, PartStates};
use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::drive::{DriveParams, PartPoints};

/// `[planner]` with `name = "track"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct TrackParams {
    pub drive: DriveParams,
    /// Rectangles (centre x, centre y, width, height), one per part id 1, 2, …
    pub rects: Vec<[f64; 4]>,
    /// Speed along the path (m/s).
    pub speed: f64,
}

impl Default for TrackParams {
    fn default() -> Self {
        Self {
            drive: DriveParams::default(),
            rects: vec![[-0.45, 0.0, 0.4, 0.3], [0.45, 0.0, 0.4, 0.3]],
            speed: 0.02,
        }
    }
}

#[derive(Debug)]
pub struct TrackPlanner {
    p: TrackParams,
    starts: PartPoints,
}

impl TrackPlanner {
    pub fn new(p: TrackParams) -> Result<Self, String> {
        p.drive.validate()?;
        if p.rects.is_empty() || !(p.speed.is_finite() && p.speed > 0.0) {
            return Err("planner: track needs rects and a positive speed".into());
        }
        if let Some(i) =
            p.rects.iter().position(|r| !r.iter().all(|x| x.is_finite()) || r[2] < 0.0 || r[3] < 0.0)
        {
            return Err(format!("planner.rects[{i}] must be finite with a width and height >= 0"));
        }
        Ok(Self { p, starts: PartPoints::default() })
    }
}

impl Planner for TrackPlanner {
    fn name(&self) -> &'static str {
        "track"
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        for part in parts.parts() {
            let start = self.starts.get_or_remember(part);
            let entry = match self.p.rects.get(part.id.wrapping_sub(1) as usize) {
                Some(&rect) => {
                    let (goal, dir) = rectangle_point(rect, self.p.speed * t);
                    let vff = [dir[0] * self.p.speed, dir[1] * self.p.speed];
                    ForceEntry::force(part.id, self.p.drive.force_to(part, goal, vff))
                }
                None => ForceEntry::force(part.id, self.p.drive.force_to(part, start, [0.0; 2])),
            };
            if out.push(entry).is_err() {
                break;
            }
        }
        !out.is_empty()
    }
}

/// Point at arc length `s` along the rectangle (cx, cy, w, h), counter-
/// clockwise from its lower-left corner, and the unit direction there.
pub fn rectangle_point(r: [f64; 4], s: f64) -> ([f64; 2], [f64; 2]) {
    let [cx, cy, w, h] = r;
    let per = 2.0 * (w + h);
    let s = s.rem_euclid(per);
    let (x0, y0) = (cx - w / 2.0, cy - h / 2.0);
    if s < w {
        ([x0 + s, y0], [1.0, 0.0])
    } else if s < w + h {
        ([x0 + w, y0 + s - w], [0.0, 1.0])
    } else if s < 2.0 * w + h {
        ([x0 + w - (s - w - h), y0 + h], [-1.0, 0.0])
    } else {
        ([x0, y0 + h - (s - 2.0 * w - h)], [0.0, -1.0])
    }
}

/// Distance from `p` to the rectangle's outline.
pub fn distance_to_rectangle(r: [f64; 4], p: [f64; 2]) -> f64 {
    let [cx, cy, w, h] = r;
    let (dx, dy) = ((p[0] - cx).abs() - w / 2.0, (p[1] - cy).abs() - h / 2.0);
    if dx > 0.0 || dy > 0.0 { dx.max(0.0).hypot(dy.max(0.0)) } else { (-dx).min(-dy) }
}
