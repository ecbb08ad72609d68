//! `upm-hmi` as a stranger starts it, on a rig prefix of its own with no
//! core: wrong starts are refused in one line; the page, its status and
//! its login rules over plain HTTP (the browser test on a running rig is
//! `clients/upm/tests/hmi_browser.rs`). This test also makes `cargo test`
//! build the binary, which `upm run --hmi` starts.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn hmi() -> Command {
    Command::new(env!("CARGO_BIN_EXE_upm-hmi"))
}

fn refused(args: &[&str]) -> String {
    let out = hmi().args(args).output().expect("running upm-hmi");
    assert_eq!(out.status.code(), Some(1), "{args:?}: {out:?}");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let last = err.lines().last().unwrap_or_default().to_owned();
    assert!(last.starts_with("upm-hmi: error: "), "{args:?}: {err}");
    last
}

/// One HTTP/1.1 exchange: (status, headers, body).
fn http(
    addr: &str,
    method: &str,
    path: &str,
    cookie: Option<&str>,
    body: Option<&str>,
) -> (u16, String, String) {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(60))).expect("timeout");
    let mut req = format!("{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n");
    if let Some(c) = cookie {
        req += &format!("Cookie: {c}\r\n");
    }
    if let Some(b) = body {
        req += &format!("Content-Type: application/json\r\nContent-Length: {}\r\n", b.len());
    }
    req += "\r\n";
    req += body.unwrap_or("");
    s.write_all(req.as_bytes()).expect("send");
    let mut answer = String::new();
    s.read_to_string(&mut answer).expect("answer");
    let (head, body) = answer.split_once("\r\n\r\n").unwrap_or((&answer, ""));
    let status = head.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, head.to_owned(), body.to_owned())
}

struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn wrong_starts_are_refused_in_one_line() {
    let prefix = format!("upm_hmi_process_bad_{}_", std::process::id());
    let missing = std::env::temp_dir().join(format!("upm_hmi_no_users_{}.toml", std::process::id()));
    let missing = missing.display().to_string();
    let e = refused(&["--prefix", &prefix, "--users", &missing]);
    assert!(e.contains(&missing), "{e}");
    let e = refused(&["--prefix", &prefix, "--duration=0"]);
    assert!(e.contains("--duration"), "{e}");
    ipc_types::rig_node::remove_prefix_segment(&prefix);
}

#[test]
fn the_page_shows_and_only_a_user_of_the_file_may_control() {
    let dir = std::env::temp_dir().join(format!("upm_hmi_process_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let users = dir.join("users.toml");
    let _ = std::fs::remove_file(&users);
    upm_users::add_user(&users, "ann", "right-pass-1").expect("add user");
    let prefix = format!("upm_hmi_process_{}_", std::process::id());
    let mut child = hmi()
        .args(["--prefix", &prefix, "--addr", "127.0.0.1:0", "--users"])
        .arg(&users)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("upm-hmi");
    let mut out = BufReader::new(child.stdout.take().expect("stdout"));
    let server = Server(child);
    let mut first = String::new();
    out.read_line(&mut first).expect("its first line");
    let addr = first
        .split("http://")
        .nth(1)
        .map(|a| a.trim_end().trim_end_matches('/').to_owned())
        .unwrap_or_else(|| panic!("no address in {first:?}"));

    let (code, head, page) = http(&addr, "GET", "/", None, None);
    assert_eq!(code, 200, "{head}");
    for id in ["id=\"state\"", "id=\"parts-on-plate\"", "id=\"picked\"", "id=\"parts-per-minute\""] {
        assert!(page.contains(id), "the page has no {id}");
    }
    assert_eq!(http(&addr, "GET", "/app.js", None, None).0, 200);
    let (code, _, live) = http(&addr, "GET", "/api/live", None, None);
    assert_eq!(code, 200);
    let live: serde_json::Value = serde_json::from_str(&live).expect("live JSON");
    assert_eq!(live["state"], "idle", "no core yet: {live}");

    // The controls need a login; a wrong password is refused and slows
    // that client's next login.
    assert_eq!(http(&addr, "POST", "/api/command/stop", None, Some("{}")).0, 401);
    let wrong = http(&addr, "POST", "/api/login", None, Some(r#"{"user":"ann","password":"wrong"}"#));
    assert_eq!(wrong.0, 401, "{wrong:?}");
    assert!(!wrong.1.to_ascii_lowercase().contains("set-cookie"), "{wrong:?}");
    assert_eq!(http(&addr, "POST", "/api/login", None, Some("not json")).0, 400);
    let asked = Instant::now();
    let (code, head, _) =
        http(&addr, "POST", "/api/login", None, Some(r#"{"user":"ann","password":"right-pass-1"}"#));
    assert_eq!(code, 200, "{head}");
    assert!(asked.elapsed() >= Duration::from_millis(450), "after a failure the next login waits");
    let cookie_line = head
        .lines()
        .find(|l| l.to_ascii_lowercase().starts_with("set-cookie:"))
        .unwrap_or_else(|| panic!("no cookie: {head}"));
    assert!(cookie_line.contains("HttpOnly") && cookie_line.contains("SameSite=Strict"), "{cookie_line}");
    let cookie =
        cookie_line.split_once(':').map(|(_, v)| v.trim()).and_then(|v| v.split(';').next()).expect("value");
    let (code, _, status) = http(&addr, "GET", "/api/status", Some(cookie), None);
    assert_eq!(code, 200);
    let status: serde_json::Value = serde_json::from_str(&status).expect("status JSON");
    assert_eq!(status["user"], "ann", "{status}");
    assert_eq!(status["counters"]["login_failures"], 1, "{status}");
    assert_eq!(status["counters"]["unauthorized"], 1, "{status}");
    assert_eq!(status["counters"]["bad_requests"], 1, "{status}");
    assert_eq!(http(&addr, "POST", "/api/command/dance", Some(cookie), Some("{}")).0, 404);
    assert_eq!(http(&addr, "POST", "/api/command/stop", Some(cookie), Some("{}")).0, 200);
    let (code, _, why) = http(&addr, "POST", "/api/recipe", Some(cookie), Some(r#"{"name":"default"}"#));
    assert_eq!(code, 422, "no cell runs: {why}");

    // SIGTERM: it stops and prints what it counted.
    // SAFETY: a plain kill(2) on the child this test started.
    unsafe { libc::kill(server.0.id() as i32, libc::SIGTERM) };
    let mut rest = String::new();
    let _ = out.read_to_string(&mut rest);
    assert!(rest.contains("upm-hmi: stopped;") && rest.contains("login_failures 1"), "{rest}");
    drop(server);
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
}
