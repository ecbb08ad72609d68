//! `sort`: every part goes to the side of its class (class 0 to the left,
//! the others to the right), all of them at once and for good.
//!
//! Unlike the paper's planner (`sort_paper`) it never lets a part go: a
//! part on its side is *parked* at the park line, on a row of its own, and
//! stays in the request. So every request asks the same simple field,
//! class 0 leftwards and the rest rightwards, which a sparse cycle
//! (`motion.cycle_slots`) gives strongly; a part dropped from the request
//! would feel whatever that field happens to be where it lies, and be
//! pushed back or into its neighbours.

use ipc_types::{ForceEntry, ForceRequest, PartState, PartStates};
use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::drive::DriveParams;

/// `[planner]` with `name = "sort"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SortParams {
    pub drive: DriveParams,
    /// |x| a part must pass on its side.
    pub sorted_x: f64,
    /// |x| every part is driven to, and where a sorted part is parked.
    pub park_x: f64,
    /// Parked parts of one class keep at least this far apart in y (m).
    pub park_spacing: f64,
    /// Parking rows stay within |y| ≤ this (m).
    pub park_y_limit: f64,
    /// A part steers sideways around parts of the other class that are
    /// ahead of it closer than this (m; 0 turns dodging off) ...
    pub dodge_distance: f64,
    /// ... and within this (m) of its lane.
    pub dodge_width: f64,
}

impl Default for SortParams {
    fn default() -> Self {
        Self {
            drive: DriveParams::default(),
            sorted_x: 0.6,
            park_x: 0.9,
            park_spacing: 0.06,
            park_y_limit: 0.42,
            dodge_distance: 0.15,
            dodge_width: 0.06,
        }
    }
}

#[derive(Debug)]
pub struct SortPlanner {
    p: SortParams,
    /// Parking rows given so far: (part id, class, y), in the order given.
    taken: Vec<(u32, u32, f64)>,
}

impl SortPlanner {
    pub fn new(p: SortParams) -> Result<Self, String> {
        p.drive.validate()?;
        check_dodge(p.dodge_distance, p.dodge_width)?;
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !p.sorted_x.is_finite() {
            return Err(format!("planner.sorted_x must be finite, got {}", p.sorted_x));
        }
        if !(pos(p.park_x) && p.park_x >= p.sorted_x) {
            return Err(format!("planner.park_x must be finite and >= planner.sorted_x, got {}", p.park_x));
        }
        if !(pos(p.park_spacing) && pos(p.park_y_limit)) {
            return Err(format!(
                "planner.park_spacing and planner.park_y_limit must be positive, got {} and {}",
                p.park_spacing, p.park_y_limit
            ));
        }
        Ok(Self { p, taken: Vec::new() })
    }

    /// The parking row of `part`, chosen when it is first sorted: its own
    /// y, or the nearest y at least `park_spacing` from every row already
    /// given to its class (within ±`park_y_limit`).
    fn park_row(&mut self, part: &PartState) -> f64 {
        if let Some(&(_, _, y)) = self.taken.iter().find(|(id, _, _)| *id == part.id) {
            return y;
        }
        let (spacing, limit) = (self.p.park_spacing, self.p.park_y_limit);
        let free = |y: f64| {
            y.abs() <= limit
                && self.taken.iter().all(|&(_, class, t)| class != part.class || (t - y).abs() >= spacing)
        };
        let start = part.y.clamp(-limit, limit);
        let step = 0.25 * spacing;
        let y = (0..)
            .take(4 * ((2.0 * limit / step) as usize + 2))
            .map(|i: usize| {
                let d = step * i.div_ceil(2) as f64;
                if i % 2 == 1 { start + d } else { start - d }
            })
            .find(|&y| free(y))
            .unwrap_or(start);
        self.taken.push((part.id, part.class, y));
        y
    }
}

impl Planner for SortPlanner {
    fn name(&self) -> &'static str {
        "sort"
    }

    /// Every part in every request: toward the park line of its side
    /// (steering around oncoming parts), or parked on its row there.
    fn plan(&mut self, parts: &PartStates, _t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        for part in parts.parts() {
            let side = sort_side(part.class);
            let (goal, vff) = if side * part.x >= self.p.sorted_x {
                ([side * self.p.park_x, self.park_row(part)], [0.0; 2])
            } else {
                let vy =
                    dodge(part, parts, self.p.dodge_distance, self.p.dodge_width, self.p.drive.max_speed);
                ([side * self.p.park_x, part.y], [0.0, vy])
            };
            if out.push(ForceEntry::force(part.id, self.p.drive.force_to(part, goal, vff))).is_err() {
                break;
            }
        }
        !out.is_empty()
    }
}

/// sort: the side a part of `class` goes to, −1 (left, class 0) or +1.
pub fn sort_side(class: u32) -> f64 {
    if class == 0 { -1.0 } else { 1.0 }
}

/// The message names the fields.
pub(crate) fn check_dodge(distance: f64, width: f64) -> Result<(), String> {
    if !(distance.is_finite() && distance >= 0.0 && width.is_finite() && width > 0.0) {
        return Err(format!(
            "planner.dodge_distance must be >= 0 (0: no dodging) and planner.dodge_width > 0, got {distance} and {width}"
        ));
    }
    Ok(())
}

