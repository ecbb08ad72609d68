//! Start-up steps that make a thread real-time: locked memory, a
//! prefaulted stack, SCHED_FIFO (through thread-priority), CPU affinity
//! (through libc) and the CPU idle policy (a PM QoS request, as cyclictest
//! makes). Each step reports whether it worked; without privileges the
//! core still runs and says so.

use thread_priority::{
    RealtimeThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue, ThreadSchedulePolicy,
    set_thread_priority_and_policy, thread_native_id,
};

/// Stack the RT threads are given and prefault.
pub const RT_STACK_BYTES: usize = 8 << 20;
const PREFAULT_BYTES: usize = 512 << 10;

/// `mlockall(MCL_CURRENT | MCL_FUTURE)`: no page faults later. False without
/// the privilege (RLIMIT_MEMLOCK / CAP_IPC_LOCK).
pub fn lock_memory() -> bool {
    // SAFETY: plain syscall with constant flags.
    unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) == 0 }
}

/// Touch the first part of this thread's stack so its pages are resident
/// before the loop starts.
#[inline(never)]
pub fn prefault_stack() {
    let mut buf = [0u8; PREFAULT_BYTES];
    for i in (0..PREFAULT_BYTES).step_by(4096) {
        buf[i] = 1;
    }
    std::hint::black_box(&mut buf);
}

/// The kernel's PM QoS interface: while a process holds it open with a
/// value written, no CPU enters an idle state whose exit latency exceeds
/// that value (µs). Closing it (process exit included) drops the request.
pub const CPU_DMA_LATENCY: &str = "/dev/cpu_dma_latency";

/// A held PM QoS request; dropping it releases the request.
#[derive(Debug)]
pub struct PmQosRequest(#[allow(dead_code)] std::fs::File);

/// Hold a request that idle CPUs wake within `latency_us` (0: stay out of
/// deep idle states, as cyclictest does by default). Needs write access to
/// [`CPU_DMA_LATENCY`] (root, or the udev rule in docs/deploy.md).
pub fn hold_cpu_dma_latency(latency_us: u32) -> std::io::Result<PmQosRequest> {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new().write(true).open(CPU_DMA_LATENCY)?;
    // The kernel takes a binary s32 (as cyclictest writes it).
    f.write_all(&(latency_us.min(i32::MAX as u32) as i32).to_ne_bytes())?;
    Ok(PmQosRequest(f))
}

/// What [`make_current_thread_realtime`] achieved.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ThreadPlacement {
    pub fifo: bool,
    pub pinned: bool,
}

/// SCHED_FIFO at `priority` and, if given, pin to `cpu`.
pub fn make_current_thread_realtime(priority: u8, cpu: Option<usize>) -> ThreadPlacement {
    let fifo = ThreadPriorityValue::try_from(priority).is_ok_and(|p| {
        set_thread_priority_and_policy(
            thread_native_id(),
            ThreadPriority::Crossplatform(p),
            ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
        )
        .is_ok()
    });
    let pinned = cpu.is_some_and(pin_current_thread);
    ThreadPlacement { fifo, pinned }
}

/// SCHED_FIFO at `priority` only together with the pin to `cpu`: if either
/// is refused the thread keeps its normal policy and its original CPU set
/// (a real-time thread off its CPU, or a normal one squeezed onto it, would
/// each compete where it should not).
pub fn make_current_thread_realtime_on(priority: u8, cpu: usize) -> ThreadPlacement {
    // SAFETY: a zeroed cpu_set_t is valid; pid 0 is the calling thread and
    // the size is the set's own.
    let mut original: libc::cpu_set_t = unsafe { core::mem::zeroed() };
    let saved = unsafe { libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut original) == 0 };
    if !saved || !pin_current_thread(cpu) {
        return ThreadPlacement { fifo: false, pinned: false };
    }
    let placed = make_current_thread_realtime(priority, None);
    if !placed.fifo {
        // SAFETY: restores the set read above for the calling thread.
        unsafe { libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &original) };
        return ThreadPlacement { fifo: false, pinned: false };
    }
    ThreadPlacement { fifo: true, pinned: true }
}

/// Pin the calling thread to `cpu`; false if the kernel refused.
pub fn pin_current_thread(cpu: usize) -> bool {
    if cpu >= libc::CPU_SETSIZE as usize {
        return false;
    }
    // SAFETY: a zeroed cpu_set_t is a valid empty set; CPU_SET stays in
    // bounds (checked above); pid 0 is the calling thread.
    unsafe {
        let mut set: libc::cpu_set_t = core::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

/// Take `cpu` out of the calling thread's CPU set, if another CPU remains
/// (keeps normal-priority work off the motor's CPU). Returns the set it
/// replaced, for [`restore_current_thread_cpus`]; `None` if it changed
/// nothing. Allocation-free, so a child may call it between fork and exec.
pub fn keep_current_thread_off(cpu: usize) -> Option<libc::cpu_set_t> {
    if cpu >= libc::CPU_SETSIZE as usize {
        return None;
    }
    // SAFETY: a zeroed cpu_set_t is valid; the kernel fills it for the
    // calling thread (pid 0); CPU_CLR stays in bounds (checked above).
    unsafe {
        let mut set: libc::cpu_set_t = core::mem::zeroed();
        if libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return None;
        }
        let original = set;
        libc::CPU_CLR(cpu, &mut set);
        let moved =
            libc::CPU_COUNT(&set) > 0 && libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0;
        moved.then_some(original)
    }
}

/// Give the calling thread back a set [`keep_current_thread_off`] replaced.
pub fn restore_current_thread_cpus(set: &libc::cpu_set_t) {
    // SAFETY: a set the kernel gave this thread before; pid 0 is the caller.
    unsafe { libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), set) };
}

/// CPU ids this process may run on (its affinity mask; a cpuset need not
/// start at 0 or be contiguous). Start-up only: it allocates.
pub fn allowed_cpus() -> Vec<usize> {
    // SAFETY: a zeroed cpu_set_t is valid; sched_getaffinity fills it for
    // this process; CPU_ISSET reads within CPU_SETSIZE.
    unsafe {
        let mut set: libc::cpu_set_t = core::mem::zeroed();
        if libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return (0..online_cpus()).collect();
        }
        (0..libc::CPU_SETSIZE as usize).filter(|&c| libc::CPU_ISSET(c, &set)).collect()
    }
}

/// Number of CPUs this process may run on.
pub fn online_cpus() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}
