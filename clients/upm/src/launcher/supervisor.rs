//! Child processes of `upm run`: spawn, watch, restart with backoff, stop
//! with SIGINT (then SIGKILL if they do not exit).

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Backoff after a crash: doubles from `FIRST_BACKOFF` up to `MAX_BACKOFF`,
/// and starts over for a process that ran `HEALTHY_RUN` before it died
/// (a client killed once an hour is restarted as fast as the first time).
const FIRST_BACKOFF: Duration = Duration::from_millis(100);
const MAX_BACKOFF: Duration = Duration::from_secs(2);
const HEALTHY_RUN: Duration = Duration::from_secs(10);

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
}

impl Supervised {
    pub fn new(name: &'static str, program: PathBuf, args: Vec<String>, log: Option<PathBuf>) -> Self {
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
        }
    }

    /// A shell command line (`sh -c`), for a user's own client.
    pub fn shell(name: &'static str, command: &str, log: Option<PathBuf>) -> Self {
        Self::new(name, PathBuf::from("/bin/sh"), vec!["-c".into(), command.into()], log)
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

    pub fn start(&mut self) -> anyhow::Result<()> {
        let mut cmd = Command::new(&self.program);
        cmd.args(&self.args).stdin(Stdio::null());
        cmd.envs(self.envs.iter().map(|(k, v)| (k, v)));
        // Never orphaned: a launcher killed with SIGKILL still stops its rig.
        crate::die_with_parent::die_with_parent(&mut cmd, libc::SIGTERM);
        if let Some(cpu) = self.avoid_cpu {
            // SAFETY: between fork and exec the hook only makes two
            // affinity syscalls on a stack cpu_set_t; it allocates nothing.
            unsafe {
                std::os::unix::process::CommandExt::pre_exec(&mut cmd, move || {
                    let _ = rt_core::runtime::rt_setup::keep_current_thread_off(cpu);
                    Ok(())
                });
            }
        }
        if let Some(log) = &self.log {
            let f = std::fs::OpenOptions::new().create(true).append(true).open(log)?;
            cmd.stdout(f.try_clone()?).stderr(f);
        }
        let child = cmd
            .spawn()
            .map_err(|e| anyhow::anyhow!("starting {} ({}): {e}", self.name, self.program.display()))?;
        self.child = Some(child);
        self.started_at = Some(Instant::now());
        Ok(())
    }

    pub fn pid(&self) -> Option<u32> {
        self.child.as_ref().map(Child::id)
    }

    /// Exit status if the process has ended (and is not yet restarted).
    pub fn exited(&mut self) -> Option<std::process::ExitStatus> {
        self.child.as_mut().and_then(|c| c.try_wait().ok().flatten())
    }

    /// Restart a dead process once its backoff has passed. Returns true
    /// when it restarted it now.
    pub fn restart_if_dead(&mut self) -> anyhow::Result<bool> {
        if let Some(at) = self.restart_at {
            if Instant::now() >= at {
                self.restart_at = None;
                self.restarts += 1;
                self.start()?;
                return Ok(true);
            }
            return Ok(false);
        }
        if self.exited().is_some() {
            self.child = None;
            if self.started_at.is_some_and(|t| t.elapsed() >= HEALTHY_RUN) {
                self.backoff = FIRST_BACKOFF;
            }
            self.restart_at = Some(Instant::now() + self.backoff);
            self.backoff = (self.backoff * 2).min(MAX_BACKOFF);
        }
        Ok(false)
    }

    /// SIGINT, wait up to `grace`, then SIGKILL. Returns the exit status.
    pub fn stop(&mut self, grace: Duration) -> Option<std::process::ExitStatus> {
        let mut child = self.child.take()?;
        if let Ok(Some(s)) = child.try_wait() {
            return Some(s);
        }
        // SAFETY: kill(2) on our own child's pid.
        unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
        let start = Instant::now();
        while start.elapsed() < grace {
            if let Ok(Some(s)) = child.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = child.kill();
        child.wait().ok()
    }
}

impl Drop for Supervised {
    fn drop(&mut self) {
        self.stop(Duration::from_secs(2));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait_exit(s: &mut Supervised) {
        while s.child.as_mut().is_some_and(|c| c.try_wait().ok().flatten().is_none()) {
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn backoff_doubles_for_crash_loops_and_starts_over_after_a_healthy_run() {
        let mut s = Supervised::new("true", "true".into(), Vec::new(), None);
        for expected_ms in [100, 200, 400] {
            s.start().expect("start");
            wait_exit(&mut s);
            assert!(!s.restart_if_dead().expect("restart"));
            assert_eq!(s.restart_at.map(|_| ()), Some(()));
            s.restart_at = None;
            assert_eq!(
                s.backoff,
                Duration::from_millis(expected_ms * 2),
                "after a crash at {expected_ms} ms"
            );
        }
        (s.program, s.args) = ("sleep".into(), vec!["10.1".into()]);
        s.start().expect("start");
        wait_exit(&mut s);
        s.restart_if_dead().expect("restart");
        assert_eq!(s.backoff, FIRST_BACKOFF * 2, "a 10 s run did not reset the backoff");
    }
}
