//! The feed cell around the simulator: arrivals at the recipe's rate that
//! never overfill the plate or land on a part; the robot takes a settled
//! part at a pose of its class within tolerance (modulo the outline's
//! symmetry) and a clear gripper, and nothing else; the ground truth shows
//! the parts on the plate with their ids; same seed, same cell; the cell's
//! step allocates nothing.

use drivers::feed::{FeedCell, RobotMode};
use drivers::{PartState, SimConfig, Simulator};
use rt_core::alloc_count::{RtAllocCounter, allocations_in};
use upm_recipe::Recipe;

#[global_allocator]
static A: RtAllocCounter = RtAllocCounter;

const DEFAULT: &str = include_str!("../../recipes/default.toml");

/// The default recipe with `edits` applied, on a still 1 kHz plate.
fn cell(edits: &[(&str, &str)], seed: u64) -> Simulator {
    cell_with(edits, seed, RobotMode::AtPose)
}

fn cell_with(edits: &[(&str, &str)], seed: u64, robot: RobotMode) -> Simulator {
    let mut text = DEFAULT.to_owned();
    for (from, to) in edits {
        assert!(text.contains(from), "{from:?}");
        text = text.replacen(from, to, 1);
    }
    let recipe = Recipe::parse(&text, "test.toml", [1.0, 0.5]).expect("recipe");
    let cfg = SimConfig { tick_hz: 1000.0, seed, ..SimConfig::default() };
    FeedCell::simulator(cfg, &recipe, 0.04, robot).expect("cell")
}

fn run(sim: &mut Simulator, seconds: f64) {
    for _ in 0..(seconds * 1000.0).round() as u64 {
        sim.step();
    }
}

/// Indices of the parts on the plate.
fn on_plate(sim: &Simulator) -> Vec<usize> {
    (0..sim.part_count()).filter(|&i| !sim.is_parked(i)).collect()
}

#[test]
fn parts_arrive_at_the_rate_never_overfill_and_never_land_on_a_part() {
    let mut sim = cell(&[("max_on_plate = 16", "max_on_plate = 64")], 3);
    let mut seen = 0;
    for _ in 0..120 {
        run(&mut sim, 0.5);
        let on = on_plate(&sim);
        for (a, &i) in on.iter().enumerate() {
            for &j in &on[a + 1..] {
                let (p, q) = (sim.part(i).expect("i"), sim.part(j).expect("j"));
                let d = (p.position[0] - q.position[0]).hypot(p.position[1] - q.position[1]);
                let reach = sim.part_reach(i).expect("i") + sim.part_reach(j).expect("j");
                assert!(d >= reach, "parts {i} and {j} overlap: {d} < {reach}");
            }
        }
        seen = on.len();
    }
    let counts = FeedCell::of(&sim).expect("feed").counts();
    // 40 a minute for a minute: Poisson, so within a few sd of 40.
    assert!((25..=55).contains(&counts.arrived), "{counts:?}");
    assert_eq!((counts.on_plate as usize, seen), (counts.arrived as usize, counts.arrived as usize));
    assert_eq!((counts.picked, counts.lost), (0, 0), "a still plate presents nothing");

    let mut full =
        cell(&[("max_on_plate = 16", "max_on_plate = 5"), ("rate_per_min = 40", "rate_per_min = 600")], 3);
    for _ in 0..60 {
        run(&mut full, 0.5);
        assert!(on_plate(&full).len() <= 5, "more than max_on_plate");
    }
    assert_eq!(
        FeedCell::of(&full).expect("feed").counts().arrived,
        5,
        "the hopper waits while the plate is full"
    );
}

/// The first part on the plate of class `class`, once one has arrived.
fn first_of(sim: &mut Simulator, class: u32) -> usize {
    for _ in 0..6000 {
        let feed = FeedCell::of(sim).expect("feed");
        if let Some(i) = on_plate(sim).into_iter().find(|&i| feed.class_of(i) == Some(class)) {
            return i;
        }
        run(sim, 0.1);
    }
    panic!("no part of class {class} arrived");
}

fn put(sim: &mut Simulator, i: usize, position: [f64; 2], angle: f64) {
    assert!(sim.set_part(i, PartState { position, angle, stuck: true, ..PartState::default() }));
}

