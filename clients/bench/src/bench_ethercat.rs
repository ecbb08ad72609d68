//! `upm bench ethercat`: the EtherCAT process-data round trip over a veth
//! pair whose far end (the simulated chain, answering on a raw socket) sits
//! in its own network namespace, at 1 and 4 kHz, through two paths:
//!
//! - **motor-thread poll** (what `EthercatDriver` does): the motor thread
//!   sends the frame and waits for its answer itself;
//! - **ethercrab's io_uring task**: a TX/RX thread owns the socket, the
//!   motor thread awaits the exchange (woken through a futex).
//!
//! Beside each, in the same run, the cycle thread's wake-up lateness (the
//! motor loop's own figure). Threads as the core places them: the cycle
//! thread SCHED_FIFO 80 on the last CPU, the io_uring task FIFO 81 there
//! too, the chain FIFO 70 on another CPU; memory locked, PM QoS held.
//! Needs root (the namespace, raw sockets, FIFO).

use std::time::Duration;

use anyhow::Context;
use drivers::{SimConfig, Simulator};
use ethercat_sim::SimulatedRig;
use ethercat_sim::serve::{ChainServer, ServerPlacement};
use ethercat_sim::veth::VethPair;
use hdrhistogram::Histogram;
use rt_core::rt_setup::{hold_cpu_dma_latency, lock_memory, make_current_thread_realtime_on, online_cpus};
use rt_core::{Clock, MonotonicClock};
use serde_json::{Value, json};
use upm_ethercat::{EthercatDriver, EthercatParams, RawSocketWire};
use upm_hardware::{ActuatorCommand, PlateDriver};

use crate::bench_latency::{new_histogram as histogram, summary_ns};

/// Simulator ticks per second behind the chain (the plant's own step).
const PLANT_HZ: f64 = 8_000.0;
const CYCLE_PRIORITY: u8 = 80;
const CHAIN_PRIORITY: u8 = 70;

/// A veth pair with the chain answering on its far end, until dropped.
fn chain(rate_hz: f64, cpu: usize) -> anyhow::Result<ChainServer<SimulatedRig>> {
    let pair = VethPair::create(&format!("b{}", std::process::id() % 10_000_000))
        .map_err(|why| anyhow::anyhow!("upm bench ethercat: {why}"))?;
    let cfg = SimConfig { tick_hz: PLANT_HZ, ..SimConfig::default() };
    let sim = Simulator::new(cfg, &[]).map_err(|e| anyhow::anyhow!("{e}"))?;
    let p = EthercatParams::default();
    let ticks = (PLANT_HZ / rate_hz).round() as u32;
    let mut rig = SimulatedRig::new(sim, p.counts_per_metre, p.rated_force_n, ticks);
    upm_core::plate_driver::keep_real_time(&mut rig);
    ChainServer::start(pair, rig, ServerPlacement { realtime: Some((CHAIN_PRIORITY, cpu)) })
        .map_err(|why| anyhow::anyhow!("the simulated chain: {why}"))
}

/// What one path measured.
struct PathRun {
    round_trip: Histogram<u64>,
    wakeup: Histogram<u64>,
    lost: u64,
    /// With distributed clocks, after the first half: where the frames
    /// reached the reference after SYNC0, and SYNC0 events the drives
    /// latched without fresh outputs.
    sync0: Option<(Histogram<u64>, u64)>,
}

/// One exchange: whether it came back whole, and the phase correction the
/// driver asks of the loop.
struct Exchanged {
    ok: bool,
    correction_ns: i64,
}

/// `cycles` periods of `period_ns` on a FIFO thread on `cpu`: wake up,
/// note the lateness, time `exchange`, shift the phase as it asks (as the
/// motor loop does).
fn cycle_loop(
    cpu: usize,
    period_ns: u64,
    cycles: u64,
    mut exchange: impl FnMut(u64) -> Exchanged,
) -> anyhow::Result<(Histogram<u64>, Histogram<u64>, u64)> {
    let (mut rtt, mut wake) = (histogram()?, histogram()?);
    let mut lost = 0;
    let placed = make_current_thread_realtime_on(CYCLE_PRIORITY, cpu);
    anyhow::ensure!(placed.fifo, "SCHED_FIFO {CYCLE_PRIORITY} on CPU {cpu} refused (run as root)");
    let clock = MonotonicClock;
    let mut next = clock.now_ns() + 10 * period_ns;
    for cycle in 0..cycles {
        clock.sleep_until(next);
        let woke = clock.now_ns();
        let _ = wake.record(woke.saturating_sub(next).max(1));
        let e = exchange(cycle);
        let done = clock.now_ns();
        let _ = rtt.record(done.saturating_sub(woke).max(1));
        lost += u64::from(!e.ok);
        // Skip rather than catch up, as the motor loop does.
        next = (next + period_ns).saturating_add_signed(e.correction_ns);
        while next <= done {
            next += period_ns;
        }
    }
    Ok((rtt, wake, lost))
}

