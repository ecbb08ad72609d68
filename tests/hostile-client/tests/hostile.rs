//! A hostile client against a running upm-core, built from `ipc-types` and
//! iceoryx2 alone (see README.md). Every message is followed by a good
//! request that must be answered with a Schedule carrying its `seq`.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::{Pub, Sub, config_with_prefix};
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{
    CoreCommand, CoreState, ExplicitSchedule, ExplicitSlot, ForceEntry, ForceRequest, HealthSource,
    MAX_PARTS, MAX_SHAPE_VERTICES, MAX_SLOTS, PartState, PartStates, RejectReason, RejectedKind, Rejection,
    Schedule, Telemetry, monotonic_now_ns, service_names,
};

/// The workspace's upm-core (next to this test's own build), or `UPM_CORE_EXE`.
fn core_exe() -> PathBuf {
    if let Some(p) = std::env::var_os("UPM_CORE_EXE") {
        return PathBuf::from(p);
    }
    let me = std::env::current_exe().expect("own path");
    let dir = me.parent().and_then(|d| d.parent()).expect("target dir");
    let exe = dir.join("upm-core");
    assert!(exe.exists(), "{} is missing: run `cargo build --release --bin upm-core` first", exe.display());
    exe
}

struct Core {
    child: Child,
    prefix: String,
}

impl Core {
    fn start(prefix: &str) -> Self {
        let child = Command::new(core_exe()).args(["--prefix", prefix]).spawn().expect("starting upm-core");
        Self { child, prefix: prefix.to_owned() }
    }

    fn alive(&mut self) -> bool {
        self.child.try_wait().expect("wait").is_none()
    }
}

impl Drop for Core {
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-INT", &self.child.id().to_string()]).status();
        let start = Instant::now();
        while self.alive() && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        ipc_types::rig_node::remove_prefix_segment(&self.prefix);
    }
}

fn publisher<T: core::fmt::Debug + ZeroCopySend>(node: &Node<ipc::Service>, service: &'static str) -> Pub<T> {
    ipc_types::ports::publisher::<T>(node, service).expect("publisher")
}

fn subscriber<T: core::fmt::Debug + ZeroCopySend>(
    node: &Node<ipc::Service>,
    service: &'static str,
) -> Sub<T> {
    ipc_types::ports::subscriber::<T>(node, service).expect("subscriber")
}

struct Client {
    parts: Pub<PartStates>,
    requests: Pub<ForceRequest>,
    explicit: Pub<ExplicitSchedule>,
    commands: Pub<CoreCommand>,
    notifier: WakeNotifier,
    schedules: Sub<Schedule>,
    telemetry: Sub<Telemetry>,
    rejections: Sub<Rejection>,
    answered: HashSet<u64>,
    /// Request seq → `parts_seq` of the part states its schedule was solved against.
    solved_against: HashMap<u64, u64>,
    /// Every rejection the core sent back, in order.
    refusals: Vec<Rejection>,
    /// What was sent last: its kind and seq (a refusal must name them).
    last_sent: (RejectedKind, u64),
    newest_telemetry: Option<Telemetry>,
    seq: u64,
    /// Stamps of the newest good part states and request the core took.
    parts_stamp: u64,
    request_stamp: u64,
    _node: Node<ipc::Service>,
    /// Last: fields drop in order, and the core's drop removes the prefix's
    /// files, which the ports and node above would otherwise outlive.
    core: Core,
}

const PAPER: [(u32, [f64; 2]); 2] = [(1, [0.5, 0.0]), (2, [-0.75, 0.25])];

fn good_parts(seq: u64, stamp_ns: u64) -> PartStates {
    let mut m = PartStates::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    for (id, [x, y]) in PAPER {
        m.push(PartState::new(id, 0, 0, [x, y, 0.0], [0.0; 3])).expect("fits");
    }
    m
}

