//! Child processes of `upm run`: spawn each in its own process group,
//! watch, restart with backoff, say what happened in one line, stop the
//! whole group (SIGINT, then SIGKILL after a grace period).

use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use super::process_group;

/// Backoff after a crash: doubles from `FIRST_BACKOFF` up to `MAX_BACKOFF`,
/// and starts over for a process that ran `HEALTHY_RUN` before it died
/// (a client killed once an hour is restarted as fast as the first time).
const FIRST_BACKOFF: Duration = Duration::from_millis(100);
const MAX_BACKOFF: Duration = Duration::from_secs(2);
const HEALTHY_RUN: Duration = Duration::from_secs(10);
/// An exit this soon after the start is a failure to start; `CRASH_LOOP`
/// of them in a row end the run (restarting would not help).
const QUICK_EXIT: Duration = Duration::from_secs(5);
const CRASH_LOOP: u32 = 3;
/// Time the rest of an exited client's group gets before SIGKILL.
const GROUP_GRACE: Duration = Duration::from_secs(2);

#[derive(Debug)]
pub struct Supervised {
    pub name: &'static str,
    program: PathBuf,
    args: Vec<String>,
    log: Option<PathBuf>,
    child: Option<Child>,
    pub restarts: u32,
    backoff: Duration,
    restart_at: Option<Instant>,
    /// A CPU the process must not run on (the motor's).
    avoid_cpu: Option<usize>,
    started_at: Option<Instant>,
    /// Extra environment of every start.
    envs: Vec<(String, String)>,
    /// What messages call it: the user's command, or upm's own client.
    label: String,
    /// Size of the log at the last start: what follows is this start's.
    log_offset: u64,
    /// How the last start ended ("exited with status 1 after 0.4 s").
    pub last_exit: Option<String>,
    /// Exits within `QUICK_EXIT` of their start, in a row.
    pub quick_failures: u32,
    /// Kills because the client was alive but its input stale.
    pub hung_kills: u32,
    /// The leader of a start that ended, unreaped until its group is
    /// killed (it holds the group's id).
    old_group: Option<Child>,
}

impl Supervised {
    pub fn new(name: &'static str, program: PathBuf, args: Vec<String>, log: Option<PathBuf>) -> Self {
        let label = format!("{} ({})", role(name), name);
        Self {
            name,
            program,
            args,
            log,
            child: None,
            restarts: 0,
            backoff: FIRST_BACKOFF,
            restart_at: None,
            avoid_cpu: None,
            started_at: None,
            envs: Vec::new(),
            label,
            log_offset: 0,
            last_exit: None,
            quick_failures: 0,
            hung_kills: 0,
            old_group: None,
        }
    }

    /// A shell command line (`sh -c`), for a user's own client.
    pub fn shell(name: &'static str, command: &str, log: Option<PathBuf>) -> Self {
        let mut s = Self::new(name, PathBuf::from("/bin/sh"), vec!["-c".into(), command.into()], log);
        s.label = format!("{} command {command:?}", role(name));
        s
    }

    /// Set `key=value` in the environment of every start.
    pub fn env(mut self, key: &str, value: &str) -> Self {
        self.envs.push((key.into(), value.into()));
        self
    }

    /// One more argument of every start.
    pub fn arg(mut self, arg: &str) -> Self {
        self.args.push(arg.into());
        self
    }

    /// Keep the process (each start) off `cpu`.
    pub fn avoiding_cpu(mut self, cpu: Option<usize>) -> Self {
        self.avoid_cpu = cpu;
        self
    }

    /// What messages call it: `planner command "python3 p.py"`.
    pub fn label(&self) -> &str {
        &self.label
    }

