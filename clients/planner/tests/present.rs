//! The `present` planner on synthetic part states: assignment, queueing,
//! pushing, holding, picking, hostile input, and a toy closed loop.

use ipc_types::{ForceEntry, ForceRequest, MAX_CURLS, PartState, PartStates};
use upm_planner::Planner;
use upm_planner::pick_assignment::Target;
use upm_planner::present::{PresentParams, PresentPlanner};
use upm_recipe::Recipe;

const PLATE: [f64; 2] = [1.0, 0.5];

fn default_recipe_path() -> String {
    format!("{}/../../recipes/default.toml", env!("CARGO_MANIFEST_DIR"))
}

/// The default recipe: class 0 (discs) at picks 0, 1; class 1 (squares)
/// at picks 2 (θ 0) and 3 (θ 45°). Tolerances 1 mm, 2°.
fn recipe() -> Recipe {
    Recipe::load(std::path::Path::new(&default_recipe_path()), PLATE).expect("default recipe")
}

fn planner() -> PresentPlanner {
    PresentPlanner::new(PresentParams { recipe: default_recipe_path(), ..Default::default() })
        .expect("builds")
}

/// Part states of (id, class, [x, y, θ]), at rest.
fn states(parts: &[(u32, u32, [f64; 3])]) -> PartStates {
    let mut s = PartStates::new();
    for &(id, class, pose) in parts {
        s.push(PartState::new(id, class, 0, pose, [0.0; 3])).expect("capacity");
    }
    s
}

fn plan(p: &mut PresentPlanner, s: &PartStates, t: f64) -> ForceRequest {
    let mut out = ForceRequest::new();
    p.plan(s, t, &mut out);
    out
}

fn entry(out: &ForceRequest, id: u32) -> Option<ForceEntry> {
    out.entries().iter().find(|e| e.part_id == id).copied()
}

fn pose_of(p: &PresentPlanner, id: u32) -> Option<usize> {
    match p.target(id) {
        Some(Target::Pose(i)) => Some(i),
        _ => None,
    }
}

#[test]
fn parts_are_given_poses_of_their_own_class() {
    let (r, mut p) = (recipe(), planner());
    let s = states(&[(1, 0, [-0.7, 0.1, 0.0]), (2, 1, [-0.7, -0.1, 0.0]), (3, 1, [-0.6, 0.3, 0.0])]);
    plan(&mut p, &s, 0.0);
    let poses: Vec<usize> = [1, 2, 3].iter().map(|&id| pose_of(&p, id).expect("a pose")).collect();
    assert_eq!(r.picks[poses[0]].class, 0);
    assert_eq!(r.picks[poses[1]].class, 1);
    assert_eq!(r.picks[poses[2]].class, 1);
    assert_ne!(poses[1], poses[2], "one part per pose");
    // Stable: the same poses next frame, wherever the parts went.
    let s = states(&[(1, 0, [0.6, -0.3, 0.0]), (2, 1, [0.8, 0.3, 0.0]), (3, 1, [0.8, -0.3, 0.0])]);
    plan(&mut p, &s, 0.1);
    let again: Vec<usize> = [1, 2, 3].iter().map(|&id| pose_of(&p, id).expect("a pose")).collect();
    assert_eq!(again, poses);
}

#[test]
fn a_part_whose_poses_are_taken_queues_off_every_pose() {
    let (r, mut p) = (recipe(), planner());
    let s = states(&[(1, 0, [-0.7, 0.1, 0.0]), (2, 0, [-0.7, -0.1, 0.0]), (3, 0, [-0.8, 0.0, 0.0])]);
    let out = plan(&mut p, &s, 0.0);
    assert!(pose_of(&p, 1).is_some() && pose_of(&p, 2).is_some());
    assert!(matches!(p.target(3), Some(Target::Spot(_))), "{:?}", p.target(3));
    let spot = p.goal(3).expect("a spot");
    let reach = 0.015 * 2f64.sqrt(); // the largest part, the square
    for q in &r.picks {
        let d = (spot[0] - q.position[0]).hypot(spot[1] - q.position[1]);
        assert!(d >= 0.015 + r.robot.clearance + reach, "spot {spot:?} within {q:?}'s clearance");
    }
    // It is pushed towards its spot, not a pose.
    let f = entry(&out, 3).and_then(|e| e.requested_force()).expect("force");
    let to = [spot[0] + 0.8, spot[1]];
    assert!(f[0] * to[0] + f[1] * to[1] > 0.99 * f[0].hypot(f[1]) * to[0].hypot(to[1]), "{f:?} {to:?}");
    assert_eq!(p.stats().queued_now, 1);
}

