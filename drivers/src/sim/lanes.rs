//! Every part's state (position, angle, velocity, spin, stick flag) as a
//! structure of arrays in groups of four lanes. The point and disc parts'
//! friction, the fence test and the Verlet test run over whole groups (LLVM
//! vectorises them; no gather or scatter); collisions and polygon parts
//! reach single lanes through [`Lanes::load`] and [`Lanes::store`].
//!
//! Point parts take the first lanes, in part order; discs start on a fresh
//! group after them, and the other extended parts on a fresh group after the
//! discs. Unused lanes are not live: they never move, never touch the fence
//! and are never written back.

use super::part::PartState;

/// Lanes per group (one AVX2 register of f64).
pub(crate) const W: usize = 4;

/// Four lanes. `lim` is the fence half-extent of each lane's center
/// ([`super::contact::fence_limits`]; infinite for unused lanes), `anchor`
/// its position when the Verlet pair list was built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Group {
    pub x: [f64; W],
    pub y: [f64; W],
    pub angle: [f64; W],
    pub vx: [f64; W],
    pub vy: [f64; W],
    pub w: [f64; W],
    /// A disc's radius (its friction depends on it); 0 for other parts.
    pub radius: [f64; W],
    /// μ here over the nominal μ (the truth's map and part scale; 1 on a
    /// nominal plate, where multiplying by it changes no bit).
    pub mu_scale: [f64; W],
    pub stuck: [bool; W],
    pub live: [bool; W],
    pub lim_x: [f64; W],
    pub lim_y: [f64; W],
    pub anchor_x: [f64; W],
    pub anchor_y: [f64; W],
}

impl Default for Group {
    fn default() -> Self {
        Self {
            x: [0.0; W],
            y: [0.0; W],
            angle: [0.0; W],
            vx: [0.0; W],
            vy: [0.0; W],
            w: [0.0; W],
            radius: [0.0; W],
            mu_scale: [1.0; W],
            stuck: [true; W],
            live: [false; W],
            lim_x: [f64::INFINITY; W],
            lim_y: [f64::INFINITY; W],
            anchor_x: [0.0; W],
            anchor_y: [0.0; W],
        }
    }
}

impl Group {
    /// Lane `k`'s state.
    #[inline]
    pub fn load(&self, k: usize) -> PartState {
        PartState {
            position: [self.x[k], self.y[k]],
            angle: self.angle[k],
            velocity: [self.vx[k], self.vy[k]],
            angular_velocity: self.w[k],
            stuck: self.stuck[k],
        }
    }

    #[inline]
    pub fn store(&mut self, k: usize, p: &PartState) {
        [self.x[k], self.y[k]] = p.position;
        self.angle[k] = p.angle;
        [self.vx[k], self.vy[k]] = p.velocity;
        self.w[k] = p.angular_velocity;
        self.stuck[k] = p.stuck;
    }
}

/// Which friction path a part takes; each kind has its own groups, in
/// this order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LaneKind {
    Point,
    Disc,
    /// Any other extended part (friction summed over its contact points).
    Patch,
}

#[derive(Debug, Clone)]
pub(crate) struct Lanes {
    pub groups: Vec<Group>,
    /// Groups `0..point_groups` hold the point parts, the next `disc_groups`
    /// the discs.
    pub point_groups: usize,
    pub disc_groups: usize,
    /// Lane of each part (group = lane / W).
    pub lane: Vec<usize>,
    /// Part of each lane (`usize::MAX` where unused).
    pub part_of: Vec<usize>,
}

impl Lanes {
    /// `kind[i]` is part `i`'s friction path, `lim[i]` its fence
    /// half-extent, `radius[i]` its radius if a disc.
    pub fn new(parts: &[PartState], kind: &[LaneKind], lim: &[[f64; 2]], radius: &[f64]) -> Self {
        let groups_of = |k: LaneKind| kind.iter().filter(|&&x| x == k).count().div_ceil(W);
        let (point_groups, disc_groups) = (groups_of(LaneKind::Point), groups_of(LaneKind::Disc));
        let total = point_groups + disc_groups + groups_of(LaneKind::Patch);
        let mut lanes = Self {
            groups: vec![Group::default(); total],
            point_groups,
            disc_groups,
            lane: Vec::with_capacity(parts.len()),
            part_of: vec![usize::MAX; total * W],
        };
        let mut next = [0, point_groups * W, (point_groups + disc_groups) * W];
        for (i, p) in parts.iter().enumerate() {
            let next = &mut next[kind[i] as usize];
            let l = *next;
            *next += 1;
            lanes.lane.push(l);
            lanes.part_of[l] = i;
            let g = &mut lanes.groups[l / W];
            let k = l % W;
            g.live[k] = true;
            g.lim_x[k] = lim[i][0];
            g.lim_y[k] = lim[i][1];
            g.radius[k] = if kind[i] == LaneKind::Disc { radius[i] } else { 0.0 };
            lanes.store(l, p);
        }
        lanes
    }

    /// Lane `l`'s state.
    #[inline]
    pub fn load(&self, l: usize) -> PartState {
        self.groups[l / W].load(l % W)
    }

    #[inline]
    pub fn store(&mut self, l: usize, p: &PartState) {
        self.groups[l / W].store(l % W, p);
    }

    /// Bring every part's state in `parts` up to date.
    #[inline]
    pub fn mirror(&self, parts: &mut [PartState]) {
        for (p, &l) in parts.iter_mut().zip(&self.lane) {
            *p = self.load(l);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_first_then_discs_then_patches_each_on_a_fresh_group() {
        let parts: Vec<PartState> = (0..8)
            .map(|i| PartState {
                position: [i as f64, -(i as f64)],
                angle: 0.1 * i as f64,
                angular_velocity: -(i as f64),
                stuck: i % 2 == 0,
                ..PartState::default()
            })
            .collect();
        use LaneKind::{Disc, Patch, Point};
        let kind = [Point, Disc, Point, Point, Patch, Point, Point, Disc];
        let lim = [[1.0, 2.0]; 8];
        let lanes = Lanes::new(&parts, &kind, &lim, &[0.5; 8]);
        assert_eq!((lanes.point_groups, lanes.disc_groups), (2, 1));
        assert_eq!(lanes.lane, vec![0, 8, 1, 2, 12, 3, 4, 9]);
        assert_eq!(lanes.groups.len(), 4);
        for (l, &p) in lanes.part_of.iter().enumerate() {
            assert!(p == usize::MAX || lanes.lane[p] == l);
        }
        let live: Vec<bool> = lanes.groups.iter().flat_map(|g| g.live).collect();
        assert_eq!(live.iter().filter(|&&l| l).count(), 8);
        assert!(!live[5] && !live[10] && !live[13] && lanes.groups[1].lim_x[1].is_infinite());
        assert_eq!(
            (lanes.groups[2].radius[1], lanes.groups[3].radius[0], lanes.groups[0].radius[0]),
            (0.5, 0.0, 0.0)
        );
        let mut back = vec![PartState::default(); 8];
        lanes.mirror(&mut back);
        assert_eq!(back, parts);
    }
}
