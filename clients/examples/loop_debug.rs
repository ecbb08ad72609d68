//! Run a scenario in lock-step and print its goal metrics (debug aid).
fn main() -> anyhow::Result<()> {
    let name = std::env::args().nth(1).unwrap_or("sort".into());
    let secs: f64 = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let seed: u64 = std::env::args().nth(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let sc = upm_clients::scenario::Scenario::load(&upm_clients::scenario::resolve(&name))?;
    let config = sc.config(seed, "unused_")?;
    let mut planner = upm_clients::planner::planner_by_name(&sc.planner_params(&config))?;
    let t = std::time::Instant::now();
    let r = upm_clients::closed_loop::run(&config, planner.as_mut(), secs)?;
    let m = sc.evaluate(&config, &r.trails);
    println!(
        "k_max {:.3} mean residual {:.4} N first (rank, κ) {:?}",
        r.k_max, r.mean_residual, r.first_rank_condition
    );
    println!(
        "{} s sim in {:.1} s wall; holds {} rejected {} saturated {}/{}",
        secs,
        t.elapsed().as_secs_f64(),
        r.hold_events,
        r.rejected_requests,
        r.saturated_schedules,
        r.schedules
    );
    // Optional: trails picture, and for sort the parts on their side every 15 s.
    if let Some(svg) = std::env::args().nth(4) {
        let half = config.plate.half_extent;
        upm_clients::launcher::plot::draw_trails(
            svg.as_ref(),
            &name,
            half,
            &config.plate.centers,
            &r.trails,
        )?;
    }
    let sort_x = sc.planner_params(&config).sort_x;
    let mut timeline = String::new();
    for step in 1..=(secs / 15.0) as usize {
        let at = step as f64 * 15.0;
        let on_side = r
            .trails
            .parts
            .values()
            .filter(|t| {
                t.points
                    .iter()
                    .rev()
                    .find(|q| q[0] <= at)
                    .is_some_and(|q| upm_clients::planner::goal::sort_side(t.class) * q[1] >= sort_x)
            })
            .count();
        timeline.push_str(&format!(" {at}s:{on_side}"));
    }
    println!("on their side over time:{timeline}");
    for (id, t) in &r.trails.parts {
        for w in t.points.windows(2) {
            let d = (w[1][1] - w[0][1]).hypot(w[1][2] - w[0][2]);
            if d > 0.02 {
                println!("part {id} jumps {d:.3} m at t {:.3}: {:?} -> {:?}", w[0][0], w[0], w[1]);
            }
        }
    }
    for p in m["parts"].as_array().into_iter().flatten() {
        println!("{} {} {:?} -> {:?} {}", p["id"], p["class"], p["start"], p["final"], p["goal_met"]);
    }
    for k in [
        "sorted_fraction",
        "tracking_rms_m",
        "path_length_m",
        "spin_angle_error_deg",
        "others_max_drift_m",
        "collisions",
    ] {
        if !m[k].is_null() {
            println!("{k} {}", m[k]);
        }
    }
    Ok(())
}
