//! Multi-part tracking for the camera: detections carry no ids, so each is
//! associated to the nearest predicted track within a gate; an alpha-beta
//! filter per track smooths position and estimates velocity. A polygon's
//! angle is seen modulo its symmetry; its track's angle is continuous from
//! the first sighting on. A track carries the outline of its latest
//! detection.

use crate::VisionSection;
use crate::class_outline::{BodyOutline, wrap_period};

/// One detection in a frame (what a camera sees: where, which class).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
    pub class: u32,
    /// The angle after which the part looks the same (rad): 90° for a
    /// square; 0 when the angle is not wrapped.
    pub period: f64,
    /// The part's contact outline in its own frame.
    pub outline: BodyOutline,
}

/// One tracked part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Track {
    pub id: u32,
    pub class: u32,
    /// Filtered pose (x, y, θ) and rates.
    pub pose: [f64; 3],
    pub velocity: [f64; 3],
    /// Consecutive frames without a matching detection.
    pub missed: u32,
    /// The outline of the latest matched detection.
    pub outline: BodyOutline,
}

/// Tracks a tracker keeps at most; more new parts wait for a free slot.
pub const MAX_TRACKS: usize = 4 * ipc_types::MAX_PARTS;

/// Runs on `[vision]`'s `alpha`, `beta`, `gate_mm` and `max_missed_frames`.
#[derive(Debug, Clone)]
pub struct Tracker {
    params: VisionSection,
    tracks: Vec<Track>,
    next_id: u32,
    // Scratch, sized once: an update allocates nothing.
    predicted: Vec<[f64; 3]>,
    pairs: Vec<(f64, usize, usize)>,
    track_used: Vec<bool>,
    det_used: Vec<bool>,
    /// Candidate pairs and new tracks that did not fit (counted, dropped).
    pub overflow: u64,
}

impl Tracker {
    pub fn new(params: &VisionSection) -> Self {
        Self {
            params: params.clone(),
            tracks: Vec::with_capacity(MAX_TRACKS),
            next_id: 1,
            predicted: Vec::with_capacity(MAX_TRACKS),
            pairs: Vec::with_capacity(MAX_TRACKS * 8),
            track_used: Vec::with_capacity(MAX_TRACKS),
            det_used: Vec::with_capacity(MAX_TRACKS),
            overflow: 0,
        }
    }

    pub fn tracks(&self) -> &[Track] {
        &self.tracks
    }

    /// Update with one frame taken `dt` seconds after the previous one.
    /// Greedy nearest-neighbour association, closest pairs first; new
    /// tracks get ids in detection order.
    pub fn update(&mut self, detections: &[Detection], dt: f64) {
        let p = &self.params;
        // Detections beyond what the scratch holds are not considered.
        let detections = &detections[..detections.len().min(MAX_TRACKS)];
        self.predicted.clear();
        self.predicted.extend(self.tracks.iter().map(|t| [0, 1, 2].map(|k| t.pose[k] + t.velocity[k] * dt)));
        self.pairs.clear();
        for (ti, pr) in self.predicted.iter().enumerate() {
            for (di, d) in detections.iter().enumerate() {
                let dist = (d.x - pr[0]).hypot(d.y - pr[1]);
                if dist <= p.gate_m && d.class == self.tracks[ti].class {
                    if self.pairs.len() == self.pairs.capacity() {
                        self.overflow += 1;
                        continue;
                    }
                    self.pairs.push((dist, ti, di));
                }
            }
        }
        // A total order (distance, track, detection): unstable sorting
        // gives the same result and allocates nothing.
        self.pairs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        self.track_used.clear();
        self.track_used.resize(self.tracks.len(), false);
        self.det_used.clear();
        self.det_used.resize(detections.len(), false);
        for &(_, ti, di) in &self.pairs {
            if self.track_used[ti] || self.det_used[di] {
                continue;
            }
            self.track_used[ti] = true;
            self.det_used[di] = true;
            let d = detections[di];
            let t = &mut self.tracks[ti];
            let z = [d.x, d.y, d.theta];
            let predicted = self.predicted[ti];
            for (k, (zk, pk)) in z.into_iter().zip(predicted).enumerate() {
                let mut r = zk - pk;
                if k == 2 {
                    // A square seen at 89° may be one at -1°: the residual
                    // is taken modulo the symmetry, so the track's angle
                    // stays continuous (a part turned by 90° reads 90°).
                    r = wrap_period(r, d.period);
                }
                t.pose[k] = pk + p.alpha * r;
                if dt > 0.0 {
                    t.velocity[k] += p.beta * r / dt;
                }
            }
            t.missed = 0;
            t.outline = d.outline;
        }
        for (ti, used) in self.track_used.iter().enumerate() {
            if !used {
                let t = &mut self.tracks[ti];
                t.pose = self.predicted[ti];
                t.missed += 1;
            }
        }
        self.tracks.retain(|t| t.missed <= p.max_missed_frames);
        for (di, d) in detections.iter().enumerate() {
            if !self.det_used[di] {
                if self.tracks.len() == self.tracks.capacity() {
                    self.overflow += 1;
                    continue;
                }
                self.tracks.push(Track {
                    id: self.next_id,
                    class: d.class,
                    pose: [d.x, d.y, d.theta],
                    velocity: [0.0; 3],
                    missed: 0,
                    outline: d.outline,
                });
                self.next_id += 1;
            }
        }
    }
}