/// Sideways speed that takes `part` around the parts of the other class
/// ahead of it closer than `reach` and within `width` of its lane: two
/// parts heading for opposite sides otherwise meet head-on and push
/// against each other for good.
pub fn dodge(part: &PartState, parts: &PartStates, reach: f64, width: f64, max_speed: f64) -> f64 {
    let heading = sort_side(part.class);
    let mut vy = 0.0;
    for other in parts.parts().iter().filter(|o| o.class != part.class) {
        let ahead = (other.x - part.x) * heading;
        let dy = part.y - other.y;
        if ahead <= 0.0 || ahead >= reach || dy.abs() >= width {
            continue;
        }
        // Head-on: the classes pick opposite ways, so the two parts
        // never both dodge the same way.
        let away = if dy.abs() > 1e-3 { dy.signum() } else { -heading };
        vy += away * max_speed * (1.0 - dy.abs() / width) * (1.0 - ahead / reach);
    }
    vy.clamp(-max_speed, max_speed)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Part states of (id, class, position), at rest.
    pub(crate) fn states(parts: &[(u32, u32, [f64; 2])]) -> PartStates {
        let mut s = PartStates::new();
        for &(id, class, [x, y]) in parts {
            s.push(PartState::new(id, class, 0, [x, y, 0.0], [0.0; 3])).expect("capacity");
        }
        s
    }

    fn dodge_of(s: &PartStates, i: usize) -> f64 {
        dodge(&s.parts()[i], s, 0.15, 0.06, 0.04)
    }

    #[test]
    fn head_on_parts_dodge_opposite_ways() {
        // Black (heading left) just right of grey (heading right), same row.
        let s = states(&[(1, 0, [0.05, 0.1]), (2, 1, [0.0, 0.1])]);
        let (black, grey) = (dodge_of(&s, 0), dodge_of(&s, 1));
        assert!(black != 0.0 && grey != 0.0, "{black} {grey}");
        assert!(black.signum() != grey.signum(), "{black} {grey}");
        // Slightly offset rows: each moves away from the other.
        let s = states(&[(1, 0, [0.05, 0.11]), (2, 1, [0.0, 0.09])]);
        assert!(dodge_of(&s, 0) > 0.0 && dodge_of(&s, 1) < 0.0);
    }

    #[test]
    fn no_dodge_for_parts_behind_beside_or_of_the_same_class() {
        // Grey behind black (black heads left, grey is to its right).
        let s = states(&[(1, 0, [0.0, 0.1]), (2, 1, [0.05, 0.1])]);
        assert_eq!(dodge_of(&s, 0), 0.0);
        // Far outside the lane, or beyond the look-ahead.
        let s = states(&[(1, 0, [0.05, 0.3]), (2, 1, [0.0, 0.1]), (3, 1, [-0.5, 0.3])]);
        assert_eq!(dodge_of(&s, 0), 0.0);
        // Same class ahead.
        let s = states(&[(1, 0, [0.05, 0.1]), (2, 0, [0.0, 0.1])]);
        assert_eq!(dodge_of(&s, 0), 0.0);
    }

    #[test]
    fn bad_parameters_name_the_field() {
        for (distance, width) in [(-0.1, 0.06), (f64::NAN, 0.06), (0.15, 0.0), (0.15, f64::INFINITY)] {
            let p = SortParams { dodge_distance: distance, dodge_width: width, ..Default::default() };
            assert!(SortPlanner::new(p).expect_err("refused").contains("planner.dodge_"));
        }
        let p = SortParams { park_x: 0.5, ..Default::default() };
        assert!(SortPlanner::new(p).expect_err("inside sorted_x").contains("planner.park_x"));
        let p = SortParams { park_spacing: 0.0, ..Default::default() };
        assert!(SortPlanner::new(p).expect_err("no spacing").contains("planner.park_spacing"));
    }

    #[test]
    fn every_part_is_driven_and_sorted_parts_park_on_rows_of_their_own() {
        let mut p = SortPlanner::new(SortParams::default()).expect("defaults");
        // Two sorted black parts on nearly the same row, one unsorted grey.
        let s = states(&[(1, 0, [-0.7, 0.10]), (2, 0, [-0.65, 0.12]), (3, 1, [0.1, 0.0])]);
        let mut out = ForceRequest::new();
        assert!(p.plan(&s, 0.0, &mut out));
        assert_eq!(out.entries().len(), 3);
        let (y1, y2) = (p.park_row(&s.parts()[0]), p.park_row(&s.parts()[1]));
        assert_eq!(y1, 0.10);
        assert!((y1 - y2).abs() >= 0.06 - 1e-12, "{y1} {y2}");
        // Sorted parts are pushed outward, the grey one to the right.
        let f = |i: usize| out.entries()[i].requested_force().expect("force");
        assert!(f(0)[0] < 0.0 && f(1)[0] < 0.0 && f(2)[0] > 0.0);
        // A row is kept once given, even if the part drifts.
        let s = states(&[(1, 0, [-0.8, 0.3])]);
        assert!(p.plan(&s, 1.0, &mut out));
        assert_eq!(p.park_row(&s.parts()[0]), 0.10);
    }
}
