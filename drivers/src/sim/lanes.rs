//! Every part's linear state (position, velocity, stick flag) as a
//! structure of arrays in groups of four lanes. The point parts' friction,
//! the fence test and the Verlet test run over whole groups (LLVM
//! vectorises them; no gather or scatter); collisions and extended parts
//! reach single lanes through [`Lanes::load`] and [`Lanes::store`].
//!
//! Point parts take the first lanes, in part order; extended parts start on
//! a fresh group. Unused lanes are not live: they never move, never touch
//! the fence and are never written back.

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
    pub vx: [f64; W],
    pub vy: [f64; W],
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
            vx: [0.0; W],
            vy: [0.0; W],
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
    /// Lane `k`'s linear state into `p` (angle and spin untouched).
    #[inline]
    pub fn load(&self, k: usize, p: &mut PartState) {
        p.position = [self.x[k], self.y[k]];
        p.velocity = [self.vx[k], self.vy[k]];
        p.stuck = self.stuck[k];
    }

    #[inline]
    pub fn store(&mut self, k: usize, p: &PartState) {
        [self.x[k], self.y[k]] = p.position;
        [self.vx[k], self.vy[k]] = p.velocity;
        self.stuck[k] = p.stuck;
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Lanes {
    pub groups: Vec<Group>,
    /// Groups `0..point_groups` hold the point parts.
    pub point_groups: usize,
    /// Lane of each part (group = lane / W).
    pub lane: Vec<usize>,
}

impl Lanes {
    /// `extended[i]` says whether part `i` is extended; `lim[i]` is its fence
    /// half-extent.
    pub fn new(parts: &[PartState], extended: &[bool], lim: &[[f64; 2]]) -> Self {
        let n_points = extended.iter().filter(|&&e| !e).count();
        let point_groups = n_points.div_ceil(W);
        let n_ext = parts.len() - n_points;
        let mut lanes = Self {
            groups: vec![Group::default(); point_groups + n_ext.div_ceil(W)],
            point_groups,
            lane: Vec::with_capacity(parts.len()),
        };
        let (mut next_point, mut next_ext) = (0, point_groups * W);
        for (i, p) in parts.iter().enumerate() {
            let next = if extended[i] { &mut next_ext } else { &mut next_point };
            let l = *next;
            *next += 1;
            lanes.lane.push(l);
            let g = &mut lanes.groups[l / W];
            let k = l % W;
            g.live[k] = true;
            g.lim_x[k] = lim[i][0];
            g.lim_y[k] = lim[i][1];
            lanes.store(l, p);
        }
        lanes
    }

    /// Copy lane `l`'s linear state into `p` (angle and spin untouched).
    #[inline]
    pub fn load(&self, l: usize, p: &mut PartState) {
        self.groups[l / W].load(l % W, p);
    }

    #[inline]
    pub fn store(&mut self, l: usize, p: &PartState) {
        self.groups[l / W].store(l % W, p);
    }

    /// Bring every part's linear state in `parts` up to date.
    #[inline]
    pub fn mirror(&self, parts: &mut [PartState]) {
        for (p, &l) in parts.iter_mut().zip(&self.lane) {
            self.load(l, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_first_then_extended_on_a_fresh_group() {
        let parts: Vec<PartState> = (0..7)
            .map(|i| PartState {
                position: [i as f64, -(i as f64)],
                stuck: i % 2 == 0,
                ..PartState::default()
            })
            .collect();
        let extended = [false, true, false, false, true, false, false];
        let lim = [[1.0, 2.0]; 7];
        let lanes = Lanes::new(&parts, &extended, &lim);
        assert_eq!(lanes.point_groups, 2);
        assert_eq!(lanes.lane, vec![0, 8, 1, 2, 9, 3, 4]);
        assert_eq!(lanes.groups.len(), 3);
        let live: Vec<bool> = lanes.groups.iter().flat_map(|g| g.live).collect();
        assert_eq!(live.iter().filter(|&&l| l).count(), 7);
        assert!(!live[5] && !live[10] && lanes.groups[1].lim_x[1].is_infinite());
        let mut back = vec![PartState::default(); 7];
        lanes.mirror(&mut back);
        assert_eq!(back, parts);
    }
}
