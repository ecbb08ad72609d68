//! A veth pair whose far end lives in a network namespace of its own, for
//! running the simulated chain "on the other end of a cable". Needs root
//! (CAP_NET_ADMIN and CAP_SYS_ADMIN); [`VethPair::create`] says why not
//! otherwise, so a test can skip with that message. Dropping the pair
//! deletes the namespace and both ends.

use std::process::Command;

#[derive(Debug)]
pub struct VethPair {
    /// The MainDevice's end, in this namespace.
    pub near: String,
    /// The chain's end, inside `namespace`.
    pub far: String,
    pub namespace: String,
}

fn ip(args: &[&str]) -> Result<(), String> {
    let o = Command::new("ip").args(args).output().map_err(|e| format!("running `ip`: {e}"))?;
    if o.status.success() {
        Ok(())
    } else {
        Err(format!("`ip {}`: {}", args.join(" "), String::from_utf8_lossy(&o.stderr).trim()))
    }
}

impl VethPair {
    /// Create the namespace `upm_ecat_<tag>` and a veth pair between it and
    /// this namespace, both ends up. `tag` keeps parallel runs apart (at
    /// most 8 characters: interface names are short).
    pub fn create(tag: &str) -> Result<Self, String> {
        // SAFETY: geteuid has no preconditions.
        if unsafe { libc::geteuid() } != 0 {
            return Err("a veth pair in a network namespace needs root".into());
        }
        let tag: String = tag.chars().filter(char::is_ascii_alphanumeric).take(8).collect();
        let pair = Self {
            near: format!("ue{tag}a"),
            far: format!("ue{tag}b"),
            namespace: format!("upm_ecat_{tag}"),
        };
        // Stale leftovers of a killed run with the same tag.
        let _ = ip(&["netns", "del", &pair.namespace]);
        let _ = ip(&["link", "del", &pair.near]);
        ip(&["netns", "add", &pair.namespace])?;
        let made = ip(&[
            "link",
            "add",
            &pair.near,
            "type",
            "veth",
            "peer",
            "name",
            &pair.far,
            "netns",
            &pair.namespace,
        ])
        .and_then(|()| ip(&["-n", &pair.namespace, "link", "set", &pair.far, "up"]))
        .and_then(|()| ip(&["link", "set", &pair.near, "up"]));
        // Dropped on error: the namespace goes again.
        made.map(|()| pair)
    }

    /// Run `f` on a new thread that has entered the far end's namespace
    /// (so a socket it opens sits on `far`).
    pub fn in_namespace<R: Send + 'static>(
        &self,
        f: impl FnOnce() -> R + Send + 'static,
    ) -> std::thread::JoinHandle<Result<R, String>> {
        let path = format!("/var/run/netns/{}", self.namespace);
        std::thread::spawn(move || {
            let c = std::ffi::CString::new(path.clone()).map_err(|e| e.to_string())?;
            // SAFETY: a NUL-terminated path; the fd is closed below.
            let fd = unsafe { libc::open(c.as_ptr(), libc::O_RDONLY | libc::O_CLOEXEC) };
            if fd < 0 {
                return Err(format!("open {path}: {}", std::io::Error::last_os_error()));
            }
            // SAFETY: fd is a network namespace; setns affects this thread only.
            let r = unsafe { libc::setns(fd, libc::CLONE_NEWNET) };
            // SAFETY: fd is ours.
            unsafe { libc::close(fd) };
            if r != 0 {
                return Err(format!("setns {path}: {}", std::io::Error::last_os_error()));
            }
            Ok(f())
        })
    }
}

impl Drop for VethPair {
    fn drop(&mut self) {
        let _ = ip(&["netns", "del", &self.namespace]);
        let _ = ip(&["link", "del", &self.near]);
    }
}