    pub fn start(&mut self) -> anyhow::Result<()> {
        let mut cmd = Command::new(&self.program);
        cmd.args(&self.args).stdin(Stdio::null());
        cmd.envs(self.envs.iter().map(|(k, v)| (k, v)));
        // Its own group: stopping it reaches whatever it started.
        cmd.process_group(0);
        // Never orphaned: a launcher killed with SIGKILL still stops its rig.
        crate::die_with_parent::die_with_parent(&mut cmd, libc::SIGTERM);
        if let Some(cpu) = self.avoid_cpu {
            // SAFETY: between fork and exec the hook only makes two
            // affinity syscalls on a stack cpu_set_t; it allocates nothing.
            unsafe {
                cmd.pre_exec(move || {
                    let _ = rt_core::rt_setup::keep_current_thread_off(cpu);
                    Ok(())
                });
            }
        }
        if let Some(log) = &self.log {
            let f = std::fs::OpenOptions::new().create(true).append(true).open(log)?;
            self.log_offset = f.metadata().map(|m| m.len()).unwrap_or(0);
            cmd.stdout(f.try_clone()?).stderr(f);
        }
        let child = cmd
            .spawn()
            .map_err(|e| anyhow::anyhow!("starting {} ({}): {e}", self.label, self.program.display()))?;
        self.child = Some(child);
        self.started_at = Some(Instant::now());
        Ok(())
    }

    pub fn pid(&self) -> Option<u32> {
        self.child.as_ref().map(Child::id)
    }

    /// How long the current start has run.
    pub fn uptime(&self) -> Option<Duration> {
        self.child.as_ref().and(self.started_at).map(|t| t.elapsed())
    }

    /// Exit status if the process has ended (and is not yet restarted).
    /// The leader is not reaped: while it is a zombie its pid, which is
    /// the group's id, cannot be reused, so signalling the group later
    /// never reaches another one.
    pub fn exited(&mut self) -> Option<ExitStatus> {
        self.child.as_ref().and_then(|c| process_group::peek_exit(c.id()))
    }

    /// Restart a dead process once its backoff has passed. Returns one line
    /// for a person when something happened: the exit (with the command,
    /// status or signal, and the log's last line), or nothing.
    pub fn restart_if_dead(&mut self) -> anyhow::Result<Option<String>> {
        if let Some(at) = self.restart_at {
            if Instant::now() >= at {
                self.restart_at = None;
                self.restarts += 1;
                // The old start's leftovers must not publish beside the new one.
                self.reap_old_group();
                self.start()?;
            }
            return Ok(None);
        }
        let Some(status) = self.exited() else { return Ok(None) };
        let ran = self.uptime().unwrap_or_default();
        // The leader is gone; its group goes too (SIGKILL at the restart).
        if let Some(child) = self.child.take() {
            process_group::signal(child.id(), libc::SIGTERM);
            self.old_group = Some(child);
        }
        self.quick_failures = if ran < QUICK_EXIT { self.quick_failures + 1 } else { 0 };
        let event = self.note_exit(&describe_exit(status), ran);
        if self.crash_looping() {
            // Restarting would not help: the launcher ends the run.
            return Ok(Some(format!(
                "{event}; {CRASH_LOOP} failures in a row, each within {} s of its start",
                QUICK_EXIT.as_secs()
            )));
        }
        Ok(Some(self.schedule_restart(event, ran)))
    }

    /// Restart after the backoff (starting over after a healthy run);
    /// returns `event` with when.
    fn schedule_restart(&mut self, event: String, ran: Duration) -> String {
        if ran >= HEALTHY_RUN {
            self.backoff = FIRST_BACKOFF;
        }
        let line = format!("{event}; restart {} in {:.1} s", self.restarts + 1, self.backoff.as_secs_f64());
        self.restart_at = Some(Instant::now() + self.backoff);
        self.backoff = (self.backoff * 2).min(MAX_BACKOFF);
        line
    }

    /// SIGKILL what is left of an ended start's group, then reap its leader.
    fn reap_old_group(&mut self) {
        if let Some(mut old) = self.old_group.take() {
            process_group::signal(old.id(), libc::SIGKILL);
            let _ = old.wait();
        }
    }

    /// True once the client failed `CRASH_LOOP` times in a row, each within
    /// `QUICK_EXIT` of its start.
    pub fn crash_looping(&self) -> bool {
        self.quick_failures >= CRASH_LOOP
    }

