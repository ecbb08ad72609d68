//! The host facts that decide latency figures, read from /proc and /sys:
//! kernel and preemption model, CPU idle driver and states, CPU model and
//! count. Every bench prints them beside its figures (BENCHMARKS.md quotes
//! them), because the same code measures differently on another host.

use serde_json::{Value, json};

fn read(path: &str) -> Option<String> {
    std::fs::read_to_string(path).ok().map(|s| s.trim().to_owned()).filter(|s| !s.is_empty())
}

/// The preemption model: debugfs's `sched/preempt` marks the active one in
/// parentheses (PREEMPT_DYNAMIC kernels); else the kernel's build string.
fn preemption() -> String {
    if let Some(modes) = read("/sys/kernel/debug/sched/preempt")
        && let Some(active) = modes.split_whitespace().find(|m| m.starts_with('('))
    {
        return format!("dynamic: {}", active.trim_matches(['(', ')']));
    }
    let version = read("/proc/sys/kernel/version").unwrap_or_default();
    ["PREEMPT_RT", "PREEMPT_DYNAMIC", "PREEMPT"]
        .into_iter()
        .find(|m| version.contains(m))
        .unwrap_or("none/voluntary")
        .to_owned()
}

/// Host facts as JSON (missing ones are null).
pub fn read_all() -> Value {
    let cpu0 = "/sys/devices/system/cpu/cpu0/cpuidle";
    let states: Vec<String> = (0..16).map_while(|i| read(&format!("{cpu0}/state{i}/name"))).collect();
    let cpuinfo = read("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map(str::trim);
    json!({
        "kernel": read("/proc/sys/kernel/osrelease"),
        "preemption": preemption(),
        "cpuidle_driver": read("/sys/devices/system/cpu/cpuidle/current_driver"),
        "cpuidle_governor": read("/sys/devices/system/cpu/cpuidle/current_governor_ro")
            .or_else(|| read("/sys/devices/system/cpu/cpuidle/current_governor")),
        "cpuidle_states": states,
        "cpu_model": model,
        // Online CPUs, not this thread's affinity.
        "cpus": cpuinfo.lines().filter(|l| l.starts_with("processor")).count(),
    })
}

/// One line for a bench's text output.
pub fn to_text(v: &Value) -> String {
    let s = |k: &str| v[k].as_str().unwrap_or("?").to_owned();
    let states: Vec<&str> =
        v["cpuidle_states"].as_array().map_or(Vec::new(), |a| a.iter().filter_map(Value::as_str).collect());
    format!(
        "host: kernel {} ({}), {} × {}, cpuidle {} [{}]",
        s("kernel"),
        s("preemption"),
        v["cpus"],
        s("cpu_model"),
        s("cpuidle_driver"),
        states.join(", ")
    )
}

/// Whether this process may hold a PM QoS request (as cyclictest, run with
/// the same rights, does by default).
pub fn may_hold_pm_qos() -> bool {
    rt_core::rt_setup::hold_cpu_dma_latency(0).is_ok()
}
