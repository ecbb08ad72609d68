//! Part–part impacts (discs; other shapes by their bounding circle) and the
//! fence at the plate's edge. Impulses are frictionless and along the line
//! of centers, so part–part contact conserves linear momentum exactly.
//!
//! Broad phase: a Verlet pair list (pairs closer than r_i + r_j + SKIN),
//! rebuilt when any part has moved SKIN/2 since the last build, so the
//! per-tick cost is O(parts) when parts are apart.

use rt_core::motion::{Pose, Twist};

use super::part::{Body, PartState};

/// Verlet skin (m).
pub(crate) const SKIN: f64 = 0.01;

#[derive(Debug, Clone, Default)]
pub(crate) struct Broadphase {
    pub pairs: Vec<(u16, u16)>,
    pub anchor: Vec<[f64; 2]>,
    pub valid: bool,
}

impl Broadphase {
    pub fn with_capacity(n: usize) -> Self {
        Self {
            pairs: Vec::with_capacity(n * n.saturating_sub(1) / 2),
            anchor: vec![[0.0; 2]; n],
            valid: false,
        }
    }

    /// Rebuild if needed; never grows past the capacity reserved in
    /// `with_capacity` (n(n−1)/2 pairs), so no allocation.
    #[inline]
    fn refresh(&mut self, bodies: &[Body], parts: &[PartState]) {
        let half2 = 0.25 * SKIN * SKIN;
        if self.valid
            && parts.iter().zip(&self.anchor).all(|(p, a)| {
                let (dx, dy) = (p.position[0] - a[0], p.position[1] - a[1]);
                dx * dx + dy * dy < half2
            })
        {
            return;
        }
        self.pairs.clear();
        for i in 0..parts.len() {
            self.anchor[i] = parts[i].position;
            for j in i + 1..parts.len() {
                let r = bodies[i].radius + bodies[j].radius + SKIN;
                let (dx, dy) = (
                    parts[j].position[0] - parts[i].position[0],
                    parts[j].position[1] - parts[i].position[1],
                );
                if dx * dx + dy * dy < r * r && self.pairs.len() < self.pairs.capacity() {
                    self.pairs.push((i as u16, j as u16));
                }
            }
        }
        self.valid = true;
    }
}

/// Resolve part–part overlaps. Returns the number of impacts.
#[inline]
pub(crate) fn collide(
    bp: &mut Broadphase,
    bodies: &[Body],
    parts: &mut [PartState],
    restitution: f64,
) -> u64 {
    bp.refresh(bodies, parts);
    let mut hits = 0;
    for &(i, j) in &bp.pairs {
        let (i, j) = (i as usize, j as usize);
        let r = bodies[i].radius + bodies[j].radius;
        let (dx, dy) =
            (parts[j].position[0] - parts[i].position[0], parts[j].position[1] - parts[i].position[1]);
        let d2 = dx * dx + dy * dy;
        if d2 >= r * r || r <= 0.0 {
            continue;
        }
        let d = d2.sqrt();
        let n = if d > 0.0 { [dx / d, dy / d] } else { [1.0, 0.0] };
        let (wi, wj) = (1.0 / bodies[i].mass, 1.0 / bodies[j].mass);
        let vn = (parts[j].velocity[0] - parts[i].velocity[0]) * n[0]
            + (parts[j].velocity[1] - parts[i].velocity[1]) * n[1];
        if vn < 0.0 {
            let jn = -(1.0 + restitution) * vn / (wi + wj);
            for k in 0..2 {
                parts[i].velocity[k] -= jn * wi * n[k];
                parts[j].velocity[k] += jn * wj * n[k];
            }
            parts[i].stuck = false;
            parts[j].stuck = false;
            hits += 1;
        }
        // Separate by mass-weighted position correction (momentum-neutral).
        let push = (r - d) / (wi + wj);
        for k in 0..2 {
            parts[i].position[k] -= push * wi * n[k];
            parts[j].position[k] += push * wj * n[k];
        }
    }
    hits
}

/// Keep a part inside the plate outline shrunk by its radius (`lim`, see
/// [`fence_limits`]). Returns true on an impact.
#[inline]
pub(crate) fn fence(
    lim: [f64; 2],
    part: &mut PartState,
    plate: &Pose,
    (sn, cs): (f64, f64),
    plate_vel: &Twist,
    restitution: f64,
) -> bool {
    let (dx, dy) = (part.position[0] - plate.x, part.position[1] - plate.y);
    let q = [cs * dx + sn * dy, -sn * dx + cs * dy];
    if (q[0].abs() <= lim[0]) & (q[1].abs() <= lim[1]) {
        return false;
    }
    let qc = [q[0].clamp(-lim[0], lim[0]), q[1].clamp(-lim[1], lim[1])];
    part.position = plate.to_world(qc);
    let vpl = plate_vel.at(plate, part.position);
    let mut hit = false;
    for axis in 0..2 {
        if q[axis] == qc[axis] {
            continue;
        }
        // Outward normal of this wall in world coordinates.
        let sgn = q[axis].signum();
        let n = if axis == 0 { [cs * sgn, sn * sgn] } else { [-sn * sgn, cs * sgn] };
        let vn = (part.velocity[0] - vpl[0]) * n[0] + (part.velocity[1] - vpl[1]) * n[1];
        if vn > 0.0 {
            let dv = (1.0 + restitution) * vn;
            part.velocity[0] -= dv * n[0];
            part.velocity[1] -= dv * n[1];
            hit = true;
        }
    }
    if hit {
        part.stuck = false;
    }
    hit
}

/// Half-extents of the region a part's center may occupy: the plate outline
/// shrunk by the part's bounding radius.
pub(crate) fn fence_limits(body: &Body, half: [f64; 2]) -> [f64; 2] {
    [(half[0] - body.radius).max(0.0), (half[1] - body.radius).max(0.0)]
}
