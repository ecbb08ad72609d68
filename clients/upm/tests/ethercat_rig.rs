//! The whole rig over the EtherCAT driver and the simulated chain (issue
//! 23): lock-step sort puts every part on its side as with the simulator
//! driver, deterministically; a drive fault and lost frames hold the core
//! within the tick the driver reports them and clear without a restart,
//! shown in telemetry; `upm run sort --driver ethercat-sim` runs the real
//! processes and `upm status --json` shows the driver.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{PAPER_PARTS, part_states, request};
use ethercat_sim::SimulatedRig;
use ipc_types::{CoreState, bus_state, driver_kind};
use rt_core::CoreParams;
use rt_core::lockstep::Lockstep;
use upm_commands::config::{Config, DriverChoice};
use upm_commands::scenario::{Scenario, resolve};
use upm_ethercat::EthercatDriver;

fn lockstep(
    name: &str,
    seed: u64,
    seconds: f64,
) -> (serde_json::Value, upm_commands::closed_loop::LoopResult) {
    let sc = Scenario::load(&resolve(name)).expect("scenario");
    let mut config = sc.config(seed, "unused_").expect("config");
    config.driver.kind = DriverChoice::EthercatSim;
    let mut planner = config.planner.build().expect("planner");
    let r = upm_commands::closed_loop::run(&config, planner.as_mut(), seconds).expect("run");
    (sc.evaluate(&config, &r.trails), r)
}

#[test]
fn sort_over_the_simulated_chain_puts_every_part_on_its_side() {
    let secs = Scenario::load(&resolve("sort")).expect("scenario").duration_s;
    for seed in [1, 2, 3] {
        let (m, r) = lockstep("sort", seed, secs);
        eprintln!("ethercat-sim sort seed {seed}: time to sort {} s", m["time_to_sort_s"]);
        assert_eq!(m["sorted_fraction"].as_f64(), Some(1.0), "seed {seed}: {m}");
        assert_eq!((r.hold_events, r.rejected_requests), (0, 0), "seed {seed}");
    }
}

#[test]
fn runs_over_the_simulated_chain_are_bit_identical() {
    let (a, ra) = lockstep("sort", 3, 20.0);
    let (b, rb) = lockstep("sort", 3, 20.0);
    assert_eq!(a, b);
    let points = |r: &upm_commands::closed_loop::LoopResult| {
        r.trails
            .parts
            .values()
            .flat_map(|t| t.points.iter().flat_map(|p| p.map(f64::to_bits)))
            .collect::<Vec<_>>()
    };
    assert_eq!(points(&ra), points(&rb), "trails differ");
}

fn ethercat_core(auto_resume_ms: f64) -> Lockstep<EthercatDriver<SimulatedRig>> {
    let config = Config::default();
    let (driver, _) = upm_core::plate_driver::ethercat_sim(&config, "default").expect("driver");
    let mut params = CoreParams::default();
    params.safety.auto_resume_ns = (auto_resume_ms * 1e6) as u64;
    Lockstep::new(&params, driver, 1_000_000_000).expect("core")
}

/// Fresh inputs every 10 ticks; stop at the first tick in `stop_at` mode.
fn run_until(
    c: &mut Lockstep<EthercatDriver<SimulatedRig>>,
    ticks: u64,
    seq: &mut u64,
    stop_at: CoreState,
) -> u64 {
    for t in 0..ticks {
        if t % 10 == 0 {
            *seq += 1;
            let now = c.now_ns();
            c.inbox().push_parts(&part_states(*seq, now, &PAPER_PARTS));
            c.inbox().push_request(&request(*seq, now, &PAPER_PARTS, 1.0));
        }
        c.run_ticks(1, |_| {});
        if c.motor().mode() == stop_at {
            return t + 1;
        }
    }
    ticks
}

