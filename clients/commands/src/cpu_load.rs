//! CPU load for latency-under-stress runs: stress-ng when it is installed,
//! else a built-in burner (arithmetic plus a cache-thrashing walk over
//! 32 MiB per CPU). Both run on every CPU except the motor thread's, so the
//! load competes with the solver, the io thread and the clients, the way
//! other work on a rig's "other" core would.

use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

/// Running load; stops when dropped.
#[derive(Debug)]
pub struct CpuLoad {
    description: String,
    child: Option<Child>,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

/// The CPUs to load: all allowed ones but `motor_cpu` (all of them on a
/// one-CPU machine).
pub fn other_cpus(motor_cpu: Option<usize>) -> Vec<usize> {
    let all = rt_core::rt_setup::allowed_cpus();
    let others: Vec<usize> = all.iter().copied().filter(|&c| Some(c) != motor_cpu).collect();
    if others.is_empty() { all } else { others }
}

impl CpuLoad {
    /// Start loading `cpus`: stress-ng if found, else the built-in burner.
    pub fn start(cpus: &[usize]) -> anyhow::Result<Self> {
        let list = cpus.iter().map(usize::to_string).collect::<Vec<_>>().join(",");
        let args = [
            "--cpu".to_owned(),
            cpus.len().to_string(),
            "--vm".to_owned(),
            "1".to_owned(),
            "--vm-bytes".to_owned(),
            "128M".to_owned(),
            "--taskset".to_owned(),
            list.clone(),
            "--quiet".to_owned(),
        ];
        let stop = Arc::new(AtomicBool::new(false));
        let mut cmd = Command::new("stress-ng");
        cmd.args(&args).stdout(Stdio::null()).stderr(Stdio::null());
        // Never left burning CPUs if upm dies without running Drop.
        crate::die_with_parent::die_with_parent(&mut cmd, libc::SIGTERM);
        if let Ok(mut child) = cmd.spawn() {
            // A stress-ng that refuses its options exits at once: then burn ourselves.
            std::thread::sleep(std::time::Duration::from_millis(300));
            if matches!(child.try_wait(), Ok(None)) {
                let description = format!("stress-ng {}", args.join(" "));
                return Ok(Self { description, child: Some(child), stop, threads: Vec::new() });
            }
        }
        let mut threads = Vec::new();
        let unpinned = Arc::new(AtomicBool::new(false));
        for &cpu in cpus {
            let (stop, unpinned) = (stop.clone(), unpinned.clone());
            let t = std::thread::Builder::new().name(format!("upm-load-{cpu}")).spawn(move || {
                // Unpinned, the load could land on the motor's CPU: then none.
                if rt_core::rt_setup::pin_current_thread(cpu) {
                    burn(&stop);
                } else {
                    unpinned.store(true, Ordering::Relaxed);
                }
            })?;
            threads.push(t);
        }
        let description = format!("built-in burner on CPUs {list} (stress-ng not installed or refused)");
        let load = Self { description, child: None, stop, threads };
        std::thread::sleep(std::time::Duration::from_millis(50));
        if unpinned.load(Ordering::Relaxed) {
            // Dropping `load` stops the threads that did start.
            anyhow::bail!("cannot pin the CPU load to CPUs {list}; refusing to load the motor's CPU");
        }
        Ok(load)
    }

    /// What is running, for reports.
    pub fn description(&self) -> &str {
        &self.description
    }
}

impl Drop for CpuLoad {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(c) = &mut self.child {
            let _ = c.kill();
            let _ = c.wait();
        }
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// Until `stop`: floating point work and a strided walk that misses cache.
fn burn(stop: &AtomicBool) {
    const WORDS: usize = 4 << 20; // 32 MiB of u64
    let mut buf = vec![1u64; WORDS];
    let mut x = 1.000_1f64;
    let mut i = 0usize;
    while !stop.load(Ordering::Relaxed) {
        for _ in 0..4096 {
            // 8 words = one cache line; odd stride in lines defeats prefetch.
            i = (i + 8 * 97) % WORDS;
            buf[i] = buf[i].wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            x = (x * 1.000_000_1).sqrt() + 0.5;
        }
    }
    std::hint::black_box((&buf, x));
}