    /// Kill a client that is alive but whose input went stale (`why`), with
    /// its group, and restart it after the backoff. Returns the line.
    pub fn kill_hung(&mut self, why: &str) -> String {
        let ran = self.uptime().unwrap_or_default();
        let Some(mut child) = self.child.take() else { return String::new() };
        process_group::signal(child.id(), libc::SIGKILL);
        let _ = child.wait();
        self.hung_kills += 1;
        self.quick_failures = 0;
        let event = self.note_exit(&format!("is hung ({why}) and was killed with its process group"), ran);
        self.schedule_restart(event, ran)
    }

    /// One line for a person on how this start ended with `status`.
    pub fn describe_end(&mut self, status: ExitStatus) -> String {
        let ran = self.uptime().unwrap_or_default();
        self.note_exit(&describe_exit(status), ran)
    }

    /// Record how this start ended; returns `<label> <what> after T s
    /// (<log's last line>; <log>)`.
    fn note_exit(&mut self, what: &str, ran: Duration) -> String {
        self.last_exit = Some(format!("{what} after {:.1} s", ran.as_secs_f64()));
        let log = self.log.as_ref().map(|l| l.display().to_string());
        let hint = self.log.as_ref().and_then(|l| last_line(l, self.log_offset));
        let paren = match (hint, log) {
            (Some(h), Some(l)) => format!(" ({h}; {l})"),
            (None, Some(l)) => format!(" ({l})"),
            _ => String::new(),
        };
        format!("{} {what} after {:.1} s{paren}", self.label, ran.as_secs_f64())
    }

    /// Signal the group (SIGINT), wait up to `grace` for all of it, then
    /// SIGKILL the group. Returns the leader's exit status and keeps it in
    /// `last_exit`. The leader is reaped last, once its group is gone.
    pub fn stop(&mut self, grace: Duration) -> Option<ExitStatus> {
        self.restart_at = None;
        self.reap_old_group();
        let mut child = self.child.take()?;
        let pgid = child.id();
        process_group::signal(pgid, libc::SIGINT);
        if !process_group::wait_empty(pgid, grace) {
            process_group::signal(pgid, libc::SIGKILL);
            process_group::wait_empty(pgid, GROUP_GRACE);
        }
        let status = child.wait().ok();
        if let Some(s) = status {
            self.last_exit = Some(format!("{} when stopped", describe_exit(s)));
        }
        status
    }
}

impl Drop for Supervised {
    fn drop(&mut self) {
        self.stop(Duration::from_secs(2));
    }
}

/// "planner" for "upm-planner".
fn role(name: &str) -> &str {
    name.trim_start_matches("upm-")
}

/// "exited with status 1", "was killed by signal 9 (SIGKILL)".
pub fn describe_exit(status: ExitStatus) -> String {
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("exited with status {code}"),
        (None, Some(sig)) => format!("was killed by signal {sig} ({})", signal_name(sig)),
        (None, None) => format!("ended ({status})"),
    }
}

fn signal_name(sig: i32) -> &'static str {
    match sig {
        libc::SIGHUP => "SIGHUP",
        libc::SIGINT => "SIGINT",
        libc::SIGQUIT => "SIGQUIT",
        libc::SIGILL => "SIGILL",
        libc::SIGABRT => "SIGABRT",
        libc::SIGBUS => "SIGBUS",
        libc::SIGFPE => "SIGFPE",
        libc::SIGKILL => "SIGKILL",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGPIPE => "SIGPIPE",
        libc::SIGTERM => "SIGTERM",
        _ => "signal",
    }
}

