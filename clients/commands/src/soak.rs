//! `upm soak --minutes N`: the sort scenario over and over, each run a
//! separate `upm run`, while a chaos schedule kills the vision or planner
//! process with SIGKILL every 20–60 s (random, seeded) and the core once
//! every 10 minutes. Reports what an operator would look for: holds,
//! restarts, the oldest input the core saw, RT allocations, overruns, parts
//! off the plate and runs that ended in error.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use crate::config::Config;

/// How the soak runs.
#[derive(Debug, Clone)]
pub struct SoakPlan {
    pub minutes: f64,
    pub seed: u64,
    pub out: PathBuf,
    /// Between client kills (s).
    pub kill_every_s: (f64, f64),
    /// Between core kills (s).
    pub core_kill_every_s: f64,
}

/// Totals over every run.
#[derive(Debug, Default)]
struct Totals {
    runs: u64,
    runs_failed_unexpectedly: Vec<String>,
    core_kills: u64,
    client_kills: u64,
    holds: u64,
    restarts: u64,
    max_input_age_ms: f64,
    rt_allocations: u64,
    ticks: u64,
    overruns: u64,
    parts_off_plate: u64,
    sorted_runs: u64,
}

fn kill(pid: u32, signal: i32) -> bool {
    // SAFETY: kill(2) with a pid read from the rig's own telemetry.
    pid > 0 && unsafe { libc::kill(pid as libc::pid_t, signal) } == 0
}

/// Run the soak; returns the report (also written to `out/soak.json`).
pub fn run(plan: &SoakPlan) -> anyhow::Result<Value> {
    std::fs::create_dir_all(&plan.out).with_context(|| format!("creating {}", plan.out.display()))?;
    let exe = std::env::current_exe().context("locating the upm binary")?;
    let mut rng = ChaCha8Rng::seed_from_u64(plan.seed);
    let mut totals = Totals::default();
    let started = Instant::now();
    let end = started + Duration::from_secs_f64(plan.minutes * 60.0);
    let draw = |rng: &mut ChaCha8Rng| {
        Duration::from_secs_f64(rng.random_range(plan.kill_every_s.0..plan.kill_every_s.1))
    };
    let mut next_client_kill = Instant::now() + draw(&mut rng);
    let mut next_core_kill = Instant::now() + Duration::from_secs_f64(plan.core_kill_every_s);
    while Instant::now() < end {
        let run = totals.runs;
        let prefix = format!("upm_soak_{}_{run}_", std::process::id());
        let dir = plan.out.join(format!("run-{run:03}"));
        let left = end.saturating_duration_since(Instant::now()).as_secs_f64().max(5.0);
        let mut child = Command::new(&exe)
            .args(["run", "sort", "--quiet", "--prefix", &prefix, "--seed", &(plan.seed + run).to_string()])
            .args(["--duration", &format!("{:.1}", left.min(300.0)), "--out"])
            .arg(&dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .context("starting upm run")?;
        totals.runs += 1;
        let mut core_killed = false;
        let status = loop {
            if let Some(s) = child.try_wait()? {
                break s;
            }
            let t = crate::status::read_telemetry(&prefix, Duration::from_millis(200)).ok();
            // Idle: no input yet (start-up); otherwise the ages show how
            // long the loop went without fresh input.
            if let Some(t) = t.filter(|t| t.core_state() != Some(ipc_types::CoreState::Idle)) {
                totals.max_input_age_ms = totals.max_input_age_ms.max(t.parts_age_ms).max(t.request_age_ms);
            }
            let now = Instant::now();
            if let Some(t) = t {
                if now >= next_core_kill && kill(t.core_pid, libc::SIGKILL) {
                    next_core_kill = now + Duration::from_secs_f64(plan.core_kill_every_s);
                    totals.core_kills += 1;
                    core_killed = true;
                } else if now >= next_client_kill {
                    let pid = if rng.random_bool(0.5) { t.vision_pid } else { t.planner_pid };
                    if kill(pid, libc::SIGKILL) {
                        totals.client_kills += 1;
                    }
                    next_client_kill = now + draw(&mut rng);
                }
            }
            std::thread::sleep(Duration::from_millis(100));
        };
        let stderr = read_all(&mut child);
        if !status.success() && !core_killed {
            totals.runs_failed_unexpectedly.push(format!("run {run}: {status}: {}", last_line(&stderr)));
        }
        add_metrics(&mut totals, &dir);
        ipc_types::rig_node::remove_prefix_segment(&prefix);
    }
    let t = &totals;
    let report = json!({
        "minutes": started.elapsed().as_secs_f64() / 60.0,
        "seed": plan.seed,
        "runs": t.runs,
        "runs_sorted": t.sorted_runs,
        "runs_failed_unexpectedly": t.runs_failed_unexpectedly,
        "core_kills": t.core_kills,
        "client_kills": t.client_kills,
        "hold_events": t.holds,
        "client_restarts": t.restarts,
        "max_input_age_ms": t.max_input_age_ms,
        "rt_thread_allocations": t.rt_allocations,
        "ticks": t.ticks,
        "overruns": t.overruns,
        "overrun_fraction": if t.ticks > 0 { t.overruns as f64 / t.ticks as f64 } else { 0.0 },
        "parts_off_plate": t.parts_off_plate,
    });
    std::fs::write(plan.out.join("soak.json"), serde_json::to_string_pretty(&report)?)?;
    Ok(report)
}

fn read_all(child: &mut Child) -> String {
    let mut s = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut s);
    }
    s
}

