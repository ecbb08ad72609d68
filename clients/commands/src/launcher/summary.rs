//! The few lines `upm run` ends with, for a person: what the scenario
//! achieved, how the core fared, and where the files are (metrics.json
//! has everything, and `--json` prints it instead).

use std::path::Path;

use serde_json::Value;

/// Three lines from a run's metrics.json.
pub fn summary(m: &Value, out: &Path, recorded: bool) -> String {
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let core = &m["core"];
    let ticks = num(&core["ticks"]);
    let overruns = if ticks > 0.0 { 100.0 * num(&core["overruns"]) / ticks } else { 0.0 };
    let mut files: Vec<String> = ["metrics.json", "trails.svg", "latency/", "logs/"].map(String::from).into();
    if recorded {
        match m["recording"]["segments"].as_array().map_or(0, Vec::len) {
            0 | 1 => files.push(super::RECORDING.into()),
            n => files.push(format!("{} and {} more segments", super::RECORDING, n - 1)),
        }
    }
    format!(
        "{} seed {}: {}\nholds {}, overruns {overruns:.2} %, rejected: requests {}, part states {}; restarts: \
         vision {}, planner {}; motor wake-up p99 {:.0} µs, solve p99 {:.2} ms\nfiles in {}: {}",
        m["scenario"].as_str().unwrap_or("?"),
        m["seed"],
        outcome(m),
        core["hold_events"],
        core["rejected_requests"],
        core["rejected_parts"],
        m["restarts"]["vision"],
        m["restarts"]["planner"],
        num(&m["latency_us"]["motor_wakeup"]["p99"]),
        num(&m["latency_us"]["solver"]["p99"]) / 1e3,
        out.display(),
        files.join(", "),
    )
}

/// What the scenario's goal came to: sorted, tracked, turned, picked, or met.
fn outcome(m: &Value) -> String {
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let parts = m["parts"].as_array().map_or(&[][..], Vec::as_slice);
    let met = parts.iter().filter(|p| p["goal_met"] == true).count();
    let seconds = m["sim_seconds"].as_f64().unwrap_or(0.0);
    if m.get("sorted_fraction").is_some() {
        return match m["time_to_sort_s"].as_f64() {
            Some(t) => format!("sorted {met} of {} in {t:.1} s", parts.len()),
            None => format!("sorted {met} of {} after {seconds:.1} s", parts.len()),
        };
    }
    if let Some(f) = m.get("feed") {
        let rate =
            f["parts_per_minute"].as_f64().map_or("n/a (a minute or less)".into(), |r| format!("{r:.1}"));
        return format!(
            "picked {} of {} arrived in {seconds:.1} s, {rate} parts/min after the first minute, pick p99 {:.2} mm \
             {:.2}°, lost {}, stuck {}",
            f["picked"],
            f["arrived"],
            num(&f["pose_error_p99_mm"]),
            num(&f["angle_error_p99_deg"]),
            f["lost"],
            f["stuck"]
        );
    }
    let mut text = format!("goal met by {met} of {} parts after {seconds:.1} s", parts.len());
    if let Some(rms) = m["tracking_rms_m"].as_f64() {
        let path = m["path_length_m"].as_f64().unwrap_or(0.0);
        text += &format!(", tracking RMS {:.1} mm over {path:.2} m", rms * 1e3);
    }
    if let Some(err) = m["spin_angle_error_deg"].as_f64() {
        text += &format!(", angle error {err:.2}°");
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_sort_run_reads_sorted_k_of_n_with_holds_overruns_and_the_files() {
        let m = json!({
            "scenario": "sort", "seed": 1, "sim_seconds": 60.0, "sorted_fraction": 1.0, "time_to_sort_s": 41.04,
            "parts": [{"goal_met": true}, {"goal_met": true}, {"goal_met": false}],
            "core": {"ticks": 10000, "overruns": 24, "hold_events": 0, "rejected_requests": 0, "rejected_parts": 2},
            "restarts": {"vision": 0, "planner": 1},
            "latency_us": {"motor_wakeup": {"p99": 40.2}, "solver": {"p99": 812.0}},
        });
        let text = summary(&m, Path::new("out/run"), true);
        assert_eq!(
            text,
            "sort seed 1: sorted 2 of 3 in 41.0 s\n\
             holds 0, overruns 0.24 %, rejected: requests 0, part states 2; restarts: vision 0, planner 1; \
             motor wake-up p99 40 µs, solve p99 0.81 ms\n\
             files in out/run: metrics.json, trails.svg, latency/, logs/, run.mcap"
        );
        let mut long = m.clone();
        long["recording"] =
            json!({ "segments": ["out/run/run.mcap", "out/run/run.001.mcap", "out/run/run.002.mcap"] });
        assert!(summary(&long, Path::new("out/run"), true).ends_with("logs/, run.mcap and 2 more segments"));
    }

    #[test]
    fn a_feed_run_names_its_picks_rate_errors_and_losses() {
        let m = json!({"scenario": "feed", "seed": 1, "sim_seconds": 600.0, "parts": [],
                       "feed": {"picked": 80, "arrived": 96, "parts_per_minute": 8.4, "pose_error_p99_mm": 0.91,
                                "angle_error_p99_deg": 1.5, "lost": 0, "stuck": 2}});
        let text = summary(&m, Path::new("o"), false);
        assert!(
            text.starts_with(
                "feed seed 1: picked 80 of 96 arrived in 600.0 s, 8.4 parts/min after the first minute, \
                 pick p99 0.91 mm 1.50°, lost 0, stuck 2\n"
            ),
            "{text}"
        );
    }

    #[test]
    fn a_track_run_names_its_rms() {
        let m = json!({"scenario": "track", "seed": 2, "sim_seconds": 30.0, "tracking_rms_m": 0.002,
                       "path_length_m": 1.4, "parts": [{"goal_met": true}]});
        let text = summary(&m, Path::new("o"), false);
        assert!(
            text.starts_with(
                "track seed 2: goal met by 1 of 1 parts after 30.0 s, tracking RMS 2.0 mm over 1.40 m\n"
            ),
            "{text}"
        );
        assert!(text.ends_with("files in o: metrics.json, trails.svg, latency/, logs/"), "{text}");
    }
}