#[test]
fn drive_faults_and_lost_frames_hold_the_core_and_clear_without_a_restart() {
    let mut c = ethercat_core(5.0);
    let mut seq = 0;
    run_until(&mut c, 2_000, &mut seq, CoreState::Hold);
    assert_eq!(c.motor().mode(), CoreState::Running);
    let t = c.telemetry();
    assert_eq!((t.driver.kind, t.driver.state), (driver_kind::ETHERCAT, bus_state::OP));

    // A drive faults: the core holds by the tick the driver sees it (the
    // fault crosses the wire within two bus cycles).
    let cycle = u64::from(upm_ethercat::EthercatParams::default().cycle_divisor);
    assert!(c.motor().driver().with_wire(|w| w.chain.devices[1].drive.fault()).is_some());
    let held_after = run_until(&mut c, 100, &mut seq, CoreState::Hold);
    assert!(held_after <= 2 * cycle + 1, "held after {held_after} ticks");
    let t = c.telemetry();
    assert_eq!((t.driver.state, t.driver.faults[1], t.counters.fault_holds), (bus_state::FAULT, 1, 1));
    // Fault reset, re-enable, then auto-resume after 5 ms of healthy reads.
    let resumed_after = run_until(&mut c, 2_000, &mut seq, CoreState::Running);
    assert!(resumed_after < 2_000, "not resumed");
    assert_eq!(c.telemetry().driver.state, bus_state::OP);

    // Frames lost on the wire: held, counted, resumed.
    assert!(c.motor().driver().with_wire(|w| w.chain.lose_frames(3)).is_some());
    run_until(&mut c, 100, &mut seq, CoreState::Hold);
    assert_eq!(c.motor().mode(), CoreState::Hold);
    run_until(&mut c, 2_000, &mut seq, CoreState::Running);
    let t = c.telemetry();
    assert_eq!((t.driver.lost_frames, t.counters.fault_holds, t.counters.resumes), (3, 2, 2));
    assert_eq!(t.counters.rt_thread_allocations, 0);
}

#[test]
fn upm_run_sort_with_the_ethercat_sim_driver_and_upm_status_shows_it() {
    let out = std::env::temp_dir().join(format!("upm_run_ecat_{}", std::process::id()));
    let prefix = common::unique_prefix("ecat_run");
    let child = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args([
            "run",
            "sort",
            "--driver",
            "ethercat-sim",
            "--duration",
            "6",
            "--quiet",
            "--prefix",
            &prefix,
            "--out",
        ])
        .arg(&out)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("upm run");
    let start = Instant::now();
    let mut status = serde_json::Value::Null;
    while start.elapsed() < Duration::from_secs(20) {
        let o = Command::new(env!("CARGO_BIN_EXE_upm"))
            .args(["status", "--json", "--prefix", &prefix])
            .output()
            .expect("upm status");
        if o.status.success() {
            status = serde_json::from_slice(&o.stdout).expect("json");
            if status["state"] == "running" {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    let o = child.wait_with_output().expect("wait");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let core_log = std::fs::read_to_string(out.join("logs/core.log")).unwrap_or_default();
    // As root the chain answers from the far end of a veth pair; otherwise
    // in process, and the core says why.
    // SAFETY: geteuid has no preconditions.
    let root = unsafe { libc::geteuid() } == 0;
    let transport = if root { "ethercat-sim over veth" } else { "ethercat-sim in process" };
    assert!(core_log.contains(transport), "expected {transport:?} in the core's log:\n{core_log}");
    let d = &status["driver"];
    assert_eq!((d["kind"].as_str(), d["state"].as_str()), (Some("ethercat"), Some("op")), "{status}");
    assert_eq!(d["faults"], serde_json::json!([0, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(d["lost_frames"], 0);
    // The drives run on distributed clocks: the SYNC0 phase is shown.
    assert!(d["sync0_phase_us"].is_number(), "{status}");
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
            .expect("json");
    assert_eq!(m["core"]["exit_ok"], true);
    assert_eq!(m["core"]["rt_thread_allocations"], 0);
    assert_eq!(m["core"]["driver"]["kind"], "ethercat");
    assert_eq!(m["core"]["hold_events"], 0);
    let _ = std::fs::remove_dir_all(&out);
}
