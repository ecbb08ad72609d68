//! `present`: a feed cell's planner. Parts of the recipe's classes arrive
//! at any time; each is given a free pick pose of its class
//! (`pick_assignment.rs`) or waits at a queue spot (`queue_spots.rs`), and
//! is pushed there and turned to the pose's angle (modulo its outline's
//! symmetry, `symmetry.rs`), all parts at once, touching parts pushed
//! apart. A part that comes within half the robot's tolerances is held
//! still until the robot takes it (it leaves `PartStates`), which frees
//! its pose.

use std::path::Path;

use ipc_types::{CapacityError, ForceEntry, ForceRequest, MAX_PARTS, PartState, PartStates};
use serde::{Deserialize, Serialize};
use upm_recipe::{Recipe, Robot};

use crate::Planner;
use crate::drive::DriveParams;
use crate::pick_assignment::{PickAssignment, Target};
use crate::queue_spots::{PoseZone, queue_spots};
use upm_recipe::angle_error;

/// A part is held once within this fraction of the robot's tolerances and
/// stays held until it leaves them: vision noise and the last drift after
/// the hold begins then keep it inside.
const HOLD_INSIDE: f64 = 0.5;

/// A part is turned only within this distance of its pose (m): a curl
/// constraint costs the whole plate's motion, so travelling parts spin freely.
const TURN_WITHIN: f64 = 0.05;

/// Queued parts come after every part with a pose (whose need is its
/// distance to it, m), the farthest off their spot (counting where their
/// speed takes them in `QUEUED_LOOKAHEAD_S`) first.
const QUEUED_NEED: f64 = 10.0;
const QUEUED_LOOKAHEAD_S: f64 = 1.0;

/// `[planner]` with `name = "present"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PresentParams {
    pub drive: DriveParams,
    /// The cell's recipe (relative: to the working directory).
    pub recipe: String,
    /// The plate's half extent (m), for the recipe's check and the queue
    /// spots; a launcher sets it from `[motion]` through
    /// `PlannerConfig::plate_half_extent_mut`.
    pub plate_half_extent: [f64; 2],
    /// Curl per radian of angle error (N/m/rad), and its limit.
    pub turn_gain: f64,
    pub max_curl: f64,
    /// Curl per rad/s of spin taken off (N/m·s/rad), as `spin`'s `damping`.
    pub turn_damping: f64,
    /// Gap kept between parts (m), beyond their outlines' reaches.
    pub gap: f64,
    /// A part with no progress to its pose for this long (s) is stuck: it
    /// gives the pose up, and takes none for as long.
    pub stuck_s: f64,
    /// Most rows (2 per constrained force, 1 per curl) a request asks:
    /// the core's sparse cycle has `[motion] cycle_slots` slots, and a
    /// request with more rows than that (less a margin) cannot be met, so
    /// every part gets the least-squares error. Parts are constrained in
    /// order of need: held and approaching parts first, then queued parts
    /// farthest from their spots; the rest are left free this frame.
    pub max_rows: usize,
}

impl Default for PresentParams {
    fn default() -> Self {
        Self {
            drive: DriveParams::default(),
            recipe: "recipes/default.toml".into(),
            plate_half_extent: [1.0, 0.5],
            turn_gain: 0.2,
            max_curl: 0.05,
            turn_damping: 0.0,
            gap: 0.005,
            stuck_s: 20.0,
            max_rows: 20,
        }
    }
}

/// What the planner has seen and done so far, and the parts now.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PresentStats {
    /// Parts that left the plate presented at their pose.
    pub picked: u64,
    /// Parts that left the plate otherwise.
    pub lost: u64,
    /// Parts released from their pose for lack of progress.
    pub stuck: u64,
    /// Parts (distinct ids on arrival) of a class not in the recipe, ignored.
    pub unknown_class: u64,
    /// Entries of `PartStates` repeating an id of the same frame, ignored.
    pub duplicate_ids: u64,
    /// Parts held at their pose, and waiting for one, in the last frame.
    pub presented_now: usize,
    pub queued_now: usize,
}

#[derive(Debug, Clone, Copy)]
struct ClassInfo {
    id: u32,
    reach: f64,
    order: Option<u32>,
}

