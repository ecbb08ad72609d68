//! The flight recorder across the process boundary: a real multi-process
//! run is recorded by upm-recorder and `upm replay` reproduces every
//! schedule bit for bit; a recording with one schedule changed by one ulp
//! is caught with the field named; messages the core rejects are recorded
//! with the core's reason and the replay rejects them the same way; and a
//! truncated, foreign or other-version file is refused in one line.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use ipc_types::{
    CoreCommand, CoreState, ExplicitSchedule, ForceRequest, FrameHeader, PartStates, Rejection, Schedule,
    Telemetry, WireMessage, monotonic_now_ns, service_names,
};
use upm_commands::recording::Recording;
use upm_recorder::{LogOptions, PlateView, RigLog};

const UPM: &str = env!("CARGO_BIN_EXE_upm");

/// One rig at a time: on two CPUs, parallel rigs would starve each other.
static RIG: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_rig() -> std::sync::MutexGuard<'static, ()> {
    RIG.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn dir(tag: &str) -> PathBuf {
    let d =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("record_replay_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("test dir");
    d
}

fn replay(file: &Path) -> Output {
    Command::new(UPM).arg("replay").arg(file).output().expect("upm replay")
}

/// `upm replay file` refuses it (exit 2) with a line containing `want`;
/// returns what it said.
fn refused(file: &Path, want: &str) -> String {
    let o = replay(file);
    let said = text(&o);
    assert_eq!(o.status.code(), Some(2), "{}: {said}", file.display());
    assert!(said.contains(want), "{}: {said}", file.display());
    said
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// `rec` rewritten message by message, `change` applied to each schedule
/// (with its index among the schedules).
fn rewrite(rec: &Recording, to: &Path, mut change: impl FnMut(usize, &mut Schedule)) {
    let mut log = RigLog::open(&LogOptions {
        plate: PlateView::default(),
        mcap: Some(to.to_path_buf()),
        serve_port: None,
        config_text: rec.config_text.clone(),
        info: rec.run.clone(),
        segment: None,
    })
    .expect("open the copy");
    let mut schedules = 0;
    rec.for_each_raw(|i, m| {
        macro_rules! copy {
            ($t:ty) => {{
                let v: $t = rec.decode(i, m)?;
                log.log(<$t>::SERVICE, &v, &[], m.log_time);
            }};
        }
        match m.topic {
            service_names::PART_STATES => copy!(PartStates),
            service_names::FORCE_REQUEST => copy!(ForceRequest),
            service_names::EXPLICIT_SCHEDULE => copy!(ExplicitSchedule),
            service_names::CORE_COMMAND => copy!(CoreCommand),
            service_names::TELEMETRY => copy!(Telemetry),
            service_names::REJECTION => copy!(Rejection),
            service_names::CAMERA_FRAME => copy!(FrameHeader),
            service_names::SCHEDULE => {
                let mut s: Schedule = rec.decode(i, m)?;
                change(schedules, &mut s);
                schedules += 1;
                log.log(Schedule::SERVICE, &s, &[], m.log_time);
            }
            _ => {}
        }
        Ok(())
    })
    .expect("read the recording");
    log.finish().expect("close the copy");
}

#[test]
fn a_real_run_is_replayed_bit_for_bit_and_a_one_ulp_change_is_caught() {
    let _rig = one_rig();
    let out = dir("run");
    let prefix = common::unique_prefix("rec");
    let run = Command::new(UPM)
        .args(["run", "sort", "--duration", "6", "--quiet", "--prefix", &prefix, "--out"])
        .arg(&out)
        .output()
        .expect("upm run");
    common::remove_prefix(&prefix);
    assert!(run.status.success(), "upm run failed: {}", text(&run));
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
            .expect("json");
    let file = out.join("run.mcap");
    assert_eq!(metrics["recording"]["file"], file.display().to_string(), "{}", metrics["recording"]);
    assert_eq!(metrics["recording"]["recorder_exit_ok"], true);

    let o = replay(&file);
    let said = text(&o);
    assert_eq!(o.status.code(), Some(0), "{said}");
    let schedules: usize = said
        .strip_prefix("identical: ")
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("unexpected verdict: {said}"));
    assert!(schedules >= 50, "a 6 s sort solves at the frame rate: {said}");
    eprintln!("{said}");

    // The same recording with the 10th schedule's first k one ulp larger.
    let rec = Recording::open(&file).expect("open");
    let changed = out.join("changed.mcap");
    let mut seq = 0;
    rewrite(&rec, &changed, |i, s| {
        if i == 9 {
            s.slots_mut()[0].k = f64::from_bits(s.slots()[0].k.to_bits() + 1);
            seq = s.seq;
        }
    });
    let o = replay(&changed);
    let said = text(&o);
    assert_eq!(o.status.code(), Some(1), "{said}");
    assert!(said.starts_with(&format!("diverged: schedule seq {seq}: slots[0].k: recorded ")), "{said}");
    assert_eq!(said.lines().count(), 1, "{said}");

    // A copy without changes replays identically: the copy itself is exact.
    let same = out.join("same.mcap");
    rewrite(&rec, &same, |_, _| {});
    assert_eq!(replay(&same).status.code(), Some(0));
    let _ = std::fs::remove_dir_all(&out);
}

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn stop(mut c: Killed) -> std::process::ExitStatus {
    // SIGINT: the recorder closes its file as on Ctrl-C.
    let _ = Command::new("kill").args(["-INT", &c.0.id().to_string()]).status();
    let status = c.0.wait().expect("wait");
    std::mem::forget(c);
    status
}

/// upm-core on `prefix` with the default config written to `config`, up.
fn start_core(prefix: &str, config: &Path) -> Killed {
    std::fs::write(config, toml::to_string(&upm_commands::config::Config::default()).expect("toml"))
        .expect("write");
    let core = Killed(
        Command::new(common::core_exe())
            .args(["--prefix", prefix, "--duration", "60", "--config"])
            .arg(config)
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn upm-core"),
    );
    let up = Instant::now();
    while upm_commands::status::read_telemetry(prefix, Duration::from_secs(1))
        .map_or(true, |t| t.core_state() != Some(CoreState::Idle))
    {
        assert!(up.elapsed() < Duration::from_secs(20), "core did not come up");
        std::thread::sleep(Duration::from_millis(20));
    }
    core
}

/// `upm recorder` on `prefix` into `file`, listening.
fn start_recorder(prefix: &str, config: &Path, file: &Path) -> Killed {
    let recorder = Killed(
        Command::new(UPM)
            .args(["recorder", "--prefix", prefix, "--config"])
            .arg(config)
            .arg("--out")
            .arg(file)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn upm recorder"),
    );
    let up = Instant::now();
    while !file.exists() {
        assert!(up.elapsed() < Duration::from_secs(20), "recorder did not start");
        std::thread::sleep(Duration::from_millis(10));
    }
    recorder
}

/// The §3.1 feed on `prefix` every 10 ms until the flag is set.
fn start_feed(prefix: &str) -> (std::sync::Arc<std::sync::atomic::AtomicBool>, std::thread::JoinHandle<()>) {
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let (p, s) = (prefix.to_owned(), stop.clone());
    (stop, std::thread::spawn(move || common::feed(&p, Duration::from_millis(10), &s)))
}

#[test]
fn a_recording_started_mid_run_is_refused_not_called_divergent() {
    let _rig = one_rig();
    let out = dir("midrun");
    let prefix = common::unique_prefix("recmid");
    let config = out.join("rig.toml");
    let core = start_core(&prefix, &config);
    let (stop_feed, feeder) = start_feed(&prefix);
    std::thread::sleep(Duration::from_millis(700));
    let file = out.join("mid.mcap");
    let recorder = start_recorder(&prefix, &config, &file);
    std::thread::sleep(Duration::from_millis(700));
    stop_feed.store(true, std::sync::atomic::Ordering::Relaxed);
    feeder.join().expect("feeder");
    std::thread::sleep(Duration::from_millis(200));
    assert!(stop(recorder).success(), "recorder exit");
    drop(core);
    common::remove_prefix(&prefix);
    refused(&file, "the recording started after the core had played ");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn rejected_messages_are_recorded_with_the_reason_and_replayed_alike() {
    let _rig = one_rig();
    let out = dir("reject");
    let prefix = common::unique_prefix("recrej");
    let config = out.join("rig.toml");
    let core = start_core(&prefix, &config);
    let file = out.join("rig.mcap");
    let recorder = start_recorder(&prefix, &config, &file);

    let node = common::plain_node(&prefix);
    let parts = ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES).expect("pub");
    let requests =
        ipc_types::ports::publisher::<ForceRequest>(&node, service_names::FORCE_REQUEST).expect("pub");
    let mut wake = ipc_types::wake_event::WakeNotifier::new(&node, ipc_types::wake_event::WakeEvent::Inbox)
        .expect("wake");
    // Part states alone first: a request must never reach the core before
    // its first part states have (that would be one more rejection).
    for _ in 0..5 {
        parts.send_copy(common::part_states(1, monotonic_now_ns(), &common::PAPER_PARTS)).expect("send");
        wake.notify();
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut bad = 0;
    for seq in 1..=40u64 {
        let now = monotonic_now_ns();
        // Every 10th round from the 7th, part 2 has left the plate but the
        // request still names it: rejected against part states no schedule
        // names, which the replay must feed from the rejection.
        let seen = if seq % 10 == 7 { &common::PAPER_PARTS[..1] } else { &common::PAPER_PARTS[..] };
        parts.send_copy(common::part_states(seq, now, seen)).expect("send");
        wake.notify();
        let mut r = common::request(seq, now, &common::PAPER_PARTS, 1.0);
        match seq % 10 {
            3 => r.protocol_version = 2,
            5 => r.entries_mut()[0].fx = f64::NAN,
            _ => {}
        }
        bad += u64::from(matches!(seq % 10, 3 | 5 | 7));
        requests.send_copy(r).expect("send");
        wake.notify();
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    assert!(stop(recorder).success(), "recorder exit");
    drop(core);
    drop((parts, requests, wake, node));
    common::remove_prefix(&prefix);

    let rec = Recording::open(&file).expect("open");
    let mut reasons = Vec::new();
    rec.for_each_raw(|i, m| {
        if m.topic == service_names::REJECTION {
            let r: Rejection = rec.decode(i, m)?;
            reasons.push(r.reason().map(|r| r.as_str()).unwrap_or("?"));
        }
        Ok(())
    })
    .expect("read");
    assert_eq!(reasons.len() as u64, bad, "{reasons:?}");
    for want in ["wrong_protocol_version", "non_finite", "unknown_part"] {
        assert!(reasons.contains(&want), "{want} in {reasons:?}");
    }
    let o = replay(&file);
    let said = text(&o);
    assert_eq!(o.status.code(), Some(0), "{said}");
    assert!(said.contains(&format!(" and {bad} rejections reproduced")), "{said}");
    assert_eq!(
        said.matches("\n  recorded: force_request seq ").count() as u64,
        bad,
        "each rejection shown: {said}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_damaged_foreign_or_other_version_file_is_refused_in_one_line() {
    let out = dir("bad");
    let good = out.join("good.mcap");
    let mut log = RigLog::open(&LogOptions {
        mcap: Some(good.clone()),
        config_text: Some(String::new()),
        ..LogOptions::default()
    })
    .expect("open");
    for seq in 1..2000u64 {
        log.log(PartStates::SERVICE, &common::part_states(seq, seq, &common::PAPER_PARTS), &[], seq);
    }
    log.finish().expect("close");
    let bytes = std::fs::read(&good).expect("read");

    let cases: [(&str, Vec<u8>, &str); 3] = [
        ("cut.mcap", bytes[..bytes.len() / 2].to_vec(), "truncated or corrupt"),
        ("text.mcap", b"[plate]\n".to_vec(), "not an MCAP file"),
        ("empty.mcap", Vec::new(), "not an MCAP file"),
    ];
    for (name, content, want) in cases {
        let f = out.join(name);
        std::fs::write(&f, content).expect("write");
        let said = refused(&f, want);
        assert!(said.starts_with("upm: error: "), "{name}: {said}");
        assert_eq!(said.trim_end().lines().count(), 1, "{name}: {said}");
    }

    // An MCAP file from elsewhere, and one claiming another protocol version.
    let v3 = format!(
        "recorded with protocol version 3; this upm speaks protocol version {}",
        ipc_types::PROTOCOL_VERSION
    );
    for (name, metadata, want) in
        [("foreign.mcap", None, "not a UPM recording"), ("v3.mcap", Some("3"), v3.as_str())]
    {
        let f = out.join(name);
        let mut w = mcap::Writer::new(std::io::BufWriter::new(std::fs::File::create(&f).expect("create")))
            .expect("writer");
        if let Some(v) = metadata {
            let m = mcap::records::Metadata {
                name: upm_recorder::RUN_METADATA.into(),
                metadata: [("protocol_version".to_owned(), v.to_owned())].into(),
            };
            w.write_metadata(&m).expect("metadata");
        }
        w.finish().expect("finish");
        drop(w);
        refused(&f, want);
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_stalled_recorder_loses_for_itself_and_counts_it_while_the_core_goes_on() {
    let _rig = one_rig();
    let out = dir("stall");
    let prefix = common::unique_prefix("recstall");
    let config = out.join("rig.toml");
    let core = start_core(&prefix, &config);
    let file = out.join("stall.mcap");
    let recorder = start_recorder(&prefix, &config, &file);
    let node = common::plain_node(&prefix);
    let schedules = ipc_types::ports::subscriber::<Schedule>(&node, service_names::SCHEDULE).expect("sub");
    let (stop_feed, feeder) = start_feed(&prefix);
    std::thread::sleep(Duration::from_millis(500));
    let pid = recorder.0.id().to_string();
    assert!(Command::new("kill").args(["-STOP", &pid]).status().expect("kill").success());
    // While the recorder is stopped, the core goes on answering.
    while schedules.receive().expect("receive").is_some() {}
    let stalled = Instant::now();
    let mut answered = 0;
    while stalled.elapsed() < Duration::from_millis(1500) {
        while schedules.receive().expect("receive").is_some() {
            answered += 1;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(Command::new("kill").args(["-CONT", &pid]).status().expect("kill").success());
    std::thread::sleep(Duration::from_millis(300));
    stop_feed.store(true, std::sync::atomic::Ordering::Relaxed);
    feeder.join().expect("feeder");
    assert!(answered >= 50, "the core answered {answered} requests in 1.5 s while the recorder was stopped");
    let t = upm_commands::status::read_telemetry(&prefix, Duration::from_secs(1)).expect("telemetry");
    assert_eq!(t.counters.hold_events, 0, "the core never held");
    assert!(stop(recorder).success(), "recorder exit");
    drop(core);
    drop((schedules, node));
    common::remove_prefix(&prefix);

    let rec = Recording::open(&file).expect("a stalled recorder still closes its file");
    let lost = |topic: &str| rec.counts.get(&format!("lost {topic}")).and_then(|v| v.parse::<u64>().ok());
    let parts_lost = lost(service_names::PART_STATES).expect("counted");
    let requests_lost = lost(service_names::FORCE_REQUEST).expect("counted");
    // 1.5 s at 100 Hz, 8 kept per subscriber: about 140 of each lost.
    assert!(
        parts_lost >= 100 && requests_lost >= 100,
        "lost {parts_lost} part states, {requests_lost} requests"
    );
    assert_eq!(
        rec.lost_total(),
        rec.counts
            .iter()
            .filter(|(k, _)| k.starts_with("lost "))
            .map(|(_, v)| v.parse::<u64>().unwrap_or(0))
            .sum::<u64>()
    );
    // What was lost cannot be replayed, and the replay says why.
    refused(&file, "cannot replay bit for bit: the recorder lost core inputs (");
    let _ = std::fs::remove_dir_all(&out);
}

/// A long recording goes on in segments: each file is a recording of its
/// own (run metadata with its number, the rig's TOML, its counts so far),
/// and every message is in exactly one of them, in order.
#[test]
fn segments_split_a_recording_and_lose_nothing() {
    let out = dir("segments");
    let first = out.join("seg.mcap");
    let mut log = RigLog::open(&LogOptions {
        mcap: Some(first.clone()),
        config_text: Some("[plate]\n".into()),
        segment: Some(Duration::from_nanos(1000)),
        ..LogOptions::default()
    })
    .expect("open");
    let mut files = vec![first.clone()];
    for seq in 1..=2500u64 {
        let t = 1_000_000 + seq * 10;
        log.log(PartStates::SERVICE, &common::part_states(seq, seq, &common::PAPER_PARTS), &[], t);
        if log.segment_due(t) {
            log.next_segment(t).expect("next segment");
            files.push(log.current_file().expect("a file"));
        }
    }
    log.finish().expect("finish");
    assert!(files.len() >= 20, "{} segments", files.len());
    assert_eq!(files[1], out.join("seg.001.mcap"));
    let mut seen = Vec::new();
    for (n, f) in files.iter().enumerate() {
        let rec = Recording::open(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        assert_eq!(rec.run.get("segment"), Some(&n.to_string()), "{}", f.display());
        assert_eq!(rec.config_text.as_deref(), Some("[plate]\n"));
        let received: u64 = rec.counts[&format!("received {}", PartStates::SERVICE)].parse().expect("count");
        rec.for_each_raw(|_, m| {
            if m.topic == PartStates::SERVICE {
                seen.push(m.log_time);
            }
            Ok(())
        })
        .expect("read");
        assert_eq!(received, seen.len() as u64, "counts so far in {}", f.display());
    }
    let sent: Vec<u64> = (1..=2500u64).map(|seq| 1_000_000 + seq * 10).collect();
    assert_eq!(seen, sent);
    // What metrics.json says of them.
    let summary = upm_commands::recording::summary_json(&first, true);
    let listed: Vec<PathBuf> = summary["segments"]
        .as_array()
        .expect("segments")
        .iter()
        .filter_map(|f| f.as_str().map(PathBuf::from))
        .collect();
    assert_eq!(listed, files, "{summary}");
    let bytes: u64 = files.iter().map(|f| std::fs::metadata(f).map_or(0, |m| m.len())).sum();
    assert_eq!(summary["bytes"], bytes, "{summary}");
    assert_eq!(summary["lost"], 0, "{summary}");
    assert!(summary["messages"].as_u64().is_some_and(|n| n >= 2500), "{summary}");
    let _ = std::fs::remove_dir_all(&out);
}