#[test]
fn the_force_points_at_the_target_and_a_square_turns_the_short_way() {
    let (r, mut p) = (recipe(), planner());
    // A square alone near pick 2 (θ 0), at 40°: it turns back 40°, not
    // on by 50°.
    let s = states(&[(5, 1, [0.82, 0.23, 40f64.to_radians()])]);
    let out = plan(&mut p, &s, 0.0);
    let i = pose_of(&p, 5).expect("a pose");
    assert_eq!(i, 2);
    let goal = r.picks[i].position;
    let e = entry(&out, 5).expect("entry");
    let f = e.requested_force().expect("force");
    let to = [goal[0] - 0.82, goal[1] - 0.23];
    let cos = (f[0] * to[0] + f[1] * to[1]) / (f[0].hypot(f[1]) * to[0].hypot(to[1]));
    assert!(cos > 0.999, "{f:?} towards {to:?}: cos {cos}");
    assert!(e.requested_curl().expect("a curl") < 0.0, "turns clockwise, back to 0°");
    // Far from its pose it travels unturned: a curl costs the whole plate.
    let s = states(&[(7, 1, [0.0, 0.2, 40f64.to_radians()])]);
    let out = plan(&mut planner(), &s, 0.0);
    assert_eq!(entry(&out, 7).and_then(|e| e.requested_curl()), None);
    // Discs are never turned.
    let s = states(&[(6, 0, [0.0, 0.0, 1.0])]);
    let out = plan(&mut planner(), &s, 0.0);
    assert_eq!(entry(&out, 6).and_then(|e| e.requested_curl()), None);
}

#[test]
fn touching_parts_are_pushed_apart() {
    // A disc heading right, alone and then with a square touching it on
    // its right: it is steered away from the square.
    let alone = plan(&mut planner(), &states(&[(1, 0, [0.0, 0.0, 0.0])]), 0.0);
    let s = states(&[(1, 0, [0.0, 0.0, 0.0]), (2, 1, [0.02, 0.0, 0.0])]);
    let both = plan(&mut planner(), &s, 0.0);
    let fx = |out: &ForceRequest| entry(out, 1).and_then(|e| e.requested_force()).expect("force")[0];
    assert!(fx(&both) < fx(&alone), "{} {}", fx(&both), fx(&alone));
    // Two parts at one point go opposite ways.
    let s = states(&[(1, 0, [-0.5, 0.0, 0.0]), (2, 0, [-0.5, 0.0, 0.0])]);
    let out = plan(&mut planner(), &s, 0.0);
    let f = |id| entry(&out, id).and_then(|e| e.requested_force()).expect("force");
    assert!(f(1)[0] < f(2)[0], "{:?} {:?}", f(1), f(2));
}

#[test]
fn a_part_within_tolerance_is_held_still() {
    let (r, mut p) = (recipe(), planner());
    // Pick 3 is θ 45°; the square lies at 135° (the same, turned 90°) and
    // 0.3 mm off, at rest; a disc 0.4 mm from pick 0.
    let q3 = r.picks[3].position;
    let q0 = r.picks[0].position;
    let s = states(&[(1, 1, [q3[0] + 3e-4, q3[1], 135f64.to_radians()]), (2, 0, [q0[0], q0[1] - 4e-4, 0.0])]);
    let out = plan(&mut p, &s, 0.0);
    assert_eq!((pose_of(&p, 1), pose_of(&p, 2)), (Some(3), Some(0)));
    for id in [1, 2] {
        let e = entry(&out, id).expect("entry");
        assert_eq!(e.requested_force(), Some([0.0, 0.0]), "part {id} held, not pushed");
        assert_eq!(e.requested_curl(), None);
    }
    assert_eq!(p.stats().presented_now, 2);
    // Held while moving: the force only takes its velocity off.
    let mut s2 = s;
    s2.parts_mut()[1].vx = 0.002;
    let out = plan(&mut p, &s2, 0.1);
    let f = entry(&out, 2).and_then(|e| e.requested_force()).expect("force");
    assert!(f[0] < 0.0 && f[1] == 0.0, "{f:?}");
    // 3 mm off is not presented: it is pushed to the pose.
    let s = states(&[(2, 0, [q0[0], q0[1] - 3e-3, 0.0])]);
    let out = plan(&mut p, &s, 0.2);
    let f = entry(&out, 2).and_then(|e| e.requested_force()).expect("force");
    assert!(f[1] > 0.0, "{f:?}");
}