/// One part of this frame, as the force pass needs it.
#[derive(Debug, Clone, Copy)]
struct Body {
    /// Into `PartStates::parts()`.
    index: usize,
    reach: f64,
    /// Its class is in the recipe: it gets an entry.
    known: bool,
    presented: bool,
    /// Where it is driven (None: it holds where it is).
    goal: Option<[f64; 2]>,
    /// Turn still to do (rad); None: no curl asked.
    turn: Option<f64>,
    /// Lower first: the order parts get rows of the request in.
    need: f64,
}

#[derive(Debug)]
pub struct PresentPlanner {
    p: PresentParams,
    recipe: Recipe,
    robot: Robot,
    classes: Vec<ClassInfo>,
    assignment: PickAssignment,
    /// Per-frame scratch, never beyond `MAX_PARTS`.
    bodies: Vec<Body>,
    frame: Vec<(u32, u32, [f64; 2])>,
    /// Known bodies (into `bodies`), in order of need.
    by_need: Vec<usize>,
    /// Ids of unknown class in the last frame (to count each once).
    unknown: Vec<u32>,
    unknown_next: Vec<u32>,
    stats: PresentStats,
}

impl PresentPlanner {
    pub fn new(p: PresentParams) -> Result<Self, String> {
        p.drive.validate()?;
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !p.plate_half_extent.iter().all(|h| positive(*h)) {
            return Err(format!("planner.plate_half_extent must be positive, got {:?}", p.plate_half_extent));
        }
        for (name, v) in [("turn_gain", p.turn_gain), ("max_curl", p.max_curl), ("stuck_s", p.stuck_s)] {
            if !positive(v) {
                return Err(format!("planner.{name} must be positive, got {v}"));
            }
        }
        if p.max_rows < 2 {
            return Err(format!("planner.max_rows must be >= 2, got {}", p.max_rows));
        }
        for (name, v) in [("turn_damping", p.turn_damping), ("gap", p.gap)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("planner.{name} must be >= 0, got {v}"));
            }
        }
        let recipe = Recipe::load(Path::new(&p.recipe), p.plate_half_extent)
            .map_err(|e| format!("planner.recipe: {e}"))?;
        Ok(Self::with_recipe(p, &recipe))
    }

    /// The planner for an already checked `recipe` (`p.recipe` unused).
    pub fn with_recipe(p: PresentParams, recipe: &Recipe) -> Self {
        let classes: Vec<ClassInfo> = recipe
            .classes
            .iter()
            .map(|c| ClassInfo {
                id: c.id,
                reach: c.outline.reach(),
                order: Some(c.outline.symmetry_order()).filter(|&n| n > 0),
            })
            .collect();
        let spots = spots_for(&p, recipe, &classes);
        Self {
            assignment: PickAssignment::new(recipe.picks.clone(), spots, p.stuck_s),
            recipe: recipe.clone(),
            robot: recipe.robot,
            classes,
            bodies: Vec::with_capacity(MAX_PARTS),
            frame: Vec::with_capacity(MAX_PARTS),
            by_need: Vec::with_capacity(MAX_PARTS),
            unknown: Vec::with_capacity(MAX_PARTS),
            unknown_next: Vec::with_capacity(MAX_PARTS),
            stats: PresentStats::default(),
            p,
        }
    }

    pub fn stats(&self) -> PresentStats {
        let c = self.assignment.counts();
        PresentStats { picked: c.picked, lost: c.lost, stuck: c.stuck, ..self.stats }
    }

    /// Where `id` is sent (None: not a part of a known class on the plate).
    pub fn target(&self, id: u32) -> Option<Target> {
        self.assignment.target(id)
    }

    /// Where `id` is driven: its pose's or its queue spot's position (None:
    /// it holds where it is, or is not tracked).
    pub fn goal(&self, id: u32) -> Option<[f64; 2]> {
        match self.assignment.target(id)? {
            Target::Pose(i) => self.assignment.pose(i).map(|q| q.position),
            Target::Spot(i) => self.assignment.spot(i),
            Target::Stay => None,
        }
    }

    /// This frame's parts, once each; unknown classes and repeated ids counted.
    fn collect(&mut self, parts: &[PartState]) {
        self.bodies.clear();
        self.frame.clear();
        self.unknown_next.clear();
        let largest = self.classes.iter().map(|c| c.reach).fold(0.0, f64::max);
        let plate = self.p.plate_half_extent[0].max(self.p.plate_half_extent[1]);
        for (index, part) in parts.iter().enumerate() {
            if self.bodies.iter().any(|b| parts[b.index].id == part.id) {
                self.stats.duplicate_ids += 1;
                continue;
            }
            let class = self.classes.iter().find(|c| c.id == part.class);
            let reach = match class {
                Some(c) => c.reach,
                // Still an obstacle: its own outline's size if it says one.
                None if part.radius.is_finite() && part.radius > 0.0 => part.radius.min(plate),
                None => largest,
            };
            if class.is_some() {
                self.frame.push((part.id, part.class, [part.x, part.y]));
            } else {
                if !self.unknown.contains(&part.id) {
                    self.stats.unknown_class += 1;
                }
                self.unknown_next.push(part.id);
            }
            let known = class.is_some();
            self.bodies.push(Body {
                index,
                reach,
                known,
                presented: false,
                goal: None,
                turn: None,
                need: f64::INFINITY,
            });
        }
        std::mem::swap(&mut self.unknown, &mut self.unknown_next);
    }

    /// Each known part's goal, turn and whether it is presented; stuck
    /// parts are released here.
    fn targets(&mut self, parts: &[PartState], t: f64) {
        let (tol, tol_angle) = (self.robot.tolerance, self.robot.tolerance_angle);
        let (mut presented_now, mut queued_now) = (0, 0);
        for b in self.bodies.iter_mut().filter(|b| b.known) {
            let part = &parts[b.index];
            let order = self.classes.iter().find(|c| c.id == part.class).and_then(|c| c.order);
            match self.assignment.target(part.id) {
                Some(Target::Pose(i)) => {
                    let Some(pose) = self.assignment.pose(i).copied() else { continue };
                    let d = (pose.position[0] - part.x).hypot(pose.position[1] - part.y);
                    // The turn from the part to the pose: minus its error.
                    let turn = -angle_error(part.theta, pose.theta, order.unwrap_or(0));
                    let within = |k: f64| d <= k * tol && turn.abs() <= k * tol_angle;
                    let was = self.assignment.presented(part.id);
                    b.presented = within(if was { 1.0 } else { HOLD_INSIDE });
                    let error = d + b.reach * turn.abs();
                    if self.assignment.progress(part.id, error, b.presented, t) {
                        continue; // Released as stuck: it holds this frame, queues next.
                    }
                    b.goal = Some(pose.position);
                    b.turn = order.filter(|_| d <= TURN_WITHIN).map(|_| turn);
                    b.need = if b.presented { -1.0 } else { d };
                    presented_now += usize::from(b.presented);
                }
                Some(Target::Spot(i)) => {
                    b.goal = self.assignment.spot(i);
                    let off = b.goal.map_or(0.0, |g| (g[0] - part.x).hypot(g[1] - part.y));
                    b.need = QUEUED_NEED - off - QUEUED_LOOKAHEAD_S * part.vx.hypot(part.vy);
                    queued_now += 1;
                }
                Some(Target::Stay) | None => {
                    b.need = QUEUED_NEED - QUEUED_LOOKAHEAD_S * part.vx.hypot(part.vy);
                    queued_now += 1;
                }
            }
        }
        (self.stats.presented_now, self.stats.queued_now) = (presented_now, queued_now);
    }

    /// Feed-forward velocity pushing body `k` away from every part it is
    /// closer to than their reaches plus the gap (plus the clearance of a
    /// presented part: the gripper's room).
    fn repulsion(&self, parts: &[PartState], k: usize) -> [f64; 2] {
        let me = &self.bodies[k];
        let (p, vmax) = (&parts[me.index], self.p.drive.max_speed);
        let mut v = [0.0; 2];
        for (j, other) in self.bodies.iter().enumerate().filter(|(j, _)| *j != k) {
            let o = &parts[other.index];
            let room = if other.presented { self.robot.clearance } else { self.p.gap };
            let limit = me.reach + other.reach + room;
            let (dx, dy) = (p.x - o.x, p.y - o.y);
            let d = dx.hypot(dy);
            if d >= limit || d.is_nan() {
                continue;
            }
            // Two parts at one point: the ids pick opposite ways.
            let dir = if d > 1e-9 {
                [dx / d, dy / d]
            } else if (p.id, k) < (o.id, j) {
                [-1.0, 0.0]
            } else {
                [1.0, 0.0]
            };
            let w = vmax * (1.0 - d / limit);
            v = [v[0] + w * dir[0], v[1] + w * dir[1]];
        }
        let s = v[0].hypot(v[1]);
        if s > vmax { [v[0] * vmax / s, v[1] * vmax / s] } else { v }
    }

    /// Body `k`'s entry: held still when presented, else driven (and
    /// turned) to its goal, away from its neighbours.
    fn entry(&self, parts: &[PartState], k: usize) -> ForceEntry {
        let b = &self.bodies[k];
        let part = &parts[b.index];
        let drive = &self.p.drive;
        // Holding: the goal is where it is, i.e. only its velocity is taken off.
        let here = [part.x, part.y];
        if b.presented {
            return ForceEntry::force(part.id, finite(drive.force_to(part, here, [0.0; 2])));
        }
        let f = finite(drive.force_to(part, b.goal.unwrap_or(here), self.repulsion(parts, k)));
        match b.turn {
            Some(turn) => {
                let curl = (self.p.turn_gain * turn - self.p.turn_damping * part.omega)
                    .clamp(-self.p.max_curl, self.p.max_curl);
                ForceEntry::force_and_curl(part.id, f, if curl.is_finite() { curl } else { 0.0 })
            }
            None => ForceEntry::force(part.id, f),
        }
    }
}

