//! A client and everything it starts, as one process group: `upm run`
//! signals the group, so a `sh -c` wrapper's children and their children
//! stop with it.

use std::time::{Duration, Instant};

/// Send `signal` to every process of group `pgid`, if one runs. The
/// caller keeps the group's leader unreaped until the last signal, so the
/// id cannot have passed to another group.
pub fn signal(pgid: u32, signal: libc::c_int) {
    if pgid > 0 && alive(pgid) {
        // SAFETY: kill(2) with a negative pid signals a group we created.
        unsafe { libc::kill(-(pgid as libc::pid_t), signal) };
    }
}

/// The exit status of child `pid` if it has ended, without reaping it
/// (`waitid` with `WNOWAIT`): it stays a zombie, holding its pid.
pub fn peek_exit(pid: u32) -> Option<std::process::ExitStatus> {
    use std::os::unix::process::ExitStatusExt;
    // SAFETY: an all-zero siginfo_t is valid; waitid fills it for our child.
    let mut info: libc::siginfo_t = unsafe { std::mem::zeroed() };
    let flags = libc::WEXITED | libc::WNOHANG | libc::WNOWAIT;
    // SAFETY: waitid(2) on our own child, into a local siginfo_t.
    if unsafe { libc::waitid(libc::P_PID, pid as libc::id_t, &mut info, flags) } != 0 {
        return None;
    }
    // SAFETY: si_pid and si_status are set for a child that changed state.
    let (who, status) = unsafe { (info.si_pid(), info.si_status()) };
    // Encoded as wait(2) would, so ExitStatus reads it back.
    let raw = match info.si_code {
        _ if who == 0 => return None,
        libc::CLD_EXITED => (status & 0xff) << 8,
        libc::CLD_KILLED => status,
        libc::CLD_DUMPED => status | 0x80,
        _ => return None,
    };
    Some(std::process::ExitStatus::from_raw(raw))
}

/// True while a process of group `pgid` is running (zombies do not count:
/// an orphan's zombie waits for a reaper, not for us).
pub fn alive(pgid: u32) -> bool {
    let Ok(dir) = std::fs::read_dir("/proc") else { return false };
    dir.flatten()
        .filter(|e| e.file_name().to_string_lossy().bytes().all(|b| b.is_ascii_digit()))
        .any(|e| std::fs::read_to_string(e.path().join("stat")).is_ok_and(|stat| member(&stat, pgid)))
}

/// True while process `pid` runs (not a zombie).
pub fn running(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| state_and_group(&stat).0)
}

/// Whether one `/proc/PID/stat` line is a live member of group `pgid`.
fn member(stat: &str, pgid: u32) -> bool {
    let (live, pgrp) = state_and_group(stat);
    live && pgrp == Some(pgid)
}

/// From a `/proc/PID/stat` line: not a zombie, and the process group.
fn state_and_group(stat: &str) -> (bool, Option<u32>) {
    // After the command name (which may hold spaces and parentheses):
    // state, ppid, pgrp.
    let Some(rest) = stat.rfind(')').map(|i| &stat[i + 1..]) else { return (false, None) };
    let mut fields = rest.split_whitespace();
    let state = fields.next();
    let pgrp = fields.nth(1).and_then(|f| f.parse::<u32>().ok());
    (state.is_some_and(|s| !matches!(s, "Z" | "X")), pgrp)
}

/// Wait up to `grace` for group `pgid` to empty; true if it did.
pub fn wait_empty(pgid: u32, grace: Duration) -> bool {
    let start = Instant::now();
    loop {
        if !alive(pgid) {
            return true;
        }
        if start.elapsed() >= grace {
            return false;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stat_line_is_read_past_a_command_name_with_spaces_and_parentheses() {
        let line = "4242 (a (b) c) S 1 777 777 0 -1 4194560 0 0";
        assert!(member(line, 777));
        assert!(!member(line, 1));
        assert!(!member("4242 (x) Z 1 777 777 0", 777), "a zombie is not alive");
        assert!(!member("garbage", 777));
    }

    #[test]
    fn an_exit_is_seen_without_reaping_the_child() {
        let mut child = std::process::Command::new("sh").args(["-c", "exit 7"]).spawn().expect("sh");
        let pid = child.id();
        let seen = loop {
            if let Some(s) = peek_exit(pid) {
                break s;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        assert_eq!(seen.code(), Some(7));
        assert!(std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok(), "still a zombie, not reaped");
        assert_eq!(child.wait().expect("wait").code(), Some(7));
        let mut killed = std::process::Command::new("sleep").arg("30").spawn().expect("sleep");
        let _ = killed.kill();
        let seen = loop {
            if let Some(s) = peek_exit(killed.id()) {
                break s;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(seen.signal(), Some(libc::SIGKILL));
        let _ = killed.wait();
    }

    #[test]
    fn a_group_is_alive_while_a_member_runs() {
        use std::os::unix::process::CommandExt;
        let mut child =
            std::process::Command::new("sleep").arg("30").process_group(0).spawn().expect("sleep");
        let pgid = child.id();
        assert!(alive(pgid));
        signal(pgid, libc::SIGKILL);
        let _ = child.wait();
        assert!(wait_empty(pgid, Duration::from_secs(5)));
    }
}
