//! Part–part impacts (discs; other shapes by their bounding circle) and the
//! fence at the plate's edge. Impulses are frictionless and along the line
//! of centers, so part–part contact conserves linear momentum exactly.
//!
//! Broad phase: a Verlet pair list (pairs closer than r_i + r_j + SKIN),
//! rebuilt when any part has moved SKIN/2 since the last build, so the
//! per-tick cost is O(parts) when parts are apart.

use upm_motion::{Pose, Twist};

use super::lanes::{Group, Lanes, W};
use super::part::{Body, PartState};

/// Verlet skin (m).
pub(crate) const SKIN: f64 = 0.01;

/// Pairs of part indices; the anchors live in the lanes.
#[derive(Debug, Clone, Default)]
pub(crate) struct Broadphase {
    pub pairs: Vec<(u16, u16)>,
    pub valid: bool,
}

impl Broadphase {
    pub fn with_capacity(n: usize) -> Self {
        Self { pairs: Vec::with_capacity(n * n.saturating_sub(1) / 2), valid: false }
    }

    /// Rebuild if needed; never grows past the capacity reserved in
    /// `with_capacity` (n(n−1)/2 pairs), so no allocation.
    #[inline(always)]
    fn refresh(&mut self, bodies: &[Body], lanes: &mut Lanes) {
        if self.valid && !moved_half_skin(&lanes.groups) {
            return;
        }
        self.rebuild(bodies, lanes);
    }

    #[inline(never)]
    fn rebuild(&mut self, bodies: &[Body], lanes: &mut Lanes) {
        self.pairs.clear();
        let pos = |l: usize| {
            let g = &lanes.groups[l / W];
            [g.x[l % W], g.y[l % W]]
        };
        for i in 0..lanes.lane.len() {
            let pi = pos(lanes.lane[i]);
            for j in i + 1..lanes.lane.len() {
                let pj = pos(lanes.lane[j]);
                let r = bodies[i].radius + bodies[j].radius + SKIN;
                let (dx, dy) = (pj[0] - pi[0], pj[1] - pi[1]);
                if dx * dx + dy * dy < r * r && self.pairs.len() < self.pairs.capacity() {
                    self.pairs.push((i as u16, j as u16));
                }
            }
        }
        for g in &mut lanes.groups {
            g.anchor_x = g.x;
            g.anchor_y = g.y;
        }
        self.valid = true;
    }
}

/// Has any lane moved SKIN/2 from its anchor? One pass, no early exit, so
/// the loop vectorises.
#[inline(always)]
fn moved_half_skin(groups: &[Group]) -> bool {
    let half2 = 0.25 * SKIN * SKIN;
    let mut far = false;
    for g in groups {
        for k in 0..W {
            let (dx, dy) = (g.x[k] - g.anchor_x[k], g.y[k] - g.anchor_y[k]);
            // "Not closer", so that NaN forces a rebuild.
            far |= !(dx * dx + dy * dy < half2);
        }
    }
    far
}

/// Resolve part–part overlaps. Returns the number of impacts.
#[inline(always)]
pub(crate) fn collide(bp: &mut Broadphase, bodies: &[Body], lanes: &mut Lanes, restitution: f64) -> u64 {
    bp.refresh(bodies, lanes);
    if bp.pairs.is_empty() {
        return 0;
    }
    resolve_pairs(bp, bodies, lanes, restitution)
}

/// The pairs of the Verlet list (out of line: most ticks have none).
#[inline(never)]
fn resolve_pairs(bp: &Broadphase, bodies: &[Body], lanes: &mut Lanes, restitution: f64) -> u64 {
    let mut hits = 0;
    for &(i, j) in &bp.pairs {
        let (i, j) = (i as usize, j as usize);
        let r = bodies[i].radius + bodies[j].radius;
        let (mut a, mut b) = (lanes.load(lanes.lane[i]), lanes.load(lanes.lane[j]));
        let (dx, dy) = (b.position[0] - a.position[0], b.position[1] - a.position[1]);
        let d2 = dx * dx + dy * dy;
        if d2 >= r * r || r <= 0.0 {
            continue;
        }
        let d = d2.sqrt();
        let n = if d > 0.0 { [dx / d, dy / d] } else { [1.0, 0.0] };
        let (wi, wj) = (1.0 / bodies[i].mass, 1.0 / bodies[j].mass);
        let vn = (b.velocity[0] - a.velocity[0]) * n[0] + (b.velocity[1] - a.velocity[1]) * n[1];
        if vn < 0.0 {
            let jn = -(1.0 + restitution) * vn / (wi + wj);
            for k in 0..2 {
                a.velocity[k] -= jn * wi * n[k];
                b.velocity[k] += jn * wj * n[k];
            }
            a.stuck = false;
            b.stuck = false;
            hits += 1;
        }
        // Separate by mass-weighted position correction (momentum-neutral).
        let push = (r - d) / (wi + wj);
        for k in 0..2 {
            a.position[k] -= push * wi * n[k];
            b.position[k] += push * wj * n[k];
        }
        lanes.store(lanes.lane[i], &a);
        lanes.store(lanes.lane[j], &b);
    }
    hits
}

/// The fence for every lane: a vectorised inside test per group, and
/// [`fence`] for the lanes outside. Returns the number of impacts.
#[inline(always)]
pub(crate) fn fence_groups(
    groups: &mut [Group],
    plate: &Pose,
    (sn, cs): (f64, f64),
    plate_vel: &Twist,
    restitution: f64,
) -> u64 {
    let mut hits = 0;
    for g in groups {
        let mut outside = [false; W];
        for k in 0..W {
            let (dx, dy) = (g.x[k] - plate.x, g.y[k] - plate.y);
            let q = [cs * dx + sn * dy, -sn * dx + cs * dy];
            // Written as "not inside" so that NaN counts as outside.
            outside[k] = !((q[0].abs() <= g.lim_x[k]) & (q[1].abs() <= g.lim_y[k]));
        }
        if outside.iter().fold(false, |any, &o| any | o) {
            hits += fence_lanes(g, outside, plate, (sn, cs), plate_vel, restitution);
        }
    }
    hits
}

/// [`fence`] for the `outside` lanes of a group (out of line: rare).
#[inline(never)]
fn fence_lanes(
    g: &mut Group,
    outside: [bool; W],
    plate: &Pose,
    sc: (f64, f64),
    plate_vel: &Twist,
    restitution: f64,
) -> u64 {
    let mut hits = 0;
    for k in (0..W).filter(|&k| outside[k]) {
        let mut p = g.load(k);
        hits += fence([g.lim_x[k], g.lim_y[k]], &mut p, plate, sc, plate_vel, restitution) as u64;
        g.store(k, &p);
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