fn last_line(s: &str) -> &str {
    s.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("")
}

/// Add one run's metrics.json (written even when its core was killed).
fn add_metrics(t: &mut Totals, dir: &Path) {
    let Ok(text) = std::fs::read_to_string(dir.join("metrics.json")) else {
        t.runs_failed_unexpectedly.push(format!("{}: no metrics.json", dir.display()));
        return;
    };
    let Ok(m) = serde_json::from_str::<Value>(&text) else { return };
    let n = |v: &Value| v.as_u64().unwrap_or(0);
    let core = &m["core"];
    t.holds += n(&core["hold_events"]);
    t.rt_allocations += n(&core["rt_thread_allocations"]);
    t.ticks += n(&core["ticks"]);
    t.overruns += n(&core["overruns"]);
    t.restarts += n(&m["restarts"]["vision"]) + n(&m["restarts"]["planner"]);
    if m["sorted_fraction"].as_f64() == Some(1.0) {
        t.sorted_runs += 1;
    }
    let half = Config::load(&dir.join("config.toml")).map_or([f64::INFINITY; 2], |c| c.plate.half_extent);
    let off = |p: &Value| {
        let (x, y) = (p["final"][0].as_f64().unwrap_or(0.0), p["final"][1].as_f64().unwrap_or(0.0));
        x.abs() > half[0] || y.abs() > half[1]
    };
    t.parts_off_plate += m["parts"].as_array().map_or(0, |ps| ps.iter().filter(|p| off(p)).count() as u64);
}

/// A few lines for the terminal.
pub fn to_text(v: &Value) -> String {
    format!(
        "soak: {:.1} min, {} runs ({} sorted), {} unexpected failures {}\n\
         kills: {} clients, {} cores;  client restarts {};  hold events {}\n\
         largest input age: {:.1} ms;  rt allocations {};  overruns {} of {} ticks ({:.3} %);  parts off the plate {}",
        v["minutes"].as_f64().unwrap_or(0.0),
        v["runs"],
        v["runs_sorted"],
        v["runs_failed_unexpectedly"].as_array().map_or(0, Vec::len),
        v["runs_failed_unexpectedly"],
        v["client_kills"],
        v["core_kills"],
        v["client_restarts"],
        v["hold_events"],
        v["max_input_age_ms"].as_f64().unwrap_or(0.0),
        v["rt_thread_allocations"],
        v["overruns"],
        v["ticks"],
        v["overrun_fraction"].as_f64().unwrap_or(0.0) * 100.0,
        v["parts_off_plate"],
    )
}