#[test]
fn a_picked_part_frees_its_pose_for_the_next() {
    let (r, mut p) = (recipe(), planner());
    let (q0, q1) = (r.picks[0].position, r.picks[1].position);
    let s = states(&[(1, 0, [q0[0], q0[1], 0.0]), (2, 0, [q1[0], q1[1], 0.0]), (3, 0, [-0.8, 0.0, 0.0])]);
    plan(&mut p, &s, 0.0);
    assert!(matches!(p.target(3), Some(Target::Spot(_))));
    // The robot takes part 1: part 3 gets pick 0 in the same frame.
    let s = states(&[(2, 0, [q1[0], q1[1], 0.0]), (3, 0, [-0.8, 0.0, 0.0])]);
    plan(&mut p, &s, 0.1);
    assert_eq!(pose_of(&p, 3), Some(0));
    assert_eq!(p.target(1), None);
    let st = p.stats();
    assert_eq!((st.picked, st.lost), (1, 0));
}

#[test]
fn unknown_classes_and_repeated_ids_are_ignored_and_counted() {
    let mut p = planner();
    let s = states(&[(1, 7, [0.0, 0.0, 0.0]), (2, 0, [-0.5, 0.0, 0.0]), (2, 1, [0.3, 0.0, 0.0])]);
    for k in 0..3 {
        let out = plan(&mut p, &s, 0.1 * k as f64);
        assert_eq!(entry(&out, 1), None, "unknown class: no entry");
        assert_eq!(out.entries().iter().filter(|e| e.part_id == 2).count(), 1);
    }
    let st = p.stats();
    assert_eq!(st.unknown_class, 1, "counted once per part, not per frame");
    assert_eq!(st.duplicate_ids, 3);
    assert_eq!(p.target(1), None);
    // The first entry of a repeated id is the one planned for.
    assert!(matches!(p.target(2), Some(Target::Pose(0 | 1))));
}

#[test]
fn a_part_without_progress_gives_its_pose_up() {
    let (r, mut p) = (recipe(), planner());
    // Part 1 is stuck against something; part 3 waits for a class-0 pose.
    let q1 = r.picks[1].position;
    let frame = states(&[(1, 0, [0.2, 0.0, 0.0]), (2, 0, [q1[0], q1[1], 0.0]), (3, 0, [0.0, 0.2, 0.0])]);
    plan(&mut p, &frame, 0.0);
    let held = pose_of(&p, 1).expect("a pose");
    assert!(matches!(p.target(3), Some(Target::Spot(_))));
    let mut t = 0.0;
    while t < 25.0 {
        t += 0.5;
        plan(&mut p, &frame, t);
    }
    assert_eq!(p.stats().stuck, 1);
    assert_eq!(pose_of(&p, 3), Some(held), "the waiting part took the pose");
    assert!(matches!(p.target(1), Some(Target::Spot(_))));
    // A presented part is never stuck, however long the robot takes.
    assert_eq!(pose_of(&p, 2), Some(1));
}

#[test]
fn a_bad_recipe_is_one_line_naming_the_field() {
    for recipe in ["no/such/recipe.toml".to_string(), format!("{}/Cargo.toml", env!("CARGO_MANIFEST_DIR"))] {
        let e = PresentPlanner::new(PresentParams { recipe, ..Default::default() }).expect_err("refused");
        assert!(e.starts_with("planner.recipe: "), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
    // Through the config, as the process reads it.
    let c: upm_planner::PlannerConfig =
        toml::from_str("name = \"present\"\nrecipe = \"missing.toml\"\n").expect("parses");
    assert!(c.build().err().expect("refused").contains("planner.recipe"));
    let e = PresentPlanner::new(PresentParams { stuck_s: 0.0, ..Default::default() }).expect_err("refused");
    assert!(e.contains("planner.stuck_s"), "{e}");
}

/// A small deterministic generator (no dependency for it).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn unit(&mut self) -> f64 {
        self.next() as f64 / (1u64 << 31) as f64
    }
}

#[test]
fn any_ids_classes_and_poses_never_panic_and_give_valid_requests() {
    let mut p = planner();
    let mut rng = Lcg(7);
    let wild = [0.0, 1e-300, -1e300, f64::MAX, f64::MIN, 0.85, -0.25];
    for frame in 0..3000 {
        let mut s = PartStates::new();
        for _ in 0..rng.below(65) {
            // Few ids, so they repeat, vanish and come back; classes 0..4.
            let (id, class) = (rng.below(80) as u32, rng.below(4) as u32);
            let mut pose = [2.0 * rng.unit() - 1.0, rng.unit() - 0.5, 10.0 * rng.unit()];
            if rng.below(10) == 0 {
                pose[rng.below(3) as usize] = wild[rng.below(wild.len() as u64) as usize];
            }
            let v = [0.1 * rng.unit() - 0.05, 0.0, if rng.below(50) == 0 { f64::MAX } else { 0.0 }];
            let _ = s.push(PartState::new(id, class, 0, pose, v));
        }
        let out = plan(&mut p, &s, frame as f64 * 0.05);
        let e = out.entries();
        assert!(e.iter().all(|e| e.fx.is_finite() && e.fy.is_finite() && e.curl.is_finite()));
        assert!(out.curl_count() <= MAX_CURLS);
        for (i, a) in e.iter().enumerate() {
            assert!(e[..i].iter().all(|b| b.part_id != a.part_id), "id {} twice", a.part_id);
        }
    }
    let st = p.stats();
    assert!(st.unknown_class > 0 && st.duplicate_ids > 0, "{st:?}");
}