#[test]
fn the_robot_takes_a_settled_part_at_its_pose_and_nothing_else() {
    // The infeed slowed to a trickle, so the poses stay clear.
    let mut sim = cell(&[("rate_per_min = 40", "rate_per_min = 2")], 5);
    let square = first_of(&mut sim, 1);
    let id = FeedCell::of(&sim).expect("feed").id_of(square);
    // Pose 3: class 1 at (0.85, −0.25), θ = π/4. Turned a quarter more is
    // the same square; 3° off is out of tolerance (2°).
    put(&mut sim, square, [0.85, -0.25], core::f64::consts::FRAC_PI_4 + 3f64.to_radians());
    run(&mut sim, 1.0);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 0, "3° off was taken");
    let turned = core::f64::consts::FRAC_PI_4 + core::f64::consts::FRAC_PI_2 + 1f64.to_radians();
    put(&mut sim, square, [0.8505, -0.25], turned);
    run(&mut sim, 0.1);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 0, "taken before it settled (0.2 s)");
    run(&mut sim, 0.2);
    let feed = FeedCell::of(&sim).expect("feed");
    assert_eq!(feed.counts().picked, 1);
    let pick = feed.picks()[0];
    assert_eq!((pick.part_id, pick.class, pick.pose), (id, 1, 3));
    assert!(
        (pick.position_error - 0.0005).abs() < 1e-9 && (pick.angle_error - 1f64.to_radians()).abs() < 1e-9
    );
    assert!(
        sim.is_parked(square) && FeedCell::of(&sim).expect("feed").id_of(square) == 0,
        "a picked part leaves"
    );

    // A disc at pose 0 with another part in the gripper's clearance waits.
    let disc = first_of(&mut sim, 0);
    let other =
        on_plate(&sim).into_iter().find(|&i| i != disc).unwrap_or_else(|| first_other(&mut sim, disc));
    put(&mut sim, disc, [0.7, 0.25], 2.0);
    put(&mut sim, other, [0.7, 0.25 + 0.015 + 0.005 + 0.015 + 0.004], 0.0);
    run(&mut sim, 1.5);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 1, "taken with a part in the clearance");
    put(&mut sim, other, [0.0, 0.0], 0.0);
    run(&mut sim, 0.5);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 2, "the disc, at any angle, once clear");
}

#[test]
fn an_external_robot_takes_only_the_part_it_posts() {
    let mut sim = cell_with(&[("rate_per_min = 40", "rate_per_min = 2")], 5, RobotMode::External);
    let mailbox = FeedCell::accept_picks(&mut sim).expect("an external robot's mailbox");
    let square = first_of(&mut sim, 1);
    let id = FeedCell::of(&sim).expect("feed").id_of(square);
    put(&mut sim, square, [0.85, -0.25], core::f64::consts::FRAC_PI_4);
    run(&mut sim, 1.0);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 0, "the simulator's robot picked");
    // The wrong pose, a part that is not there, a pose out of range.
    assert!(mailbox.post(2, id) && mailbox.post(3, id + 1000));
    assert!(!mailbox.post(ipc_types::MAX_PICK_POSES as u32, id));
    run(&mut sim, 0.01);
    assert_eq!((mailbox.taken(), mailbox.refused()), (0, 2));
    assert!(mailbox.post(3, id));
    run(&mut sim, 0.01);
    let feed = FeedCell::of(&sim).expect("feed");
    assert_eq!((mailbox.taken(), feed.counts().picked), (1, 1));
    assert_eq!((feed.picks()[0].part_id, feed.picks()[0].pose), (id, 3));
    assert_ne!(feed.id_of(square), id, "a picked part leaves");
    let mut at_pose = cell(&[], 5);
    assert!(FeedCell::accept_picks(&mut at_pose).is_none(), "a mailbox beside the simulator's robot");
}

fn first_other(sim: &mut Simulator, not: usize) -> usize {
    for _ in 0..6000 {
        if let Some(i) = on_plate(sim).into_iter().find(|&i| i != not) {
            return i;
        }
        run(sim, 0.1);
    }
    panic!("no second part arrived");
}

