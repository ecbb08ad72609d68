//! Children that must not outlive the `upm` process that started them (the
//! core, the clients, stress-ng), even when it dies by SIGKILL or abort and
//! no `Drop` runs.

use std::os::unix::process::CommandExt;
use std::process::Command;

/// Have the kernel send `signal` to the child when its parent thread dies.
/// SIGTERM lets the core bring the plate home first. The parent is the
/// spawning *thread*: spawn from a thread that lives as long as the child.
pub fn die_with_parent(cmd: &mut Command, signal: libc::c_int) -> &mut Command {
    let parent = std::process::id() as libc::pid_t;
    // SAFETY: between fork and exec the hook only calls async-signal-safe
    // functions (prctl, getppid, raise) and allocates nothing.
    unsafe {
        cmd.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, signal as libc::c_ulong, 0, 0, 0) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // The parent may have died before prctl took effect.
            if libc::getppid() != parent {
                libc::raise(signal);
            }
            Ok(())
        })
    }
}
