//! The rig as a Foxglove 3D scene (`foxglove.SceneUpdate`): the plate's
//! outline, the parts coloured by class with their trails, the forces the
//! planner asked for and the forces the playing schedule gives (green and
//! blue arrows), and the centers of rotation sized by |k_j| (red k > 0,
//! blue k < 0). Built from the messages alone, in the plate's frame.

use std::collections::{BTreeMap, VecDeque};

use foxglove::messages::{
    ArrowPrimitive, Color, CylinderPrimitive, LinePrimitive, Point3, Pose, Quaternion, SceneEntity,
    SceneUpdate, SpherePrimitive, TextPrimitive, Timestamp, Vector3, line_primitive,
};
use ipc_types::{ForceRequest, PartStates, Schedule};

/// What the scene needs of the rig (`[plate]`).
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(default)]
pub struct PlateView {
    pub half_extent: [f64; 2],
    pub mu_m_g: f64,
    pub centers: Vec<[f64; 2]>,
}

/// Trail points kept per part (at the scene's rate).
const TRAIL_POINTS: usize = 300;
/// Arrow length of a force of μmg.
const ARROW_PER_MU_M_G: f64 = 0.15;
const PART_DIAMETER: f64 = 0.02;

/// The newest messages and the trails, turned into a scene on demand.
#[derive(Debug, Default)]
pub struct Scene {
    plate: PlateView,
    parts: Option<PartStates>,
    request: Option<ForceRequest>,
    schedule: Option<Schedule>,
    trails: BTreeMap<u32, VecDeque<[f64; 2]>>,
}

fn pose(x: f64, y: f64, yaw: f64) -> Option<Pose> {
    let (s, c) = (0.5 * yaw).sin_cos();
    Some(Pose {
        position: Some(Vector3 { x, y, z: 0.0 }),
        orientation: Some(Quaternion { x: 0.0, y: 0.0, z: s, w: c }),
    })
}

fn color(r: f64, g: f64, b: f64) -> Option<Color> {
    Some(Color { r, g, b, a: 1.0 })
}

/// A distinct colour per part class.
fn class_color(class: u32) -> Option<Color> {
    const PALETTE: [[f64; 3]; 6] = [
        [0.95, 0.6, 0.1],
        [0.2, 0.6, 0.95],
        [0.3, 0.8, 0.3],
        [0.85, 0.3, 0.8],
        [0.9, 0.9, 0.2],
        [0.6, 0.6, 0.6],
    ];
    let [r, g, b] = PALETTE[class as usize % PALETTE.len()];
    color(r, g, b)
}

fn arrow(from: [f64; 2], f: [f64; 2], mu_m_g: f64, rgb: Option<Color>) -> Option<ArrowPrimitive> {
    let len = f[0].hypot(f[1]) / mu_m_g.max(1e-12) * ARROW_PER_MU_M_G;
    (len.is_finite() && len > 1e-4).then(|| ArrowPrimitive {
        pose: pose(from[0], from[1], f[1].atan2(f[0])),
        shaft_length: 0.8 * len,
        shaft_diameter: 0.002,
        head_length: 0.2 * len,
        head_diameter: 0.006,
        color: rgb,
    })
}

impl Scene {
    pub fn new(plate: PlateView) -> Self {
        Self { plate, ..Self::default() }
    }

    pub fn on_parts(&mut self, m: &PartStates) {
        self.parts = Some(*m);
        // Trails of parts no longer seen go: ids may change without end.
        self.trails.retain(|id, _| m.parts().iter().any(|p| p.id == *id));
    }

    pub fn on_request(&mut self, m: &ForceRequest) {
        self.request = Some(*m);
    }

    pub fn on_schedule(&mut self, m: &Schedule) {
        self.schedule = Some(*m);
    }

    /// The average force the playing schedule gives at `p` (ARCHITECTURE.md §2).
    fn achieved(&self, s: &Schedule, p: [f64; 2]) -> [f64; 2] {
        let n = s.slots().len().max(1) as f64;
        let mut f = [0.0; 2];
        for slot in s.slots() {
            let (dx, dy) = (p[0] - slot.x, p[1] - slot.y);
            let r = dx.hypot(dy);
            if r > 1e-9 {
                f[0] += slot.k * -dy / r;
                f[1] += slot.k * dx / r;
            }
        }
        [f[0] * self.plate.mu_m_g / n, f[1] * self.plate.mu_m_g / n]
    }

