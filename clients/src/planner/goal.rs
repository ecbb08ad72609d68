//! The built-in planners share one controller: every part gets a desired
//! velocity towards its goal (speed-limited), and the requested force is
//! m·k_v·(v_desired − v), clamped to a fraction of μmg. What differs is the
//! goal: the side for `sort`, a point moving along a rectangle for `track`,
//! staying put (plus a curl) for `spin`, one goal and zero force on every
//! other part for `local`.

use ipc_types::{ForceEntry, ForceRequest, PartState, PartStates};

use super::{Planner, PlannerParams};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Track,
    Sort,
    Spin,
    Local,
}

#[derive(Debug)]
pub struct GoalPlanner {
    mode: Mode,
    p: PlannerParams,
    /// Start position per part id, for goals relative to the start.
    starts: Vec<(u32, [f64; 2])>,
    /// sort: where each held part is held.
    anchors: Vec<(u32, [f64; 2])>,
}

impl GoalPlanner {
    pub fn new(mode: Mode, p: PlannerParams) -> anyhow::Result<Self> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !(pos(p.max_speed) && pos(p.position_gain) && pos(p.velocity_gain) && pos(p.mu_m_g) && pos(p.mass))
        {
            anyhow::bail!("planner: max_speed, gains, mu_m_g and mass must be positive");
        }
        if !(p.max_force_fraction > 0.0 && p.max_force_fraction <= 1.0) {
            anyhow::bail!("planner.max_force_fraction must be in (0, 1]");
        }
        if !(p.sort_dodge_distance.is_finite() && p.sort_dodge_distance >= 0.0 && pos(p.sort_dodge_width)) {
            anyhow::bail!(
                "planner: sort_dodge_distance must be >= 0 (0: no dodging) and sort_dodge_width > 0"
            );
        }
        if mode == Mode::Track && (p.track_rects.is_empty() || !pos(p.track_speed)) {
            anyhow::bail!("planner: track needs track_rects and a positive track_speed");
        }
        Ok(Self { mode, p, starts: Vec::new(), anchors: Vec::new() })
    }

    /// Where a held part is held: set while it is driven, else where it was
    /// first seen.
    fn anchor_of(&mut self, part: &PartState) -> [f64; 2] {
        remembered(&mut self.anchors, part)
    }

    fn set_anchor(&mut self, id: u32, at: [f64; 2]) {
        match self.anchors.iter_mut().find(|(i, _)| *i == id) {
            Some((_, a)) => *a = at,
            None => self.anchors.push((id, at)),
        }
    }

    fn start_of(&mut self, part: &PartState) -> [f64; 2] {
        remembered(&mut self.starts, part)
    }

    /// Force that drives `part` to `goal` (with feed-forward velocity `vff`).
    fn force_to(&self, part: &PartState, goal: [f64; 2], vff: [f64; 2]) -> [f64; 2] {
        let p = &self.p;
        let mut vd =
            [vff[0] + p.position_gain * (goal[0] - part.x), vff[1] + p.position_gain * (goal[1] - part.y)];
        let s = vd[0].hypot(vd[1]);
        if s > p.max_speed {
            vd = [vd[0] * p.max_speed / s, vd[1] * p.max_speed / s];
        }
        let mut f =
            [p.mass * p.velocity_gain * (vd[0] - part.vx), p.mass * p.velocity_gain * (vd[1] - part.vy)];
        let fmax = p.max_force_fraction * p.mu_m_g;
        let n = f[0].hypot(f[1]);
        if n > fmax {
            f = [f[0] * fmax / n, f[1] * fmax / n];
        }
        f
    }
}