#[test]
fn a_part_off_the_plate_is_lost_and_the_truth_shows_only_the_parts_on_it() {
    let mut sim = cell(&[], 9);
    run(&mut sim, 10.0);
    let on = on_plate(&sim);
    assert!(on.len() >= 2, "parts arrived");
    let templates = vec![ipc_types::PartState::new(0, 0, 0, [0.0; 3], [0.0; 3]); sim.part_count()];
    let mut truth = ipc_types::PartStates::new();
    sim.write_ground_truth(&templates, &mut truth);
    let feed = FeedCell::of(&sim).expect("feed");
    let mut ids: Vec<u32> = truth.parts().iter().map(|p| p.id).collect();
    let mut want: Vec<u32> = on.iter().map(|&i| feed.id_of(i)).collect();
    ids.sort_unstable();
    want.sort_unstable();
    assert_eq!(ids, want);
    assert!(!ids.contains(&0));

    let mut open = {
        let recipe = Recipe::parse(DEFAULT, "d.toml", [1.0, 0.5]).expect("recipe");
        let cfg = SimConfig { tick_hz: 1000.0, fence: false, seed: 9, ..SimConfig::default() };
        FeedCell::simulator(cfg, &recipe, 0.04, RobotMode::AtPose).expect("cell")
    };
    let i = first_of(&mut open, 0);
    put(&mut open, i, [1.2, 0.0], 0.0);
    run(&mut open, 0.01);
    assert_eq!(FeedCell::of(&open).expect("feed").counts().lost, 1);
    assert!(open.is_parked(i));
}

#[test]
fn the_same_seed_is_the_same_cell_and_its_step_allocates_nothing() {
    let (mut a, mut b) = (cell(&[], 11), cell(&[], 11));
    run(&mut a, 30.0);
    run(&mut b, 30.0);
    let poses = |s: &mut Simulator| s.parts().to_vec();
    assert_eq!(poses(&mut a), poses(&mut b));
    assert_eq!(FeedCell::of(&a).expect("a").counts(), FeedCell::of(&b).expect("b").counts());
    let mut c = cell(&[], 12);
    run(&mut c, 30.0);
    assert_ne!(poses(&mut a), poses(&mut c), "another seed, other arrivals");

    assert!(rt_core::alloc_count::counter_installed());
    let ((), allocated) = allocations_in(|| run(&mut a, 30.0));
    assert_eq!(allocated, 0, "the cell allocated");
}

#[test]
fn the_feeders_robot_takes_any_still_isolated_part_in_the_zone() {
    let recipe =
        Recipe::parse(&DEFAULT.replacen("rate_per_min = 40", "rate_per_min = 4", 1), "d.toml", [1.0, 0.5])
            .expect("recipe");
    let cfg = SimConfig { tick_hz: 1000.0, seed: 5, ..SimConfig::default() };
    let mut sim = FeedCell::simulator(cfg, &recipe, 0.04, RobotMode::AnyInZone).expect("cell");
    let part = first_of(&mut sim, 1);
    // Outside the zone (the poses' box, x ≥ 0.7 − 0.1): never taken.
    put(&mut sim, part, [0.55, 0.0], 1.0);
    run(&mut sim, 2.0);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().picked, 0);
    // In the zone, at any angle, between the poses: taken once settled.
    put(&mut sim, part, [0.78, 0.05], 1.0);
    run(&mut sim, 0.5);
    let feed = FeedCell::of(&sim).expect("feed");
    assert_eq!(feed.counts().picked, 1);
    // Its error is against the nearest pose of its class, (0.85, 0.25).
    let pick = feed.picks()[0];
    assert!((pick.position_error - (0.07f64).hypot(0.2)).abs() < 1e-9, "{pick:?}");
}

