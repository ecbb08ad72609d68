//! `sort_paper` (paper §4.2, the baseline of `upm bench sort`): every part
//! goes to the side of its class, class 0 to the left, the others to the
//! right; a part leaves the request once it is on its side.

use ipc_types::{ForceEntry, ForceRequest, PartState, PartStates};
use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::drive::{DriveParams, PartPoints};
use crate::sort::{dodge, sort_side};

/// `[planner]` with `name = "sort_paper"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PaperSortParams {
    pub drive: DriveParams,
    /// |x| a part must pass on its side.
    pub sorted_x: f64,
    /// Parts driven at once (the nearest to their side first); the rest are
    /// left unconstrained. The paper drives all of them.
    pub batch: usize,
    /// That many other parts nearest to the driven ones are held where they
    /// were last driven (a PD, like the driven parts), so the field does not
    /// drag them along.
    pub hold: usize,
    /// A part steers sideways around parts of the other class that are
    /// ahead of it closer than this (m; 0 turns dodging off) ...
    pub dodge_distance: f64,
    /// ... and within this (m) of its lane.
    pub dodge_width: f64,
}

impl Default for PaperSortParams {
    fn default() -> Self {
        Self {
            drive: DriveParams::default(),
            sorted_x: 0.6,
            batch: ipc_types::MAX_PARTS,
            hold: 0,
            dodge_distance: 0.15,
            dodge_width: 0.06,
        }
    }
}

#[derive(Debug)]
pub struct PaperSortPlanner {
    p: PaperSortParams,
    /// Where each held part is held: set while it is driven, else where it
    /// was first seen.
    anchors: PartPoints,
}

impl PaperSortPlanner {
    pub fn new(p: PaperSortParams) -> Result<Self, String> {
        p.drive.validate()?;
        crate::sort::check_dodge(p.dodge_distance, p.dodge_width)?;
        if !p.sorted_x.is_finite() {
            return Err(format!("planner.sorted_x must be finite, got {}", p.sorted_x));
        }
        Ok(Self { p, anchors: PartPoints::default() })
    }
}

impl Planner for PaperSortPlanner {
    fn name(&self) -> &'static str {
        "sort_paper"
    }

    /// Drive the `batch` unsorted parts nearest to their side (all of
    /// them, as in the paper, when the batch is large enough), steering
    /// around oncoming parts; leave the others free.
    fn plan(&mut self, parts: &PartStates, _t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        let x_goal = self.p.sorted_x + 0.1;
        let side = |p: &PartState| sort_side(p.class);
        let mut todo: Vec<&PartState> = parts.parts().iter().filter(|p| side(p) * p.x < x_goal).collect();
        todo.sort_by(|a, b| {
            (x_goal - side(a) * a.x).total_cmp(&(x_goal - side(b) * b.x)).then(a.id.cmp(&b.id))
        });
        if todo.is_empty() {
            // Done: ask for zero force everywhere, so the plate rests on an
            // explicit request rather than on the core's stale-input hold.
            for part in parts.parts() {
                if out.push(ForceEntry::force(part.id, [0.0; 2])).is_err() {
                    break;
                }
            }
            return !out.is_empty();
        }
        let active: Vec<&PartState> = todo.into_iter().take(self.p.batch.max(1)).collect();
        for part in &active {
            // No pull back to a start row: a part keeps the row a dodge took
            // it to, so it does not steer back into the part it passed.
            let goal = [side(part) * (x_goal + 0.05), part.y];
            let vff =
                [0.0, dodge(part, parts, self.p.dodge_distance, self.p.dodge_width, self.p.drive.max_speed)];
            if out.push(ForceEntry::force(part.id, self.p.drive.force_to(part, goal, vff))).is_err() {
                return true;
            }
        }
        // Hold still the parts nearest to the driven ones, where they were
        // last driven (or first seen): a PD, since a bare zero force damps
        // nothing.
        for part in &active {
            self.anchors.set(part.id, [part.x, part.y]);
        }
        let dist =
            |p: &PartState| active.iter().map(|a| (a.x - p.x).hypot(a.y - p.y)).fold(f64::INFINITY, f64::min);
        let mut others: Vec<&PartState> =
            parts.parts().iter().filter(|p| active.iter().all(|a| a.id != p.id)).collect();
        others.sort_by(|a, b| dist(a).total_cmp(&dist(b)).then(a.id.cmp(&b.id)));
        let held = self.p.hold.min(others.len());
        for part in &others[..held] {
            let anchor = self.anchors.get_or_remember(part);
            if out.push(ForceEntry::force(part.id, self.p.drive.force_to(part, anchor, [0.0; 2]))).is_err() {
                break;
            }
        }
        // A free part is held, when its turn comes, where it then is, not
        // where an earlier hold left it.
        for part in &others[held..] {
            self.anchors.set(part.id, [part.x, part.y]);
        }
        !out.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sort::tests::states;

    fn sort_planner() -> PaperSortPlanner {
        PaperSortPlanner::new(PaperSortParams::default()).expect("params")
    }

    #[test]
    fn bad_dodge_parameters_are_refused() {
        for (distance, width) in [(-0.1, 0.06), (f64::NAN, 0.06), (0.15, 0.0), (0.15, f64::INFINITY)] {
            let p = PaperSortParams { dodge_distance: distance, dodge_width: width, ..Default::default() };
            let e = PaperSortPlanner::new(p).expect_err("refused");
            assert!(e.contains("planner.dodge_"), "{e}");
        }
    }

    #[test]
    fn a_finished_sort_asks_for_zero_force_instead_of_going_stale() {
        let mut p = sort_planner();
        let s = states(&[(1, 0, [-0.8, 0.0]), (2, 1, [0.8, 0.1])]);
        let mut out = ForceRequest::new();
        assert!(p.plan(&s, 0.0, &mut out));
        assert_eq!(out.entries().len(), 2);
        assert!(out.entries().iter().all(|e| e.requested_force() == Some([0.0; 2])));
    }

    #[test]
    fn only_unsorted_parts_are_driven() {
        let mut p = sort_planner();
        let s = states(&[(1, 0, [-0.8, 0.0]), (2, 1, [0.1, 0.1])]);
        let mut out = ForceRequest::new();
        assert!(p.plan(&s, 0.0, &mut out));
        assert_eq!(out.entries().len(), 1);
        assert_eq!(out.entries()[0].part_id, 2);
        assert!(out.entries()[0].requested_force().expect("force")[0] > 0.0);
    }
}
