//! The line interface as strangers use it: a robot written with Python's
//! asyncua picks from a feed rig over OPC UA (`upm run feed --robot
//! external --opcua …`), and a PLC written with pymodbus reads the
//! registers and runs the coil. Every refusal docs/line.md names is
//! provoked and checked, and the simulator's count of picks must match the
//! picks the line accepted.

mod common;

use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{add_user, free_port, json_of, upm};
use serde_json::Value;

fn client(name: &str) -> String {
    format!("{}/../line/clients/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_robot_on_opcua_and_a_plc_on_modbus_run_a_feed_rig() {
    let py_opcua = common::venv("upm-asyncua", "asyncua", "asyncua==2.1.0");
    let py_modbus = common::venv("upm-pymodbus", "pymodbus", "pymodbus==3.16.1");
    let dir = common::fresh_dir("line");
    let users = dir.join("users.toml");
    add_user(&users, "robot", "pick-pass-1");
    let text = std::fs::read_to_string(&users).expect("users file");
    assert!(!text.contains("pick-pass-1"), "the users file holds a password in clear");
    // The same name twice is refused.
    let again =
        upm().args(["users", "add"]).arg(&users).args(["robot", "--password-stdin"]).output().expect("run");
    assert!(!again.status.success());

    let (opcua, modbus) = (free_port(), free_port());
    let prefix = format!("upm_line_{}_", std::process::id());
    let rig = upm()
        .args(["run", "feed", "--duration", "150", "--quiet", "--no-record", "--robot", "external"])
        .args(["--opcua", &format!("127.0.0.1:{opcua}"), "--modbus", &format!("127.0.0.1:{modbus}")])
        .arg("--users")
        .arg(&users)
        .args(["--prefix", &prefix, "--out"])
        .arg(dir.join("run"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("upm run");
    let deadline = Instant::now() + Duration::from_secs(40);
    while TcpStream::connect(("127.0.0.1", opcua)).is_err()
        || TcpStream::connect(("127.0.0.1", modbus)).is_err()
    {
        assert!(Instant::now() < deadline, "the line's servers never came up");
        std::thread::sleep(Duration::from_millis(200));
    }

    let plc = json_of(
        &Command::new(&py_modbus)
            .arg(client("plc_modbus.py"))
            .args(["127.0.0.1", &modbus.to_string()])
            .output()
            .expect("plc"),
        "plc_modbus.py",
    );
    // A recipe of other parts: a changeover cannot switch to it.
    let bad_recipe = dir.join("bigger-discs.toml");
    let default = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../recipes/default.toml"))
        .expect("default recipe");
    std::fs::write(&bad_recipe, default.replace("radius = 0.015", "radius = 0.02")).expect("write");
    let url = format!("opc.tcp://127.0.0.1:{opcua}/");
    let robot = json_of(
        &Command::new(&py_opcua)
            .arg(client("robot_opcua.py"))
            .args([url.as_str(), "robot", "pick-pass-1", "100"])
            .arg(dir.join("run/pki"))
            .arg("two-poses")
            .arg(&bad_recipe)
            .output()
            .expect("robot"),
        "robot_opcua.py",
    );
    // `upm status` shows what the line refused, and the recipe running.
    let o = upm().args(["status", "--json", "--prefix", &prefix]).output().expect("status");
    assert!(o.status.success(), "upm status: {}", String::from_utf8_lossy(&o.stderr));
    let status: Value = serde_json::from_slice(&o.stdout).expect("status json");
    let line = &status["line"];
    assert!(line["refused"]["login_failures"].as_u64().is_some_and(|n| n >= 1), "{line}");
    assert!(line["refused"]["access_denied"].as_u64().is_some_and(|n| n >= 3), "{line}");
    assert!(line["refused"]["bad_arguments"].as_u64().is_some_and(|n| n >= 6), "{line}");
    assert!(line["refused"]["invalid_state"].as_u64().is_some_and(|n| n >= 1), "{line}");
    assert!(line["refused"]["modbus_exceptions"].as_u64().is_some_and(|n| n >= 6), "{line}");
    assert_eq!(
        (line["recipes_loaded"].as_u64(), line["recipes_refused"].as_u64()),
        (Some(1), Some(2)),
        "{line}"
    );
    // The robot's picks, and one the PLC may have acknowledged.
    assert!(line["picks_sent"].as_u64() >= robot["picks_good"].as_u64(), "{line}");
    assert!(
        status["feed"]["recipe"].as_str().is_some_and(|r| r.ends_with("/recipes/two-poses.toml")),
        "{status}"
    );
    let o = rig.wait_with_output().expect("wait");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let metrics: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run/metrics.json")).expect("metrics"))
            .expect("json");

    // The PLC: the map of docs/line.md, the coil, the refusals.
    assert_eq!(plc["state"], 1, "{plc}");
    assert_eq!(plc["poses"], 4, "{plc}");
    let p0 = &plc["pose_list"][0];
    assert_eq!(
        (p0["class"].as_u64(), p0["x_centi_mm"].as_i64(), p0["y_centi_mm"].as_i64()),
        (Some(0), Some(70_000), Some(25_000)),
        "{plc}"
    );
    assert_eq!(plc["pose_list"][3]["theta_milli_deg"], 45_000, "{plc}");
    assert_eq!(plc["run_coil"], true);
    for (k, code) in [
        ("off_map", 2),
        ("across_blocks", 2),
        ("past_poses", 2),
        ("holding_read", 2),
        ("coil_1", 2),
        ("ack_out_of_range", 3),
    ] {
        assert_eq!(plc[k], code, "{k}: {plc}");
    }
    assert!(plc["ack_not_ready"] == 6 || plc["ack_not_ready"] == "all ready", "{plc}");
    assert_eq!((plc["stop"].is_null(), plc["start"].is_null()), (true, true), "{plc}");
    assert_eq!(
        (plc["state_after_stop"].as_u64(), plc["run_coil_after_stop"].as_bool()),
        (Some(0), Some(false)),
        "{plc}"
    );
    assert_eq!(plc["state_after_start"], 1, "{plc}");
    assert_eq!(plc["malformed_closed"], serde_json::json!([true, true]), "{plc}");
    assert_eq!(plc["after_churn_state"], 1, "{plc}");

    // The robot: what it read, what it was refused, what it picked.
    assert_eq!(
        (robot["State"].as_str(), robot["Recipe"].as_str()),
        (Some("running"), Some("default")),
        "{robot}"
    );
    assert_eq!(robot["poses"].as_array().map(Vec::len), Some(4), "{robot}");
    assert_eq!(robot["poses"][2]["X"], 0.85, "{robot}");
    assert!(robot["subscription_notifications"].as_u64().is_some_and(|n| n >= 2), "{robot}");
    for k in ["anonymous_stop", "anonymous_picked", "anonymous_load"] {
        assert_eq!(robot[k], "BadUserAccessDenied", "{k}: {robot}");
    }
    assert_eq!(robot["wrong_password"], "BadUserAccessDenied", "{robot}");
    // Basic256Sha256 SignAndEncrypt: refused until the operator trusts the
    // robot's certificate, then a user session like any other.
    assert_ne!(robot["secure_untrusted"], "Good", "an untrusted certificate was served: {robot}");
    assert!(robot["secure_rejected_files"].as_u64().is_some_and(|n| n >= 1), "{robot}");
    assert_eq!(
        (robot["secure_state"].as_str(), robot["secure_resume"].as_str()),
        (Some("running"), Some("Good")),
        "{robot}"
    );
    for (k, code) in [
        ("out_of_range", "BadOutOfRange"),
        ("far_out_of_range", "BadOutOfRange"),
        ("string_pose", "BadTypeMismatch"),
        ("int64_pose", "BadTypeMismatch"),
        ("no_pose", "BadArgumentsMissing"),
        ("two_poses", "BadTooManyArguments"),
        ("stop_with_argument", "BadTooManyArguments"),
        ("not_ready_pose", "BadInvalidState"),
        ("load_unknown", "BadInvalidArgument"),
        ("load_other_parts", "BadInvalidArgument"),
        ("load_int", "BadTypeMismatch"),
        ("load_nothing", "BadArgumentsMissing"),
        ("load", "Good"),
        ("recipe_error_after_load", ""),
        ("stop", "Good"),
        ("start", "Good"),
        ("resume", "Good"),
    ] {
        assert_eq!(robot[k], code, "{k}: {robot}");
    }
    assert_eq!(
        (robot["state_after_stop"].as_str(), robot["state_after_start"].as_str()),
        (Some("idle"), Some("running")),
        "{robot}"
    );
    // A changeover: refused with the reason and the running recipe kept,
    // then done; the poses move and the robot goes on picking.
    let error = |k: &str| robot[k].as_str().unwrap_or_default().to_owned();
    assert!(error("load_unknown_error").contains("no-such-recipe"), "{robot}");
    assert!(error("load_other_parts_error").contains("class[0]"), "{robot}");
    assert_eq!(
        (robot["recipe_after_refusals"].as_str(), robot["recipe_after_load"].as_str()),
        (Some("default"), Some("two-poses")),
        "{robot}"
    );
    assert_eq!(robot["pose_count_after_load"], 2, "{robot}");
    assert_eq!(robot["pose0_after_load"], serde_json::json!([0.7, 0.15]), "{robot}");
    assert_eq!(robot["pose3_ready_after_load"], false, "a pose the recipe no longer has: {robot}");
    assert_eq!(
        (robot["Line.RecipesLoaded"].as_u64(), robot["Line.RecipesRefused"].as_u64()),
        (Some(1), Some(2))
    );
    assert!(robot["picks_other"].as_object().is_some_and(|m| m.is_empty()), "{robot}");
    let before = robot["picks_before_changeover"].as_u64().unwrap_or(0);
    let good = robot["picks_good"].as_u64().unwrap_or(0);
    assert!(before >= 1 && good > before, "picks before and after the changeover: {robot}");
    assert!(robot["Line.LoginFailures"].as_u64().is_some_and(|n| n >= 1), "{robot}");
    assert!(robot["Line.AccessDenied"].as_u64().is_some_and(|n| n >= 2), "{robot}");
    // Every pick the line accepted, the simulator carried out; it picked
    // nothing by itself.
    assert_eq!(metrics["feed"]["picked"].as_u64(), Some(good), "accepted {good}: {}", metrics["feed"]);
    assert_eq!(metrics["feed"]["lost"], 0);
    assert!(metrics["processes"]["line"].as_u64().is_some(), "{}", metrics["processes"]);
    let _ = std::fs::remove_dir_all(&dir);
}
