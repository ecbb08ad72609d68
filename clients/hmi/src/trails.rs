//! Each part's short trail: its last [`TRAIL_POINTS`] positions, one per
//! update of the page. A part vision no longer reports loses its trail.

use std::collections::{BTreeMap, VecDeque};

use ipc_types::PartStates;

/// Points kept per part: at the page's 10 updates a second, 3 s.
pub const TRAIL_POINTS: usize = 30;

#[derive(Debug, Default)]
pub struct Trails {
    by_part: BTreeMap<u32, VecDeque<[f64; 2]>>,
}

impl Trails {
    /// Add the newest positions of `parts`.
    pub fn add(&mut self, parts: &PartStates) {
        let seen = parts.parts();
        self.by_part.retain(|id, _| seen.iter().any(|p| p.id == *id));
        for p in seen {
            let trail = self.by_part.entry(p.id).or_default();
            if trail.back() != Some(&[p.x, p.y]) {
                trail.push_back([p.x, p.y]);
            }
            if trail.len() > TRAIL_POINTS {
                trail.pop_front();
            }
        }
    }

    /// Part `id`'s trail, oldest first.
    pub fn of(&self, id: u32) -> impl Iterator<Item = &[f64; 2]> {
        self.by_part.get(&id).into_iter().flatten()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc_types::PartState;

    fn states(parts: &[(u32, f64)]) -> PartStates {
        let mut s = PartStates::new();
        for &(id, x) in parts {
            s.push(PartState::new(id, 0, 0, [x, 0.0, 0.0], [0.0; 3])).expect("room");
        }
        s
    }

    #[test]
    fn trails_are_short_and_forget_parts_gone() {
        let mut t = Trails::default();
        for k in 0..100 {
            t.add(&states(&[(1, f64::from(k)), (2, 0.0)]));
        }
        assert_eq!(t.of(1).count(), TRAIL_POINTS);
        assert_eq!(t.of(1).last(), Some(&[99.0, 0.0]));
        assert_eq!(t.of(2).count(), 1, "a part at rest is one point");
        t.add(&states(&[(2, 0.0)]));
        assert_eq!(t.of(1).count(), 0);
    }
}
