//! What |k| each center can play (`motion::playable_k`): the bound plays
//! both ways within the motion and actuator limits, a little more does not,
//! it differs from center to center, and a schedule of every center at its
//! own bound passes the actuator check (slots are independent).

use upm_motion::{MotionParams, PlateMotion, Rig, RigParams, ScheduleEntry, playable_k};

fn plays(m: &mut PlateMotion, rig: &Rig, center: [f64; 2], k: f64) -> bool {
    [k, -k]
        .iter()
        .all(|&k| m.set_schedule(&[ScheduleEntry { center, k }]).is_ok() && rig.check_motion(m).is_ok())
}

#[test]
fn each_center_gets_its_own_playable_bound() {
    // A 6 mm stroke: the bound falls below k_max for some centers only.
    let p = MotionParams { displacement: 6e-3, ..MotionParams::default() };
    let rig = Rig::new(RigParams::default()).expect("rig");
    let mut m = PlateMotion::new(p).expect("motion");
    let centers: Vec<[f64; 2]> =
        (0..7).flat_map(|i| (0..5).map(move |j| [-1.4 + 0.45 * i as f64, -0.8 + 0.4 * j as f64])).collect();
    let bounds: Vec<f64> = centers.iter().map(|&c| playable_k(&mut m, &rig, c, p.k_max)).collect();
    for (&c, &u) in centers.iter().zip(&bounds) {
        assert!(u > 0.0 && u <= p.k_max, "{c:?}: {u}");
        assert!(plays(&mut m, &rig, c, u), "{c:?}: its bound {u} does not play");
        if u < p.k_max {
            assert!(!plays(&mut m, &rig, c, u * 1.001), "{c:?}: {u} is not the largest");
        }
    }
    let (lo, hi) = bounds.iter().fold((f64::MAX, 0.0f64), |(a, b), &u| (a.min(u), b.max(u)));
    assert!(hi > 1.05 * lo, "bounds {lo}..{hi}: no center differs");
    // Every center at its own bound, signs alternating, in one schedule.
    let all: Vec<ScheduleEntry> = centers
        .iter()
        .zip(&bounds)
        .enumerate()
        .map(|(i, (&center, &u))| ScheduleEntry { center, k: if i % 2 == 0 { u } else { -u } })
        .collect();
    m.set_schedule(&all).expect("motion limits");
    rig.check_motion(&m).expect("actuator limits");
}

#[test]
fn a_center_that_cannot_play_gets_zero() {
    // An absurd stroke: no rotation fits the actuators' travel.
    let p = MotionParams { displacement: 0.5, ..MotionParams::default() };
    let rig = Rig::new(RigParams::default()).expect("rig");
    let mut m = PlateMotion::new(p).expect("motion");
    assert_eq!(playable_k(&mut m, &rig, [0.0, 0.0], p.k_max), 0.0);
}