/// The last non-empty line written to `log` after byte `from`, shortened
/// to 200 characters: for a Python client, the exception.
fn last_line(log: &std::path::Path, from: u64) -> Option<String> {
    use std::io::{Read, Seek, SeekFrom};
    let mut f = std::fs::File::open(log).ok()?;
    let len = f.metadata().ok()?.len();
    let start = from.max(len.saturating_sub(64 * 1024));
    f.seek(SeekFrom::Start(start)).ok()?;
    let mut bytes = Vec::new();
    f.read_to_end(&mut bytes).ok()?;
    let text = String::from_utf8_lossy(&bytes);
    let line = text.lines().map(str::trim).rfind(|l| !l.is_empty())?;
    let short: String = line.chars().take(200).collect();
    Some(if short.len() < line.len() { format!("{short}…") } else { short })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait_exit(s: &mut Supervised) {
        while s.child.is_some() && s.exited().is_none() {
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn backoff_doubles_for_crash_loops_and_starts_over_after_a_healthy_run() {
        let mut s = Supervised::new("true", "true".into(), Vec::new(), None);
        for expected_ms in [100, 200] {
            s.start().expect("start");
            wait_exit(&mut s);
            assert!(s.restart_if_dead().expect("restart").is_some());
            assert_eq!(s.restart_at.map(|_| ()), Some(()));
            s.restart_at = None;
            assert_eq!(
                s.backoff,
                Duration::from_millis(expected_ms * 2),
                "after a crash at {expected_ms} ms"
            );
        }
        s.start().expect("start");
        wait_exit(&mut s);
        let line = s.restart_if_dead().expect("restart").expect("reported");
        assert!(s.crash_looping(), "three exits within a second of their start");
        assert!(s.restart_at.is_none(), "no restart after the third: {line}");
        assert!(line.ends_with("; 3 failures in a row, each within 5 s of its start"), "{line}");
        s.quick_failures = 0;
        (s.program, s.args) = ("sleep".into(), vec!["10.1".into()]);
        s.start().expect("start");
        wait_exit(&mut s);
        s.restart_if_dead().expect("restart");
        assert_eq!(s.backoff, FIRST_BACKOFF * 2, "a 10 s run did not reset the backoff");
        assert!(!s.crash_looping(), "a 10 s run ends the streak");
    }

    #[test]
    fn an_exit_is_one_line_naming_the_command_status_log_and_its_last_line() {
        let dir = std::env::temp_dir().join(format!("upm_supervised_{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let log = dir.join("planner.log");
        std::fs::write(&log, "an older start's last words\n").expect("log");
        let cmd = "echo 'Traceback (most recent call last):'; echo 'ModuleNotFoundError: x' >&2; exit 3";
        let mut s = Supervised::shell("upm-planner", cmd, Some(log.clone()));
        s.start().expect("start");
        wait_exit(&mut s);
        let line = s.restart_if_dead().expect("restart").expect("an exit is reported");
        let want = format!("planner command {cmd:?} exited with status 3 after ");
        assert!(line.starts_with(&want), "{line}");
        assert!(line.contains(&format!(" s (ModuleNotFoundError: x; {})", log.display())), "{line}");
        assert!(line.ends_with("; restart 1 in 0.1 s"), "{line}");
        assert!(s.last_exit.as_deref().is_some_and(|e| e.starts_with("exited with status 3 after")));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_clean_exit_says_exited_and_a_signal_is_named() {
        let ok = std::process::Command::new("true").status().expect("true");
        assert_eq!(describe_exit(ok), "exited with status 0");
        let killed = std::process::Command::new("sh").args(["-c", "kill -9 $$"]).status().expect("sh");
        assert_eq!(describe_exit(killed), "was killed by signal 9 (SIGKILL)");
    }

    #[test]
    fn stopping_a_client_stops_a_grandchild_that_ignores_sigint_and_sigterm() {
        let dir = std::env::temp_dir().join(format!("upm_group_{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let pidfile = dir.join("grandchild.pid");
        let cmd = format!("(trap '' INT TERM; exec sleep 600) & echo $! > '{}'; wait", pidfile.display());
        let mut s = Supervised::shell("upm-planner", &cmd, None);
        s.start().expect("start");
        let pid = loop {
            if let Some(p) = std::fs::read_to_string(&pidfile).ok().and_then(|t| t.trim().parse::<u32>().ok())
            {
                break p;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        s.stop(Duration::from_millis(300));
        assert!(!process_group::running(pid), "the grandchild {pid} outlived its client");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