#[test]
fn parts_arriving_over_time_all_reach_their_poses_in_a_toy_world() {
    // Toy plate: each part accelerates by the force asked over its mass
    // and turns by the curl asked (ω' = curl / 2m), its spin damped;
    // a part is taken after lying within tolerance for settle_s + pick_s.
    let r = recipe();
    let mut p = planner();
    let params = PresentParams::default();
    let m = params.drive.part_mass;
    let (dt, spin_damping) = (0.02, 2.0);
    let arrivals: Vec<(u32, u32, [f64; 3])> = (0..8)
        .map(|i| {
            (i + 1, i % 2, [-0.8 + 0.05 * f64::from(i % 3), -0.3 + 0.08 * f64::from(i), 0.3 * f64::from(i)])
        })
        .collect();
    let mut on_plate: Vec<(PartState, f64)> = Vec::new(); // (state, time within tolerance)
    let (mut next, mut taken) = (0usize, 0u32);
    for step in 0..(400.0 / dt) as usize {
        let t = step as f64 * dt;
        if next < arrivals.len() && t >= 6.0 * next as f64 {
            let (id, class, pose) = arrivals[next];
            on_plate.push((PartState::new(id, class, 0, pose, [0.0; 3]), 0.0));
            next += 1;
        }
        let mut s = PartStates::new();
        for (part, _) in &on_plate {
            s.push(*part).expect("capacity");
        }
        let out = plan(&mut p, &s, t);
        for (part, settled) in &mut on_plate {
            let e = entry(&out, part.id).expect("every known part has an entry");
            let f = e.requested_force().unwrap_or([0.0; 2]);
            let curl = e.requested_curl().unwrap_or(0.0);
            (part.vx, part.vy) = (part.vx + f[0] / m * dt, part.vy + f[1] / m * dt);
            part.omega += (curl / (2.0 * m) - spin_damping * part.omega) * dt;
            (part.x, part.y, part.theta) =
                (part.x + part.vx * dt, part.y + part.vy * dt, part.theta + part.omega * dt);
            let ok = r.picks.iter().any(|q| {
                let order = if part.class == 0 { 0 } else { 4 };
                q.class == part.class
                    && (q.position[0] - part.x).hypot(q.position[1] - part.y) <= r.robot.tolerance
                    && upm_recipe::angle_error(part.theta, q.theta, order).abs() <= r.robot.tolerance_angle
            });
            *settled = if ok { *settled + dt } else { 0.0 };
        }
        let before = on_plate.len();
        on_plate.retain(|(_, settled)| *settled < r.robot.settle_s + r.robot.pick_s);
        taken += (before - on_plate.len()) as u32;
        if next == arrivals.len() && on_plate.is_empty() {
            break;
        }
    }
    // The planner sees the last pick in its next frame.
    plan(&mut p, &PartStates::new(), 400.0);
    let st = p.stats();
    assert_eq!(taken, 8, "left on the plate: {:?}", on_plate.iter().map(|(q, _)| q).collect::<Vec<_>>());
    assert_eq!((st.stuck, st.lost), (0, 0), "{st:?}");
    assert_eq!(st.picked, 8);
}

#[test]
fn a_request_keeps_within_its_rows_nearest_the_poses_first() {
    // Six discs: two with a pose (the nearer the first), four queued.
    let mut p = PresentPlanner::new(PresentParams {
        recipe: default_recipe_path(),
        max_rows: 6,
        ..Default::default()
    })
    .expect("planner");
    let s = states(&[
        (1, 0, [-0.8, 0.3, 0.0]),
        (2, 0, [0.6, -0.25, 0.0]),
        (3, 0, [-0.8, -0.3, 0.0]),
        (4, 0, [-0.7, 0.0, 0.0]),
        (5, 0, [-0.6, 0.2, 0.0]),
        (6, 0, [-0.6, -0.2, 0.0]),
    ]);
    let out = plan(&mut p, &s, 0.0);
    assert_eq!(out.entries().len(), 3, "6 rows: three forces");
    assert!(entry(&out, 1).is_some() && entry(&out, 2).is_some(), "the parts with a pose come first");
    assert!(
        PresentPlanner::new(PresentParams {
            recipe: default_recipe_path(),
            max_rows: 1,
            ..Default::default()
        })
        .is_err()
    );
}