#[test]
fn the_status_names_the_part_at_each_pose_and_every_pick_by_number() {
    let mut sim = cell(&[("rate_per_min = 40", "rate_per_min = 2")], 5);
    let mut status = FeedCell::publish_status(&mut sim, 100).expect("a feed cell");
    let disc = first_of(&mut sim, 0);
    let other = first_other(&mut sim, disc);
    let id = FeedCell::of(&sim).expect("feed").id_of(disc);
    // Pose 0 (class 0 at (0.7, 0.25)) holds the disc, a part in its clearance.
    put(&mut sim, disc, [0.7, 0.25], 0.0);
    put(&mut sim, other, [0.7, 0.25 + 0.015 + 0.005 + 0.015 + 0.004], 0.0);
    run(&mut sim, 1.0);
    let s = *status.read();
    assert_eq!(s.len(), 4, "the recipe's four poses");
    assert_eq!((s.poses()[0].part_id, s.poses()[0].ready, s.poses()[0].class), (id, 0, 0));
    assert!(s.poses()[1..].iter().all(|p| p.part_id == 0 && p.ready == 0));
    assert_eq!((s.poses()[3].x, s.poses()[3].y), (0.85, -0.25));
    assert_eq!(s.picked, 0);
    assert!((s.time_s - sim.time()).abs() < 0.1 + 1e-9, "{} against {}", s.time_s, sim.time());
    put(&mut sim, other, [0.0, 0.0], 0.0);
    run(&mut sim, 1.0);
    let s = *status.read();
    assert_eq!(s.picked, 1);
    let pick = s.recent().last().copied().expect("one pick");
    assert_eq!((pick.number, pick.part_id, pick.pose), (1, id, 0));
    assert!(s.poses()[0].part_id == 0 && s.robot_busy_s > 0.0);

    // Picked by number for as long as the log keeps them; nothing allocates.
    let feed = FeedCell::of(&sim).expect("feed");
    assert_eq!(feed.pick_numbered(1), Some(pick));
    assert_eq!(feed.pick_numbered(2), None);
    assert_eq!(feed.pick_numbered(0), None);
    let ((), allocated) = allocations_in(|| run(&mut sim, 5.0));
    assert_eq!(allocated, 0, "the status port allocated");
}

#[test]
fn a_changeover_moves_the_poses_keeps_the_parts_and_allocates_nothing_where_it_lands() {
    let mut sim = cell_with(&[], 13, RobotMode::External);
    let mut recipes = FeedCell::accept_recipes(&mut sim).expect("a cell's mailbox");
    run(&mut sim, 20.0);
    let before = FeedCell::of(&sim).expect("feed").counts();
    assert!(before.on_plate >= 2, "parts arrived");
    let ids: Vec<u32> = on_plate(&sim).iter().map(|&i| FeedCell::of(&sim).expect("feed").id_of(i)).collect();
    // Two poses, moved, and a faster robot: the same classes.
    let next = Recipe::parse(
        &DEFAULT.replacen("position = [0.7, 0.25]", "position = [0.6, 0.1]", 1).replacen(
            "pick_s = 1.0",
            "pick_s = 0.5",
            1,
        ),
        "next.toml",
        [1.0, 0.5],
    )
    .expect("next");
    let mut next = next;
    next.picks.truncate(2);
    let running = FeedCell::of(&sim).expect("feed").recipe().clone();
    assert_eq!(running.check_changeover(&next), Ok(()));
    recipes.post(next.clone());
    // The step that swaps it in allocates nothing (the old recipe is freed
    // by the next post).
    let ((), allocated) = allocations_in(|| run(&mut sim, 0.001));
    assert_eq!(allocated, 0, "the changeover allocated on the cell's thread");
    let feed = FeedCell::of(&sim).expect("feed");
    assert_eq!(feed.recipe(), &next);
    assert_eq!(feed.counts().changeovers, 1);
    assert_eq!(feed.counts().arrived, before.arrived, "no part came or went with it");
    let still: Vec<u32> = on_plate(&sim).iter().map(|&i| feed.id_of(i)).collect();
    assert_eq!(still, ids, "the parts on the plate stay");
    let mut status = ipc_types::FeedStatus::new();
    feed.write_status(&sim, &mut status);
    assert_eq!(status.count, 2);
    assert_eq!([status.poses[0].x, status.poses[0].y], [0.6, 0.1]);
    // A second post frees the first recipe here, off the cell's thread.
    recipes.post(running.clone());
    run(&mut sim, 0.001);
    assert_eq!(FeedCell::of(&sim).expect("feed").recipe(), &running);
    assert_eq!(FeedCell::of(&sim).expect("feed").counts().changeovers, 2);
}