fn poll_path(rate_hz: f64, cycles: u64, cpus: (usize, usize)) -> anyhow::Result<PathRun> {
    let chain = chain(rate_hz, cpus.0)?;
    let p = EthercatParams { tick_hz: rate_hz, cycle_divisor: 1, ..EthercatParams::default() };
    // Checked against the 1–4 kHz rule with divisor 1.
    let wire = RawSocketWire::open(chain.near(), p.frame_deadline()).map_err(anyhow::Error::msg)?;
    let near = std::thread::scope(|s| {
        s.spawn(|| -> anyhow::Result<PathRun> {
            let mut d = EthercatDriver::start(wire, p, upm_motion::RigParams::default())
                .map_err(anyhow::Error::msg)?;
            let mut lost_before = d.health().lost_frames;
            let mut phase = histogram()?;
            let settled = cycles / 2;
            let missed = || chain.wire.lock().map(|c| c.chain.devices[0].sync0_missed).unwrap_or(0);
            let mut missed_at_settled = 0;
            let (round_trip, wakeup, lost) = cycle_loop(cpus.1, (1e9 / rate_hz) as u64, cycles, |cycle| {
                let _ = d.write(&ActuatorCommand::HOME);
                d.advance();
                let now = d.health().lost_frames;
                let ok = now == lost_before;
                lost_before = now;
                if cycle == settled {
                    missed_at_settled = missed();
                }
                if let Some(dc) = d.distributed_clocks().filter(|_| cycle >= settled) {
                    let _ = phase.record(dc.after_sync0_ns.max(1));
                }
                Exchanged { ok, correction_ns: d.clock_correction_ns() }
            })?;
            let sync0 = d.distributed_clocks().map(|_| (phase, missed() - missed_at_settled));
            Ok(PathRun { round_trip, wakeup, lost, sync0 })
        })
        .join()
    });
    near.map_err(|_| anyhow::anyhow!("the cycle thread panicked"))?
}

type Storage = ethercrab::PduStorage<16, { ethercrab::PduStorage::element_size(1100) }>;

fn io_uring_path(rate_hz: f64, cycles: u64, cpus: (usize, usize)) -> anyhow::Result<PathRun> {
    use ethercrab::{MainDevice, MainDeviceConfig, Timeouts};
    use futures_lite::future::block_on;
    let chain = chain(rate_hz, cpus.0)?;
    let storage: &'static Storage = Box::leak(Box::new(Storage::new()));
    let (tx, rx, pdu_loop) = storage.try_split().map_err(|()| anyhow::anyhow!("PDU storage split twice"))?;
    let near = chain.near().to_string();
    let task = std::thread::spawn(move || {
        make_current_thread_realtime_on(CYCLE_PRIORITY + 1, cpus.1);
        ethercrab::std::tx_rx_task_io_uring(&near, tx, rx).map(|_| ())
    });
    let md = MainDevice::new(
        pdu_loop,
        Timeouts { pdu: Duration::from_millis(100), ..Timeouts::default() },
        MainDeviceConfig { dc_static_sync_iterations: 0, ..MainDeviceConfig::default() },
    );
    let run = std::thread::scope(|s| {
        s.spawn(|| -> anyhow::Result<PathRun> {
            let group = block_on(md.init_single_group::<8, 256>(ethercrab::std::ethercat_now))
                .map_err(|e| anyhow::anyhow!("io_uring path: bus start-up: {e}"))?;
            for sd in group.iter(&md) {
                block_on(sd.sdo_write(0x6060, 0, 8i8))
                    .map_err(|e| anyhow::anyhow!("io_uring path: SDO: {e}"))?;
            }
            let group =
                block_on(group.into_op(&md)).map_err(|e| anyhow::anyhow!("io_uring path: OP: {e}"))?;
            let expected = 3 * group.len() as u16;
            let (round_trip, wakeup, lost) = cycle_loop(cpus.1, (1e9 / rate_hz) as u64, cycles, |_| {
                // Controlword 0 (drives stay disabled): the same frame size
                // and work for the bus, no motion needed.
                for sd in group.iter(&md) {
                    let mut o = sd.outputs_raw_mut();
                    o.fill(0);
                }
                let ok = block_on(group.tx_rx(&md)).is_ok_and(|r| r.working_counter == expected);
                Exchanged { ok, correction_ns: 0 }
            })?;
            Ok(PathRun { round_trip, wakeup, lost, sync0: None })
        })
        .join()
    });
    // SAFETY: the group lived and died inside the scope above, so no group
    // of this MainDevice is used again; releasing wakes the io_uring task,
    // which sees the exit flag and returns.
    let _ = unsafe { md.release_all() };
    let _ = task.join();
    run.map_err(|_| anyhow::anyhow!("the cycle thread panicked"))?
}

