//! The feed cell in the closed loop, lock-step: parts arrive on the
//! simulator, vision's test double sees them come and go, the `present`
//! planner brings each to its pick pose and the simulated robot takes it.

use upm_commands::scenario::{Scenario, resolve};

#[test]
fn the_present_planner_feeds_the_robot_in_lock_step() {
    let sc = Scenario::load(&resolve("feed")).expect("scenario");
    let config = sc.config(1, "unused_").expect("config");
    let seconds: f64 = std::env::var("UPM_FEED_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(120.0);
    let mut planner = config.planner.build().expect("planner");
    let started = std::time::Instant::now();
    let r = upm_commands::closed_loop::run(&config, planner.as_mut(), seconds).expect("run");
    let feed = r.feed.expect("a feed cell");
    let picks = &feed.picks;
    let worst = |f: fn(&ipc_types::PickEvent) -> f64| picks.iter().map(f).fold(0.0, f64::max);
    eprintln!(
        "feed {seconds} s in {:.1} s: worst pick {:.2} mm {:.2}°; holds {}, rejected {}",
        started.elapsed().as_secs_f64(),
        worst(|p| p.position_error_m) * 1e3,
        worst(|p| p.angle_error_rad.abs()).to_degrees(),
        r.hold_events,
        r.rejected_requests
    );
    for (id, t) in &r.trails.parts {
        let (a, b) = (t.points.first().expect("first"), t.points.last().expect("last"));
        eprintln!(
            "part {id} class {}: ({:.3}, {:.3}) at {:.1} s -> ({:.3}, {:.3}, {:.1}°) at {:.1} s",
            t.class,
            a[1],
            a[2],
            a[0],
            b[1],
            b[2],
            b[3].to_degrees(),
            b[0]
        );
    }
    eprintln!("schedules {}, k_max {}; {}", r.schedules, r.k_max, feed.to_json());
    let counts = feed.last;
    assert!(counts.arrived > 0, "nothing arrived");
    assert_eq!(counts.lost, 0);
    assert_eq!(r.hold_events, 0);
    assert!(counts.picked > 0, "the robot took nothing");
    assert_eq!((feed.picks_unseen, feed.picks.len() as u64), (0, counts.picked), "every pick is kept");
}