/// `n` distinct parts spread over the plate, ids 1..=n.
fn many_parts(n: u32, seq: u64, stamp_ns: u64) -> PartStates {
    let mut m = PartStates::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    for i in 0..n.min(MAX_PARTS as u32) {
        let (x, y) = (-0.875 + f64::from(i % 8) * 0.25, -0.35 + f64::from(i / 8) * 0.1);
        m.push(PartState::new(i + 1, 0, 0, [x, y, 0.0], [0.0; 3])).expect("fits");
    }
    m.count = n;
    m
}

fn good_request(seq: u64, stamp_ns: u64) -> ForceRequest {
    let mut r = ForceRequest::new();
    r.seq = seq;
    r.stamp_ns = stamp_ns;
    r.deadline_ns = stamp_ns + 1_000_000_000;
    r.push(ForceEntry::force(1, [0.01, 0.01])).expect("fits");
    r.push(ForceEntry::force(2, [-0.01, 0.0])).expect("fits");
    r
}

fn explicit(n: u32, seq: u64, stamp_ns: u64) -> ExplicitSchedule {
    let mut e = ExplicitSchedule::new();
    e.seq = seq;
    e.stamp_ns = stamp_ns;
    for i in 0..n.min(MAX_SLOTS as u32) {
        e.slots[i as usize] = ExplicitSlot::new(i % 4, if i % 2 == 0 { 0.3 } else { -0.3 });
    }
    e.count = n;
    e
}

fn rejected(t: &Telemetry) -> u64 {
    t.rejected_by_reason.iter().sum()
}

impl Client {
    fn connect(prefix: &str) -> Self {
        let core = Core::start(prefix);
        let config = config_with_prefix(prefix).expect("prefix");
        let node = NodeBuilder::new()
            .config(&config)
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .expect("node");
        let mut c = Self {
            parts: publisher(&node, service_names::PART_STATES),
            requests: publisher(&node, service_names::FORCE_REQUEST),
            explicit: publisher(&node, service_names::EXPLICIT_SCHEDULE),
            commands: publisher(&node, service_names::CORE_COMMAND),
            notifier: WakeNotifier::new(&node, WakeEvent::Inbox).expect("notifier"),
            schedules: subscriber(&node, service_names::SCHEDULE),
            telemetry: subscriber(&node, service_names::TELEMETRY),
            rejections: subscriber(&node, service_names::REJECTION),
            answered: HashSet::new(),
            solved_against: HashMap::new(),
            refusals: Vec::new(),
            last_sent: (RejectedKind::PartStates, 0),
            newest_telemetry: None,
            seq: 0,
            parts_stamp: 0,
            request_stamp: 0,
            core,
            _node: node,
        };
        let start = Instant::now();
        while c.poll_telemetry().is_none() {
            assert!(c.core.alive(), "upm-core exited at start-up");
            assert!(start.elapsed() < Duration::from_secs(30), "upm-core sent no telemetry");
            std::thread::sleep(Duration::from_millis(20));
        }
        // The core's subscribers connect to our publishers on their next look.
        std::thread::sleep(Duration::from_millis(300));
        c
    }

    fn next_seq(&mut self) -> u64 {
        self.seq += 1;
        self.seq
    }

    fn send_parts(&mut self, m: PartStates) {
        self.last_sent = (RejectedKind::PartStates, m.seq);
        self.parts.send_copy(m).expect("send");
        self.notifier.notify();
    }

    fn send_request(&mut self, m: ForceRequest) {
        self.last_sent = (RejectedKind::ForceRequest, m.seq);
        self.requests.send_copy(m).expect("send");
        self.notifier.notify();
    }

    fn send_explicit(&mut self, m: ExplicitSchedule) {
        self.last_sent = (RejectedKind::ExplicitSchedule, m.seq);
        self.explicit.send_copy(m).expect("send");
        self.notifier.notify();
    }

    fn send_command(&mut self, m: CoreCommand) {
        self.last_sent = (RejectedKind::CoreCommand, m.seq);
        self.commands.send_copy(m).expect("send");
        self.notifier.notify();
    }