/// Both paths at 1 and 4 kHz for `seconds` each.
pub fn run(seconds: f64) -> anyhow::Result<Value> {
    let cpus = match online_cpus() {
        0 | 1 => (0, 0),
        n => (0, n - 1),
    };
    let memory_locked = lock_memory();
    let pm_qos = hold_cpu_dma_latency(0).ok();
    let mut rows = Vec::new();
    for rate in [1000.0, 4000.0] {
        let cycles = (seconds * rate) as u64;
        for (path, r) in [
            ("motor-thread poll", poll_path(rate, cycles, cpus)),
            ("ethercrab io_uring task", io_uring_path(rate, cycles, cpus)),
        ] {
            let r = r.with_context(|| format!("{path} at {rate} Hz"))?;
            rows.push(json!({
                "rate_hz": rate,
                "path": path,
                "round_trip_us": summary_ns(&r.round_trip),
                "wakeup_us": summary_ns(&r.wakeup),
                "lost_frames": r.lost,
                "sync0_phase_us": r.sync0.as_ref().map(|(h, _)| summary_ns(h)),
                "sync0_without_data": r.sync0.as_ref().map(|(_, m)| *m),
            }));
        }
    }
    Ok(json!({
        "seconds_per_run": seconds,
        "rows": rows,
        "memory_locked": memory_locked,
        "pm_qos_held": pm_qos.is_some(),
        "cpus": { "chain": cpus.0, "cycle": cpus.1 },
        "host": crate::host_facts::read_all(),
    }))
}

pub fn to_text(v: &Value) -> String {
    let mut out = format!(
        "EtherCAT process data over veth (simulated chain in a network namespace), {} s per run\n\
         {:<8} {:<24} {:>38}   {:>38}   {:>5}   {}\n",
        v["seconds_per_run"],
        "rate",
        "path",
        "round trip µs p50 / p99 / p99.9 / max",
        "wake-up µs p50 / p99 / p99.9 / max",
        "lost",
        "after SYNC0 µs p50 / p99 / max, latched without data (2nd half)"
    );
    let f = |x: &Value| x.as_f64().unwrap_or(f64::NAN);
    let q = |s: &Value| {
        format!("{:>8.1} {:>8.1} {:>9.1} {:>9.1}", f(&s["p50"]), f(&s["p99"]), f(&s["p999"]), f(&s["max"]))
    };
    for r in v["rows"].as_array().into_iter().flatten() {
        let sync0 = match (&r["sync0_phase_us"], &r["sync0_without_data"]) {
            (p, m) if p.is_object() => {
                format!("{:.1} / {:.1} / {:.1}, {}", f(&p["p50"]), f(&p["p99"]), f(&p["max"]), m)
            }
            _ => "no DC".to_string(),
        };
        out += &format!(
            "{:<8} {:<24} {}   {}   {:>5}   {}\n",
            format!("{} Hz", f(&r["rate_hz"])),
            r["path"].as_str().unwrap_or("?"),
            q(&r["round_trip_us"]),
            q(&r["wakeup_us"]),
            r["lost_frames"],
            sync0
        );
    }
    out += &format!(
        "memory locked {}, PM QoS held {}; {}",
        v["memory_locked"],
        v["pm_qos_held"],
        crate::host_facts::to_text(&v["host"])
    );
    out
}