/// Arbitrary (huge) poses may overflow to a non-finite force; ask none then.
/// Where parts wait for a pose of `recipe`: clear of its poses and its
/// infeed.
fn spots_for(p: &PresentParams, recipe: &Recipe, classes: &[ClassInfo]) -> Vec<[f64; 2]> {
    let reach_of = |class: u32| classes.iter().find(|c| c.id == class).map_or(0.0, |c| c.reach);
    let zones: Vec<PoseZone> =
        recipe.picks.iter().map(|q| PoseZone { position: q.position, reach: reach_of(q.class) }).collect();
    let largest = classes.iter().map(|c| c.reach).fold(0.0, f64::max);
    queue_spots(
        &zones,
        Some(recipe.infeed.region),
        largest,
        recipe.robot.clearance,
        p.gap,
        p.plate_half_extent,
        MAX_PARTS,
    )
}

fn finite(f: [f64; 2]) -> [f64; 2] {
    if f.iter().all(|x| x.is_finite()) { f } else { [0.0; 2] }
}

impl Planner for PresentPlanner {
    fn name(&self) -> &'static str {
        "present"
    }

    fn recipe_changed(&mut self, path: &str) -> Result<bool, String> {
        let next = Recipe::load(Path::new(path), self.p.plate_half_extent).map_err(|e| e.to_string())?;
        if next == self.recipe {
            return Ok(false);
        }
        self.recipe.check_changeover(&next).map_err(|e| format!("{path}: {e}"))?;
        let spots = spots_for(&self.p, &next, &self.classes);
        self.assignment.changeover(next.picks.clone(), spots);
        self.robot = next.robot;
        self.recipe = next;
        Ok(true)
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        let parts = parts.parts();
        self.collect(parts);
        self.assignment.update(&self.frame, t);
        self.targets(parts, t);
        let mut by_need = std::mem::take(&mut self.by_need);
        by_need.clear();
        by_need.extend((0..self.bodies.len()).filter(|&k| self.bodies[k].known));
        by_need.sort_by(|&a, &b| self.bodies[a].need.total_cmp(&self.bodies[b].need).then(a.cmp(&b)));
        let mut rows = 0;
        for &k in &by_need {
            if rows + 2 > self.p.max_rows {
                break;
            }
            let mut entry = self.entry(parts, k);
            if entry.curl_flag != 0 && rows + 3 > self.p.max_rows {
                (entry.curl_flag, entry.curl) = (0, 0.0);
            }
            let pushed = match out.push(entry) {
                // More turning parts than curls: this one only moves.
                Err(CapacityError::CurlsFull { .. }) => {
                    entry = ForceEntry { curl_flag: 0, curl: 0.0, ..entry };
                    out.push(entry)
                }
                r => r,
            };
            if pushed.is_err() {
                break;
            }
            rows += 2 + usize::from(entry.curl_flag != 0);
        }
        self.by_need = by_need;
        !out.is_empty()
    }
}