    fn poll(&mut self) {
        while let Some(s) = self.schedules.receive().expect("receive schedule") {
            self.answered.insert(s.payload().seq);
            self.solved_against.insert(s.payload().seq, s.payload().parts_seq);
        }
        while let Some(r) = self.rejections.receive().expect("receive rejection") {
            self.refusals.push(*r.payload());
        }
        self.poll_telemetry();
    }

    fn poll_telemetry(&mut self) -> Option<Telemetry> {
        while let Some(t) = self.telemetry.receive().expect("receive telemetry") {
            self.newest_telemetry = Some(*t.payload());
        }
        self.newest_telemetry
    }

    /// Telemetry published after this call.
    fn fresh_telemetry(&mut self) -> Telemetry {
        let after = monotonic_now_ns();
        let start = Instant::now();
        loop {
            self.poll();
            if let Some(t) = self.newest_telemetry.filter(|t| t.stamp_ns > after) {
                return t;
            }
            assert!(self.core.alive(), "upm-core died");
            assert!(start.elapsed() < Duration::from_secs(5), "no fresh telemetry");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Wait up to 3 s for `done`; false on timeout.
    fn wait_for(&mut self, mut done: impl FnMut(&mut Self) -> bool) -> bool {
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(3) {
            self.poll();
            if done(self) {
                return true;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        false
    }

    /// Good part states and a good request; the request must be answered.
    fn round_trip(&mut self, after: &str) {
        let seq = self.next_seq();
        self.parts_stamp = monotonic_now_ns();
        self.send_parts(good_parts(seq, self.parts_stamp));
        self.request_stamp = monotonic_now_ns();
        self.send_request(good_request(seq, self.request_stamp));
        let answered = self.wait_for(|c| c.answered.contains(&seq));
        assert!(self.core.alive(), "upm-core died after {after}");
        assert!(answered, "a good request (seq {seq}) sent after {after} was not answered");
    }

    /// Send one hostile message; it must be rejected under `reason` (or, for
    /// `None`, taken without any rejection), and the core must answer the
    /// next good request.
    fn expect(&mut self, label: &str, reason: Option<RejectReason>, send: impl FnOnce(&mut Self)) {
        let before = self.fresh_telemetry();
        send(self);
        match reason {
            Some(r) => {
                let counted = self.wait_for(|c| {
                    c.newest_telemetry.is_some_and(|t| {
                        t.rejected_by_reason[r.index()] > before.rejected_by_reason[r.index()]
                    })
                });
                let t = self.fresh_telemetry();
                assert!(
                    counted,
                    "{label}: not counted as {r} (rejections {} → {})",
                    rejected(&before),
                    rejected(&t)
                );
                // ... and answered to the sender: its kind, its seq, why.
                let (kind, seq) = self.last_sent;
                let told = self.wait_for(|c| {
                    c.refusals.iter().any(|a| a.kind() == Some(kind) && a.seq == seq && a.reason() == Some(r))
                });
                assert!(
                    told,
                    "{label}: no Rejection {r} for {kind:?} seq {seq} on {}",
                    service_names::REJECTION
                );
                let a = self.refusals.iter().rev().find(|a| a.seq == seq).expect("found above");
                assert!(!a.detail_str().is_empty(), "{label}: a rejection without a reason text");
            }
            None => {
                let t = self.fresh_telemetry();
                assert_eq!(rejected(&t), rejected(&before), "{label}: rejected, expected it to be taken");
            }
        }
        self.round_trip(label);
    }

    /// Good part states changed by `shape` must be taken, and a request with
    /// their seq solved against them and played.
    fn taken_and_solved(&mut self, label: &str, shape: impl FnOnce(&mut PartStates)) {
        let before = self.fresh_telemetry();
        let seq = self.next_seq();
        let mut m = good_parts(seq, monotonic_now_ns());
        shape(&mut m);
        self.send_parts(m);
        self.send_request(good_request(seq, monotonic_now_ns()));
        let played = self.wait_for(|c| c.answered.contains(&seq));
        let t = self.fresh_telemetry();
        assert!(self.core.alive(), "upm-core died after {label}");
        assert_eq!(rejected(&t), rejected(&before), "{label}: rejected, expected it to be taken");
        assert!(played, "{label}: the request against it was not played");
        assert_eq!(self.solved_against.get(&seq), Some(&seq), "{label}: solved against other part states");
        self.round_trip(label);
    }

    /// Send one message that must be played (a Schedule with its seq) or
    /// rejected and counted: never silence.
    fn played_or_rejected(&mut self, label: &str, seq: u64, send: impl FnOnce(&mut Self)) -> bool {
        let before = self.fresh_telemetry();
        send(self);
        let mut played = false;
        let settled = self.wait_for(|c| {
            played = c.answered.contains(&seq);
            played || c.newest_telemetry.is_some_and(|t| rejected(&t) > rejected(&before))
        });
        assert!(settled, "{label}: neither played nor rejected");
        self.round_trip(label);
        played
    }
}

fn unique_prefix(tag: &str) -> String {
    ipc_types::rig_node::unique_prefix(&format!("upmh_{tag}"))
}

const SQUARE: [[f64; 2]; 4] = [[0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01], [0.01, -0.01]];
/// Clockwise.
const TRIANGLE: [[f64; 2]; 3] = [[0.02, 0.0], [-0.01, -0.015], [-0.01, 0.015]];

fn octagon(radius: f64) -> [[f64; 2]; MAX_SHAPE_VERTICES] {
    core::array::from_fn(|k| {
        let a = core::f64::consts::TAU * k as f64 / MAX_SHAPE_VERTICES as f64;
        [radius * a.cos(), radius * a.sin()]
    })
}

/// Part `i` of good part states as a polygon with `vertices`.
fn with_polygon(m: &mut PartStates, i: usize, vertices: &[[f64; 2]]) {
    let p = &mut m.parts_mut()[i];
    *p = p.with_polygon(vertices).expect("at most 8 vertices");
}

/// A named way to spoil a good message, and the reason it must be rejected for.
type Spoil<T> = (&'static str, RejectReason, fn(&mut T, u64));

const FLOATS: [f64; 5] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e308, -1e308];

#[test]
fn every_value_the_types_allow_is_played_or_rejected_and_counted() {
    let mut c = Client::connect(&unique_prefix("values"));
    let r = RejectReason::NoPartStates;
    c.expect("a request before any part states", Some(r), |c| {
        let (seq, now) = (c.next_seq(), monotonic_now_ns());
        c.send_request(good_request(seq, now));
    });

    // --- PartStates
    for n in [0u32, 1, 2, 63, 64] {
        c.expect(&format!("part_states.count {n}"), None, |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            c.send_parts(many_parts(n, seq, now));
        });
    }
    for n in [65u32, 192, 1000, u32::MAX] {
        c.expect(&format!("part_states.count {n}"), Some(RejectReason::CountExceedsCapacity), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            c.send_parts(many_parts(n, seq, now));
        });
    }
    for field in 0..6 {
        for v in FLOATS {
            // Positions beyond the plate are off it; other huge but finite
            // values are legal (nothing the core computes uses them).
            let reason = if !v.is_finite() {
                Some(RejectReason::NonFinite)
            } else if field < 2 {
                Some(RejectReason::OffPlate)
            } else {
                None
            };
            c.expect(&format!("part_states field {field} = {v}"), reason, |c| {
                let (seq, now) = (c.next_seq(), monotonic_now_ns());
                let mut m = good_parts(seq, now);
                let p = &mut m.parts_mut()[0];
                *[&mut p.x, &mut p.y, &mut p.theta, &mut p.vx, &mut p.vy, &mut p.omega][field] = v;
                c.send_parts(m);
            });
        }
    }
    let cases: [Spoil<PartStates>; 5] = [
        ("part_states wrong version", RejectReason::WrongProtocolVersion, |m, _| m.protocol_version = 1),
        ("part_states zero stamp", RejectReason::Stale, |m, _| m.stamp_ns = 0),
        ("part_states stale stamp", RejectReason::Stale, |m, now| m.stamp_ns = now - 10_000_000_000),
        ("part_states future stamp", RejectReason::StampFromFuture, |m, now| {
            m.stamp_ns = now + 10_000_000_000
        }),
        ("part_states duplicate ids", RejectReason::DuplicateId, |m, _| {
            m.parts_mut()[1].id = m.parts()[0].id
        }),
    ];
    for (label, reason, spoil) in cases {
        c.expect(label, Some(reason), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut m = good_parts(seq, now);
            spoil(&mut m, now);
            c.send_parts(m);
        });
    }

    // --- PartState outlines: good ones are taken and solved against.
    c.taken_and_solved("a disc and a square", |m| {
        m.parts_mut()[0] = m.parts[0].with_disc(0.015);
        with_polygon(m, 1, &SQUARE);
    });
    c.taken_and_solved("a clockwise triangle and an octagon, turned", |m| {
        with_polygon(m, 0, &TRIANGLE);
        with_polygon(m, 1, &octagon(0.03));
        m.parts_mut()[0].theta = 2.0;
        m.parts_mut()[1].theta = -7.0;
    });
    c.taken_and_solved("a point with garbage in its unused outline fields", |m| {
        let p = &mut m.parts_mut()[0];
        (p.radius, p.vertex_count) = (f64::NAN, u32::MAX);
        p.vertices = [[f64::NAN, f64::NEG_INFINITY]; MAX_SHAPE_VERTICES];
    });
    c.taken_and_solved("a disc with garbage vertices, a triangle with garbage after it", |m| {
        let p = &mut m.parts_mut()[0];
        p.vertices = [[1e308, f64::NAN]; MAX_SHAPE_VERTICES];
        p.vertex_count = u32::MAX;
        *p = p.with_disc(0.02);
        let q = &mut m.parts_mut()[1];
        q.vertices = [[f64::INFINITY; 2]; MAX_SHAPE_VERTICES];
        q.radius = f64::NAN;
        with_polygon(m, 1, &TRIANGLE);
    });
    c.taken_and_solved("64 octagons", |m| {
        *m = many_parts(64, m.seq, m.stamp_ns);
        for i in 0..MAX_PARTS {
            with_polygon(m, i, &octagon(0.02));
        }
    });
    // As large as allowed (the plate's larger half extent, 1 m): solved or
    // refused and counted, never silence.
    for (label, disc) in [("a disc of radius 1 m", true), ("an octagon of radius 1 m", false)] {
        let seq = c.next_seq();
        c.played_or_rejected(label, seq, |c| {
            let mut m = good_parts(seq, monotonic_now_ns());
            if disc {
                m.parts_mut()[0] = m.parts[0].with_disc(1.0);
            } else {
                with_polygon(&mut m, 1, &octagon(1.0));
            }
            c.send_parts(m);
            c.send_request(good_request(seq, monotonic_now_ns()));
        });
    }

    // Malformed outlines on parts[1], each with the field its line must name.
    type BadOutline = (String, &'static str, Box<dyn Fn(&mut PartState)>);
    let mut bad: Vec<BadOutline> = Vec::new();
    for code in [3, 7, 1 << 31, u32::MAX] {
        bad.push((format!("shape {code}"), "shape", Box::new(move |p| p.shape = code)));
    }
    for r in FLOATS.into_iter().chain([0.0, -0.0, -0.01, -f64::MIN_POSITIVE, 1.0 + 1e-9]) {
        bad.push((format!("disc radius {r:?}"), "radius", Box::new(move |p| *p = p.with_disc(r))));
    }
    for n in [0, 1, 2, 9, 64, u32::MAX] {
        let spoil = move |p: &mut PartState| {
            *p = p.with_polygon(&SQUARE).expect("4 fit");
            p.vertex_count = n;
        };
        bad.push((format!("polygon vertex_count {n}"), "vertex_count", Box::new(spoil)));
    }
    for (at, xy, v) in
        [0, 3].into_iter().flat_map(|at| (0..2).flat_map(move |xy| FLOATS.map(|v| (at, xy, v))))
    {
        let spoil = move |p: &mut PartState| {
            *p = p.with_polygon(&SQUARE).expect("4 fit");
            p.vertices[at][xy] = v;
        };
        bad.push((format!("polygon vertices[{at}][{xy}] = {v:?}"), "vertices", Box::new(spoil)));
    }
    let pentagram: Vec<[f64; 2]> = (0..5)
        .map(|k| {
            let a = core::f64::consts::TAU * f64::from(2 * k) / 5.0;
            [0.02 * a.cos(), 0.02 * a.sin()]
        })
        .collect();
    for (label, vertices) in [
        ("a bow-tie", vec![SQUARE[0], SQUARE[2], SQUARE[1], SQUARE[3]]),
        ("a dart", vec![[0.02, 0.0], [-0.01, 0.015], [0.0, 0.0], [-0.01, -0.015]]),
        ("a pentagram", pentagram),
        ("three on a line", vec![[0.0, 0.0], [0.01, 0.0], [0.02, 0.0]]),
        ("a repeated vertex", vec![SQUARE[0], SQUARE[0], SQUARE[1], SQUARE[2]]),
        ("all at the position", vec![[0.0; 2]; MAX_SHAPE_VERTICES]),
        ("the square twice round", [SQUARE, SQUARE].concat()),
        ("beyond the plate", vec![[1.01, 0.0], [0.0, 0.01], [0.0, -0.01]]),
    ] {
        let spoil = move |p: &mut PartState| *p = p.with_polygon(&vertices).expect("at most 8 vertices");
        bad.push((format!("polygon: {label}"), "vertices", Box::new(spoil)));
    }
    // A misnamed field is collected and reported at the end, so it does not
    // hide the checks that follow.
    let mut misnamed = Vec::new();
    for (label, field, spoil) in &bad {
        let mut sent = 0;
        c.expect(&format!("part_states {label}"), Some(RejectReason::BadShape), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut m = good_parts(seq, now);
            spoil(&mut m.parts_mut()[1]);
            sent = seq;
            c.send_parts(m);
        });
        let told = c.refusals.iter().rev().find(|r| r.seq == sent).map(|r| r.detail_str().to_owned());
        if !told.as_deref().is_some_and(|t| t.starts_with(&format!("part_states.parts[1].{field}: "))) {
            misnamed.push(format!("{label}: told {told:?}, expected the field {field}"));
        }
    }

    c.expect("part_states repeated", Some(RejectReason::Duplicate), |c| {
        let m = good_parts(c.seq, c.parts_stamp);
        c.send_parts(m);
    });
    c.expect("part_states out of order", Some(RejectReason::OutOfOrder), |c| {
        let m = good_parts(c.seq + 100, c.parts_stamp - 1_000);
        c.send_parts(m);
    });

    // --- ForceRequest
    for n in [0u32, 1, 2, 16, 63, 64] {
        let seq = c.next_seq();
        let played = c.played_or_rejected(&format!("force_request.count {n}"), seq, |c| {
            c.send_parts(many_parts(64, seq, monotonic_now_ns()));
            let mut r = ForceRequest::new();
            (r.seq, r.stamp_ns) = (seq, monotonic_now_ns());
            r.deadline_ns = r.stamp_ns + 1_000_000_000;
            for id in 1..=n {
                r.push(ForceEntry::force(id, [0.001 * f64::from(id % 3), -0.001])).expect("fits");
            }
            c.send_request(r);
        });
        assert!(played, "a valid request for {n} of 64 parts was not played");
    }
    for n in [65u32, 1000, u32::MAX] {
        c.expect(&format!("force_request.count {n}"), Some(RejectReason::CountExceedsCapacity), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut r = good_request(seq, now);
            r.count = n;
            c.send_request(r);
        });
    }
    for field in 0..3 {
        for v in FLOATS {
            let reason = if v.is_finite() { RejectReason::Unsolvable } else { RejectReason::NonFinite };
            c.expect(&format!("force_request field {field} = {v}"), Some(reason), |c| {
                let (seq, now) = (c.next_seq(), monotonic_now_ns());
                let mut r = good_request(seq, now);
                let e = &mut r.entries_mut()[0];
                e.curl_flag = 1;
                *[&mut e.fx, &mut e.fy, &mut e.curl][field] = v;
                c.send_request(r);
            });
        }
    }
    let cases: [Spoil<ForceRequest>; 10] = [
        ("request wrong version", RejectReason::WrongProtocolVersion, |r, _| r.protocol_version = u32::MAX),
        ("request zero stamp", RejectReason::Stale, |r, _| r.stamp_ns = 0),
        ("request stale stamp", RejectReason::Stale, |r, now| {
            r.stamp_ns = now - 10_000_000_000;
        }),
        ("request future stamp", RejectReason::StampFromFuture, |r, now| r.stamp_ns = now + 10_000_000_000),
        ("request deadline before stamp", RejectReason::DeadlineBeforeStamp, |r, _| {
            r.deadline_ns = r.stamp_ns - 1
        }),
        ("request flag 7", RejectReason::NotAFlag, |r, _| r.entries_mut()[0].force_flag = 7),
        ("request constrains nothing", RejectReason::ConstrainsNothing, |r, _| {
            r.entries_mut()[0].force_flag = 0
        }),
        ("request duplicate part", RejectReason::DuplicateId, |r, _| r.entries_mut()[1].part_id = 1),
        ("request unknown part", RejectReason::UnknownPart, |r, _| r.entries_mut()[1].part_id = 999),
        ("request 17 curls", RejectReason::TooManyCurls, |r, _| {
            // push() refuses the 17th curl; a hostile client writes it anyway.
            for id in 1..=17 {
                r.entries[id as usize - 1] = ForceEntry::curl(id, 0.0);
            }
            r.count = 17;
        }),
    ];
    for (label, reason, spoil) in cases {
        c.expect(label, Some(reason), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut r = good_request(seq, now);
            spoil(&mut r, now);
            c.send_request(r);
        });
    }
    c.expect("request repeated", Some(RejectReason::Duplicate), |c| {
        let r = good_request(c.seq, c.request_stamp);
        c.send_request(r);
    });
    c.expect("request out of order", Some(RejectReason::OutOfOrder), |c| {
        let r = good_request(c.seq + 100, c.request_stamp - 1_000);
        c.send_request(r);
    });

    // --- ExplicitSchedule: every count the type can carry, and beyond.
    let mut played = 0;
    for n in 1..=MAX_SLOTS as u32 {
        let seq = c.next_seq();
        if c.played_or_rejected(&format!("explicit_schedule.count {n}"), seq, |c| {
            c.send_explicit(explicit(n, seq, monotonic_now_ns()));
        }) {
            played += 1;
        }
    }
    assert!(played > 0, "no explicit schedule was played");
    eprintln!("explicit schedules: {played} of {MAX_SLOTS} counts played, the rest rejected and counted");
    for (n, reason) in [(0, RejectReason::Empty), (193, RejectReason::CountExceedsCapacity)] {
        c.expect(&format!("explicit_schedule.count {n}"), Some(reason), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            c.send_explicit(explicit(n, seq, now));
        });
    }
    c.expect("explicit_schedule.count u32::MAX", Some(RejectReason::CountExceedsCapacity), |c| {
        let (seq, now) = (c.next_seq(), monotonic_now_ns());
        c.send_explicit(explicit(u32::MAX, seq, now));
    });
    for (k, reason) in [
        (f64::NAN, RejectReason::NonFinite),
        (f64::INFINITY, RejectReason::NonFinite),
        (1e308, RejectReason::KOutOfRange),
        (-0.999, RejectReason::KOutOfRange),
    ] {
        c.expect(&format!("explicit k = {k}"), Some(reason), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut e = explicit(4, seq, now);
            e.slots[2].k = k;
            c.send_explicit(e);
        });
    }
    for index in [4, u32::MAX] {
        c.expect(&format!("explicit center {index}"), Some(RejectReason::UnknownCenter), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            let mut e = explicit(4, seq, now);
            e.slots[3].center_index = index;
            c.send_explicit(e);
        });
    }

    // --- CoreCommand
    for command in [0, 7, u32::MAX] {
        c.expect(&format!("core_command {command}"), Some(RejectReason::UnknownCommand), |c| {
            let (seq, now) = (c.next_seq(), monotonic_now_ns());
            c.send_command(CoreCommand::new(command, seq, now));
        });
    }
    c.expect("core_command wrong version", Some(RejectReason::WrongProtocolVersion), |c| {
        let mut m = CoreCommand::new(CoreCommand::RESUME, c.next_seq(), monotonic_now_ns());
        m.protocol_version = 0;
        c.send_command(m);
    });
    c.expect("resume with nothing to resume", None, |c| {
        let m = CoreCommand::new(CoreCommand::RESUME, c.next_seq(), monotonic_now_ns());
        c.send_command(m);
    });

    let t = c.fresh_telemetry();
    assert_eq!(t.health().map(|h| h.0), Some(HealthSource::Ok), "{}", t.health_detail_str());
    assert_ne!(t.core_state(), Some(CoreState::Fault));
    assert_eq!(t.counters.rt_thread_allocations, 0, "the RT threads allocated");
    let by_reason: Vec<String> = RejectReason::ALL
        .iter()
        .filter(|r| t.rejected_by_reason[r.index()] > 0)
        .map(|r| format!("{r} {}", t.rejected_by_reason[r.index()]))
        .collect();
    eprintln!("rejected by reason: {}", by_reason.join(", "));
    assert!(
        t.rejected_by_reason[RejectReason::BadShape.index()] >= bad.len() as u64,
        "bad_shape undercounted"
    );
    assert!(misnamed.is_empty(), "rejections that do not name the field:\n{}", misnamed.join("\n"));
}

