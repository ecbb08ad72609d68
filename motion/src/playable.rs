//! What |k| a rotation about one center can play on a rig: the slot must
//! be buildable within the motion limits (`PlateMotion::max_playable_k`)
//! and every actuator must follow it within its stroke, speed and force
//! (`Rig::check_motion`), turning either way. Per center, because a center
//! far from the plate turns the plate through a small angle but swings its
//! far corner fast, while one at the middle does the opposite.

use super::{PlateMotion, Rig, ScheduleEntry};

/// Bisection steps on the actuator check: the bound to 2⁻³⁰ of k_max.
const BISECTIONS: usize = 30;

/// The largest |k| ≤ `k_max` a slot about `center` plays within the motion
/// limits of `probe` and the actuator limits of `rig` (0 if none). `probe`
/// is scratch: its schedule is overwritten.
pub fn playable_k(probe: &mut PlateMotion, rig: &Rig, center: [f64; 2], k_max: f64) -> f64 {
    let top = k_max.min(probe.max_playable_k(center));
    let mut plays = |k: f64| {
        [k, -k].iter().all(|&k| {
            probe.set_schedule(&[ScheduleEntry { center, k }]).is_ok() && rig.check_motion(probe).is_ok()
        })
    };
    if !(top > 0.0) || plays(top) {
        return top.max(0.0);
    }
    let (mut lo, mut hi) = (0.0, top);
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if plays(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}