impl GoalPlanner {
    /// Drive the `sort_batch` unsorted parts nearest to their side (all of
    /// them, as in the paper, when the batch is large enough), steering
    /// around oncoming parts; leave the others free.
    fn plan_sort(&mut self, parts: &PartStates, out: &mut ForceRequest) -> bool {
        let x_goal = self.p.sort_x + 0.1;
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
        let active: Vec<&PartState> = todo.into_iter().take(self.p.sort_batch.max(1)).collect();
        for part in &active {
            // No pull back to a start row: a part keeps the row a dodge took
            // it to, so it does not steer back into the part it passed.
            let goal = [side(part) * (x_goal + 0.05), part.y];
            let vff = [0.0, self.dodge(part, parts)];
            if out.push(ForceEntry::force(part.id, self.force_to(part, goal, vff))).is_err() {
                return true;
            }
        }
        // Hold still the parts nearest to the driven ones, where they were
        // last driven (or first seen): a PD, since a bare zero force damps
        // nothing.
        for part in &active {
            self.set_anchor(part.id, [part.x, part.y]);
        }
        let dist =
            |p: &PartState| active.iter().map(|a| (a.x - p.x).hypot(a.y - p.y)).fold(f64::INFINITY, f64::min);
        let mut others: Vec<&PartState> =
            parts.parts().iter().filter(|p| active.iter().all(|a| a.id != p.id)).collect();
        others.sort_by(|a, b| dist(a).total_cmp(&dist(b)).then(a.id.cmp(&b.id)));
        let held = self.p.sort_hold.min(others.len());
        for part in &others[..held] {
            let anchor = self.anchor_of(part);
            if out.push(ForceEntry::force(part.id, self.force_to(part, anchor, [0.0; 2]))).is_err() {
                break;
            }
        }
        // A free part is held, when its turn comes, where it then is, not
        // where an earlier hold left it.
        for part in &others[held..] {
            self.set_anchor(part.id, [part.x, part.y]);
        }
        !out.is_empty()
    }
}

impl GoalPlanner {
    /// Sideways speed that takes `part` around the parts of the other class
    /// ahead of it in its lane: two parts heading for opposite sides
    /// otherwise meet head-on and push against each other for good.
    fn dodge(&self, part: &PartState, parts: &PartStates) -> f64 {
        let (reach, width) = (self.p.sort_dodge_distance, self.p.sort_dodge_width);
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
            vy += away * self.p.max_speed * (1.0 - dy.abs() / width) * (1.0 - ahead / reach);
        }
        vy.clamp(-self.p.max_speed, self.p.max_speed)
    }
}

/// sort: the side a part of `class` goes to, −1 (left, class 0) or +1.
pub fn sort_side(class: u32) -> f64 {
    if class == 0 { -1.0 } else { 1.0 }
}