#[test]
fn a_flood_of_ten_thousand_messages_a_second_leaves_the_core_answering() {
    let mut c = Client::connect(&unique_prefix("flood"));
    c.round_trip("start-up");
    let start = Instant::now();
    let mut sent = 0u64;
    let mut next = Instant::now();
    while start.elapsed() < Duration::from_secs(10) {
        let seq = c.next_seq();
        let now = monotonic_now_ns();
        if seq.is_multiple_of(2) {
            c.send_parts(good_parts(seq, now));
        } else {
            c.send_request(good_request(seq, now));
        }
        sent += 1;
        next += Duration::from_micros(100);
        if let Some(wait) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        if sent.is_multiple_of(1000) {
            c.poll();
        }
    }
    let rate = sent as f64 / start.elapsed().as_secs_f64();
    c.round_trip("the flood");
    let t = c.fresh_telemetry();
    eprintln!(
        "flood: {sent} messages at {rate:.0}/s; answered {}; overflow {}; rejected {}; ticks {}; overruns {}",
        c.answered.len(),
        t.rejected_by_reason[RejectReason::Overflow.index()],
        rejected(&t),
        t.counters.ticks,
        t.counters.overruns,
    );
    assert!(rate > 8_000.0, "the flood reached only {rate:.0} messages/s");
    assert_eq!(t.health().map(|h| h.0), Some(HealthSource::Ok), "{}", t.health_detail_str());
    assert_eq!(t.counters.rt_thread_allocations, 0, "the RT threads allocated");
}
