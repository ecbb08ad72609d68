//! The operator page in a real browser: headless Debian chromium, driven
//! through chromedriver by Python's selenium
//! (`clients/hmi/clients/browser_operator.py`), on a feed rig started as
//! an operator would (`upm run feed --hmi ADDR --users FILE`). What the
//! page shows is checked against `upm status --json`; a wrong password is
//! refused; a logged-in operator presses stop and the rig stops.
//! `UPM_HMI_SCREENSHOT=FILE.png` also saves the page as the browser drew it.

mod common;

use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{add_user, free_port, json_of, upm};

/// The rig, stopped with Ctrl-C whatever the test's outcome.
struct Rig(Child);

impl Drop for Rig {
    fn drop(&mut self) {
        // SAFETY: a plain kill(2) on the child this test started.
        unsafe { libc::kill(self.0.id() as i32, libc::SIGINT) };
        let _ = self.0.wait();
    }
}

#[test]
fn an_operator_in_chromium_sees_the_live_rig_and_stops_it() {
    for (path, package) in [("/usr/bin/chromium", "chromium"), ("/usr/bin/chromedriver", "chromium-driver")] {
        assert!(
            Path::new(path).is_file(),
            "{path} is missing: this test drives Debian's headless chromium; install it with \
             `apt-get install -y chromium chromium-driver` ({package}; .ci/run does)"
        );
    }
    let py = common::venv("upm-selenium", "selenium", "selenium==4.38.0");
    let dir = common::fresh_dir("hmi_browser");
    let users = dir.join("users.toml");
    add_user(&users, "operator", "stop-pass-1");
    let addr = format!("127.0.0.1:{}", free_port());
    let prefix = common::unique_prefix("hmi");
    let rig = Rig(upm()
        .args(["run", "feed", "--duration", "300", "--quiet", "--no-record", "--hmi", &addr, "--users"])
        .arg(&users)
        .args(["--prefix", &prefix, "--out"])
        .arg(dir.join("run"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("upm run"));
    let deadline = Instant::now() + Duration::from_secs(60);
    while TcpStream::connect(&addr).is_err() {
        assert!(
            Instant::now() < deadline,
            "the page's server never came up; see {}",
            dir.join("run/logs").display()
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../hmi/clients/browser_operator.py");
    let mut operator = Command::new(&py);
    operator.arg(script).arg(format!("http://{addr}/")).arg(env!("CARGO_BIN_EXE_upm"));
    operator.args([prefix.as_str(), "operator", "stop-pass-1"]);
    if let Some(shot) = std::env::var_os("UPM_HMI_SCREENSHOT") {
        operator.arg(std::path::absolute(shot).expect("screenshot path"));
    }
    let seen = json_of(&operator.output().expect("browser_operator.py"), "browser_operator.py");
    drop(rig);
    let log = std::fs::read_to_string(dir.join("run/logs/hmi.log")).unwrap_or_default();
    common::remove_prefix(&prefix);

    // What the page showed, beside `upm status` read between two looks.
    assert_eq!(seen["title"], "UPM rig", "{seen}");
    let status_parts =
        seen["status_parts_on_plate"].as_i64().unwrap_or_else(|| panic!("no feed in status: {seen}"));
    for look in ["page_before", "page_after"] {
        let page = &seen[look];
        assert_eq!(page["state"], seen["status_state"], "{look}: {seen}");
        let parts = page["parts_on_plate"].as_i64().expect("a count");
        assert!(
            (parts - status_parts).abs() <= 2,
            "{look}: {parts} parts on the page, {status_parts} in status"
        );
    }
    assert!(
        seen["parts_drawn"].as_u64().is_some_and(|n| n >= 3),
        "parts and poses labelled on the plate: {seen}"
    );
    // Controls: refused without a login and with a wrong password.
    assert_eq!(seen["stop_enabled_before_login"], false, "{seen}");
    assert!(seen["wrong_password"].as_str().is_some_and(|m| m.contains("wrong password")), "{seen}");
    assert_eq!(seen["stop_enabled_after_wrong_password"], false, "{seen}");
    // Logged in, stop: the page and `upm status` both see the rig stopped.
    assert_eq!(seen["operator"], "operator: operator", "{seen}");
    assert_eq!(seen["page_state_after_stop"], "idle", "{seen}");
    assert_eq!(seen["status_state_after_stop"], "idle", "{seen}");
    let counters = &seen["server_status"]["counters"];
    assert_eq!(
        (
            counters["login_failures"].as_u64(),
            counters["logins"].as_u64(),
            counters["commands_sent"].as_u64()
        ),
        (Some(1), Some(1), Some(1)),
        "{seen}"
    );
    // The page's server counted the same at exit, in its log.
    assert!(log.contains("upm-hmi: stopped;") && log.contains("login_failures 1"), "hmi.log: {log}");
    let _ = std::fs::remove_dir_all(&dir);
}