/// The point remembered for `part`, or its current position, remembered now.
fn remembered(points: &mut Vec<(u32, [f64; 2])>, part: &PartState) -> [f64; 2] {
    if let Some((_, p)) = points.iter().find(|(id, _)| *id == part.id) {
        return *p;
    }
    points.push((part.id, [part.x, part.y]));
    [part.x, part.y]
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

impl Planner for GoalPlanner {
    fn name(&self) -> &'static str {
        match self.mode {
            Mode::Track => "track",
            Mode::Sort => "sort",
            Mode::Spin => "spin",
            Mode::Local => "local",
        }
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        if self.mode == Mode::Sort {
            return self.plan_sort(parts, out);
        }
        for part in parts.parts() {
            let start = self.start_of(part);
            let entry = match self.mode {
                // Planned as a whole by `plan_sort` above.
                Mode::Sort => continue,
                Mode::Track => {
                    // Parts without a path hold their start.
                    match self.p.track_rects.get(part.id.wrapping_sub(1) as usize) {
                        Some(&rect) => {
                            let (goal, dir) = rectangle_point(rect, self.p.track_speed * t);
                            let vff = [dir[0] * self.p.track_speed, dir[1] * self.p.track_speed];
                            ForceEntry::force(part.id, self.force_to(part, goal, vff))
                        }
                        None => ForceEntry::force(part.id, self.force_to(part, start, [0.0; 2])),
                    }
                }
                Mode::Spin => {
                    let f = self.force_to(part, start, [0.0; 2]);
                    if part.id == self.p.spin_id {
                        let err = self.p.spin_angle - part.theta;
                        let curl = (self.p.spin_gain * err).clamp(-self.p.max_curl, self.p.max_curl);
                        ForceEntry::force_and_curl(part.id, f, curl)
                    } else {
                        ForceEntry::force(part.id, f)
                    }
                }
                Mode::Local => {
                    if part.id == self.p.local_id {
                        ForceEntry::force(part.id, self.force_to(part, self.p.local_goal, [0.0; 2]))
                    } else {
                        // Everyone else holds its start. Not a bare zero-force
                        // constraint: with zero average force a part keeps
                        // whatever velocity it has (nothing damps it), so it
                        // gets the same PD as a driven part.
                        ForceEntry::force(part.id, self.force_to(part, start, [0.0; 2]))
                    }
                }
            };
            if out.push(entry).is_err() {
                break;
            }
        }
        !out.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn states(parts: &[(u32, u32, [f64; 2])]) -> PartStates {
        let mut s = PartStates::new();
        for &(id, class, [x, y]) in parts {
            s.push(PartState::new(id, class, 0, [x, y, 0.0], [0.0; 3])).expect("capacity");
        }
        s
    }

    fn sort_planner() -> GoalPlanner {
        GoalPlanner::new(Mode::Sort, PlannerParams::default()).expect("params")
    }

    #[test]
    fn head_on_parts_dodge_opposite_ways() {
        let p = sort_planner();
        // Black (heading left) just right of grey (heading right), same row.
        let s = states(&[(1, 0, [0.05, 0.1]), (2, 1, [0.0, 0.1])]);
        let (black, grey) = (p.dodge(&s.parts()[0], &s), p.dodge(&s.parts()[1], &s));
        assert!(black != 0.0 && grey != 0.0, "{black} {grey}");
        assert!(black.signum() != grey.signum(), "{black} {grey}");
        // Slightly offset rows: each moves away from the other.
        let s = states(&[(1, 0, [0.05, 0.11]), (2, 1, [0.0, 0.09])]);
        assert!(p.dodge(&s.parts()[0], &s) > 0.0 && p.dodge(&s.parts()[1], &s) < 0.0);
    }

    #[test]
    fn no_dodge_for_parts_behind_beside_or_of_the_same_class() {
        let p = sort_planner();
        // Grey behind black (black heads left, grey is to its right).
        let s = states(&[(1, 0, [0.0, 0.1]), (2, 1, [0.05, 0.1])]);
        assert_eq!(p.dodge(&s.parts()[0], &s), 0.0);
        // Far outside the lane, or beyond the look-ahead.
        let s = states(&[(1, 0, [0.05, 0.3]), (2, 1, [0.0, 0.1]), (3, 1, [-0.5, 0.3])]);
        assert_eq!(p.dodge(&s.parts()[0], &s), 0.0);
        // Same class ahead.
        let s = states(&[(1, 0, [0.05, 0.1]), (2, 0, [0.0, 0.1])]);
        assert_eq!(p.dodge(&s.parts()[0], &s), 0.0);
    }

    #[test]
    fn bad_dodge_parameters_are_refused() {
        for (distance, width) in [(-0.1, 0.06), (f64::NAN, 0.06), (0.15, 0.0), (0.15, f64::INFINITY)] {
            let p = PlannerParams {
                sort_dodge_distance: distance,
                sort_dodge_width: width,
                ..Default::default()
            };
            let e = GoalPlanner::new(Mode::Sort, p).expect_err("refused");
            assert!(e.to_string().contains("sort_dodge"), "{e}");
        }
        let off = PlannerParams { sort_dodge_distance: 0.0, ..Default::default() };
        let p = GoalPlanner::new(Mode::Sort, off).expect("0 turns dodging off");
        let s = states(&[(1, 0, [0.05, 0.1]), (2, 1, [0.0, 0.1])]);
        assert_eq!(p.dodge(&s.parts()[0], &s), 0.0);
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
}
