//! Keeping a client off the core's motor CPU when it was not started by
//! `upm run` (which sets its children's CPU set before they start): the
//! motor thread's CPU is read from /proc, then every thread of this
//! process leaves it. Threads started later inherit the narrower set.

use std::path::Path;

/// The core's motor thread, as it names itself.
const MOTOR_THREAD: &str = "upm-motor";

/// The CPU the motor thread of the core `core_pid` is pinned to; None if
/// it is not pinned to one CPU, or /proc does not say.
pub fn motor_cpu(core_pid: u32) -> Option<usize> {
    let tasks = std::fs::read_dir(format!("/proc/{core_pid}/task")).ok()?;
    for task in tasks.flatten() {
        let named_motor = std::fs::read_to_string(task.path().join("comm"))
            .is_ok_and(|comm| comm.trim_end() == MOTOR_THREAD);
        if !named_motor {
            continue;
        }
        let cpus = task.file_name().to_str().and_then(|t| t.parse().ok()).and_then(thread_cpus)?;
        return match cpus.as_slice() {
            [one] => Some(*one),
            _ => None,
        };
    }
    None
}

/// Move every thread of this process off `cpu`, where another CPU of its
/// set remains. Returns how many threads moved.
pub fn keep_process_off(cpu: usize) -> usize {
    if cpu >= libc::CPU_SETSIZE as usize {
        return 0;
    }
    let Ok(tasks) = std::fs::read_dir(Path::new("/proc/self/task")) else { return 0 };
    let mut moved = 0;
    for tid in
        tasks.flatten().filter_map(|t| t.file_name().to_str().and_then(|t| t.parse::<libc::pid_t>().ok()))
    {
        // SAFETY: a zeroed cpu_set_t is a valid empty set; the kernel fills
        // it for thread `tid` of this process; CPU_CLR stays in bounds
        // (checked above).
        let done = unsafe {
            let mut set: libc::cpu_set_t = core::mem::zeroed();
            if libc::sched_getaffinity(tid, size_of::<libc::cpu_set_t>(), &mut set) != 0
                || !libc::CPU_ISSET(cpu, &set)
            {
                continue;
            }
            libc::CPU_CLR(cpu, &mut set);
            libc::CPU_COUNT(&set) > 0 && libc::sched_setaffinity(tid, size_of::<libc::cpu_set_t>(), &set) == 0
        };
        moved += usize::from(done);
    }
    moved
}

/// The CPUs thread `tid` may run on.
fn thread_cpus(tid: libc::pid_t) -> Option<Vec<usize>> {
    // SAFETY: a zeroed cpu_set_t is valid; the kernel fills it for `tid`;
    // CPU_ISSET reads within CPU_SETSIZE.
    unsafe {
        let mut set: libc::cpu_set_t = core::mem::zeroed();
        if libc::sched_getaffinity(tid, size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return None;
        }
        Some((0..libc::CPU_SETSIZE as usize).filter(|&c| libc::CPU_ISSET(c, &set)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_process_without_a_motor_thread_has_no_motor_cpu() {
        assert_eq!(motor_cpu(std::process::id()), None);
        assert_eq!(motor_cpu(u32::MAX), None);
    }

    #[test]
    fn keeping_off_a_cpu_out_of_range_moves_nothing() {
        assert_eq!(keep_process_off(usize::MAX), 0);
    }
}