    /// The scene now, and one more trail point per part.
    pub fn update(&mut self, stamp: Timestamp) -> SceneUpdate {
        let entity = |id: &str| SceneEntity {
            timestamp: Some(stamp),
            frame_id: "plate".into(),
            id: id.into(),
            frame_locked: true,
            ..SceneEntity::default()
        };
        let [hx, hy] = self.plate.half_extent;
        let mut plate = entity("plate");
        plate.lines.push(LinePrimitive {
            r#type: line_primitive::Type::LineLoop as i32,
            thickness: 0.002,
            points: [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]
                .iter()
                .map(|&[x, y]| Point3 { x, y, z: 0.0 })
                .collect(),
            color: color(0.8, 0.8, 0.8),
            pose: pose(0.0, 0.0, 0.0),
            ..LinePrimitive::default()
        });
        let mut parts = entity("parts");
        let mut trails = entity("trails");
        let mut forces = entity("forces");
        if let Some(m) = &self.parts {
            for p in m.parts() {
                parts.cylinders.push(CylinderPrimitive {
                    pose: pose(p.x, p.y, p.theta),
                    size: Some(Vector3 { x: PART_DIAMETER, y: PART_DIAMETER, z: 0.004 }),
                    bottom_scale: 1.0,
                    top_scale: 1.0,
                    color: class_color(p.class),
                });
                let trail = self.trails.entry(p.id).or_default();
                if trail.len() == TRAIL_POINTS {
                    trail.pop_front();
                }
                trail.push_back([p.x, p.y]);
                trails.lines.push(LinePrimitive {
                    r#type: line_primitive::Type::LineStrip as i32,
                    thickness: 0.001,
                    points: trail.iter().map(|&[x, y]| Point3 { x, y, z: 0.0 }).collect(),
                    color: class_color(p.class),
                    pose: pose(0.0, 0.0, 0.0),
                    ..LinePrimitive::default()
                });
                let at = [p.x, p.y];
                let asked =
                    self.request.as_ref().and_then(|r| r.entries().iter().find(|e| e.part_id == p.id));
                if let Some(f) = asked.and_then(|e| e.requested_force()) {
                    forces.arrows.extend(arrow(at, f, self.plate.mu_m_g, color(0.2, 0.85, 0.2)));
                }
                if let Some(s) = &self.schedule {
                    let f = self.achieved(s, at);
                    forces.arrows.extend(arrow(at, f, self.plate.mu_m_g, color(0.2, 0.4, 1.0)));
                }
            }
        }
        let mut centers = entity("centers");
        if let Some(s) = &self.schedule {
            for slot in s.slots() {
                let d = 0.004 + 0.016 * slot.k.abs().min(1.0);
                let rgb = if slot.k >= 0.0 { color(0.9, 0.2, 0.2) } else { color(0.2, 0.3, 0.9) };
                centers.spheres.push(SpherePrimitive {
                    pose: pose(slot.x, slot.y, 0.0),
                    size: Some(Vector3 { x: d, y: d, z: d }),
                    color: rgb,
                });
                centers.texts.push(TextPrimitive {
                    pose: pose(slot.x, slot.y + 0.015, 0.0),
                    billboard: true,
                    font_size: 12.0,
                    scale_invariant: true,
                    color: color(1.0, 1.0, 1.0),
                    text: format!("{:+.2}", slot.k),
                });
            }
        } else {
            for &[x, y] in &self.plate.centers {
                centers.spheres.push(SpherePrimitive {
                    pose: pose(x, y, 0.0),
                    size: Some(Vector3 { x: 0.004, y: 0.004, z: 0.004 }),
                    color: color(0.6, 0.6, 0.6),
                });
            }
        }
        SceneUpdate { deletions: Vec::new(), entities: vec![plate, parts, trails, forces, centers] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc_types::ScheduleSlot;

    #[test]
    fn one_ccw_rotation_pushes_a_part_right_of_its_center_up() {
        let mut scene = Scene::new(PlateView { half_extent: [0.2, 0.2], mu_m_g: 0.1, centers: vec![] });
        let mut s = Schedule::new();
        let _ = s.push(ScheduleSlot::new(0, [0.0, 0.0], 0.5));
        let f = scene.achieved(&s, [0.1, 0.0]);
        assert!((f[0]).abs() < 1e-12 && (f[1] - 0.05).abs() < 1e-12, "{f:?}");
        scene.on_schedule(&s);
        let u = scene.update(Timestamp::new(1, 0));
        assert_eq!(u.entities.len(), 5);
        assert_eq!(u.entities[4].spheres.len(), 1);
    }
}
