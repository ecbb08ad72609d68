//! `upm replay FILE`: the recorded inputs fed to a lock-step core, each at
//! the instant the recorded core handled it, and every output compared bit
//! for bit with the recorded one.
//!
//! A recorded schedule names its whole input: the request (`seq`,
//! `request_stamp_ns`), the part states it was solved against (`parts_seq`,
//! `parts_stamp_ns`) and the instant the core picked the request up
//! (`stamp_ns`); a rejection names the refused message, the newest part
//! states the core had accepted and the instant. Outputs are replayed in
//! that order through the core's own solve stage (`Lockstep::handle_at`),
//! each part states fed when an output first names it, so the solver's
//! warm start sees the same history. Compared: every field but `cycle` and
//! `solve_time_ns` (timing, not a function of the input).
//!
//! Refused rather than half-compared: a recording whose recorder lost core
//! inputs, one that starts after the core had played schedules (the
//! solver's warm start carries history the file lacks), one with a
//! recorded request no output answers (an answer lost), and one with
//! nothing to compare.
//!
//! `--planner NAME` instead feeds the recorded part states to another
//! planner and the core, open loop (the parts move as they did), and writes
//! what came out to a new recording. It plans on every recorded part
//! states; the planner process plans on the newest each time it wakes, so
//! under load it may plan less often than this.

use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, bail};
use ipc_types::{
    ExplicitSchedule, ForceRequest, PartStates, RejectedKind, Rejection, Schedule, Telemetry, WireMessage,
    service_names,
};
use rt_core::lockstep::Lockstep;
use serde_json::{Value, json};
use upm_hardware::IdealDriver;
use upm_recorder::{LogOptions, PlateView, RigLog};

use crate::config::Config;
use crate::recording::{RawMessage, Recording};

/// What a recording holds that a replay needs, in log order.
#[derive(Debug, Default)]
struct Inputs {
    parts: Vec<(u64, PartStates)>,
    requests: Vec<ForceRequest>,
    explicit: Vec<ExplicitSchedule>,
    /// With their index in the file (the recorded order).
    schedules: Vec<(usize, Schedule)>,
    rejections: Vec<(usize, Rejection)>,
    /// The first telemetry recorded: what the core had done before.
    first_telemetry: Option<Telemetry>,
}

fn read_inputs(rec: &Recording) -> anyhow::Result<Inputs> {
    rec.check_type::<PartStates>(service_names::PART_STATES)?;
    rec.check_type::<ForceRequest>(service_names::FORCE_REQUEST)?;
    rec.check_type::<ExplicitSchedule>(service_names::EXPLICIT_SCHEDULE)?;
    rec.check_type::<Schedule>(service_names::SCHEDULE)?;
    rec.check_type::<Rejection>(service_names::REJECTION)?;
    rec.check_type::<Telemetry>(service_names::TELEMETRY)?;
    let mut i = Inputs::default();
    rec.for_each_raw(|index, m: RawMessage<'_>| {
        match m.topic {
            service_names::PART_STATES => i.parts.push((m.log_time, rec.decode(index, m)?)),
            service_names::FORCE_REQUEST => i.requests.push(rec.decode(index, m)?),
            service_names::EXPLICIT_SCHEDULE => i.explicit.push(rec.decode(index, m)?),
            service_names::SCHEDULE => i.schedules.push((index as usize, rec.decode(index, m)?)),
            service_names::REJECTION => i.rejections.push((index as usize, rec.decode(index, m)?)),
            service_names::TELEMETRY if i.first_telemetry.is_none() => {
                i.first_telemetry = Some(rec.decode(index, m)?)
            }
            _ => {}
        }
        Ok(())
    })?;
    Ok(i)
}

/// The core the recording ran with, in lock-step at `start_ns`.
fn core_for(rec: &Recording, start_ns: u64) -> anyhow::Result<(Config, Lockstep<IdealDriver>)> {
    let shown = format!("{} (its {})", rec.shown, upm_recorder::CONFIG_ATTACHMENT);
    let config = Config::parse(rec.config_text()?, &shown)?;
    let params = config.core_params(&shown)?;
    // Schedules do not depend on the plate: any driver will do.
    let driver = IdealDriver::new(params.rig, params.motion.tick_hz).map_err(|e| anyhow::anyhow!("{e}"))?;
    let core =
        Lockstep::new(&params, driver, start_ns.max(1)).map_err(|e| anyhow::anyhow!("{shown}: {e}"))?;
    Ok((config, core))
}

/// One recorded output: what the core answered, in the order it did.
#[derive(Debug, Clone, Copy)]
enum Output<'a> {
    Schedule(&'a Schedule),
    Rejection(&'a Rejection),
}

impl Output<'_> {
    fn handled_ns(&self) -> u64 {
        match self {
            Self::Schedule(s) => s.stamp_ns,
            Self::Rejection(r) => r.stamp_ns,
        }
    }

    /// The part states the core held when it answered; None: none yet.
    fn parts(&self) -> Option<(u64, u64)> {
        let key = match self {
            Self::Schedule(s) => (s.parts_seq, s.parts_stamp_ns),
            Self::Rejection(r) => (r.parts_seq, r.parts_stamp_ns),
        };
        (key != (0, 0)).then_some(key)
    }

    /// The message answered: (kind, seq, stamp).
    fn input(&self) -> Option<(RejectedKind, u64, u64)> {
        match self {
            // `solve_time_ns` is 0 exactly for an explicit schedule (protocol.md).
            Self::Schedule(s) if s.solve_time_ns == 0 => {
                Some((RejectedKind::ExplicitSchedule, s.seq, s.request_stamp_ns))
            }
            Self::Schedule(s) => Some((RejectedKind::ForceRequest, s.seq, s.request_stamp_ns)),
            Self::Rejection(r) => r.kind().map(|k| (k, r.seq, r.message_stamp_ns)),
        }
    }

    fn describe(&self) -> String {
        match self {
            Self::Schedule(s) => format!("schedule seq {}", s.seq),
            Self::Rejection(r) => {
                format!("rejection of {} seq {}", r.kind().map_or("?", |k| k.as_str()), r.seq)
            }
        }
    }
}

/// The first field in which two schedules differ (timing fields aside).
fn schedule_difference(a: &Schedule, b: &Schedule) -> Option<(String, String, String)> {
    macro_rules! same {
        ($($f:ident),*) => {$(
            if a.$f != b.$f {
                return Some((stringify!($f).into(), a.$f.to_string(), b.$f.to_string()));
            }
        )*};
    }
    same!(
        protocol_version,
        count,
        seq,
        stamp_ns,
        parts_seq,
        parts_stamp_ns,
        request_stamp_ns,
        rank,
        saturated
    );
    let bits = |name: &str, x: f64, y: f64| {
        (x.to_bits() != y.to_bits()).then(|| (name.to_owned(), format!("{x:e}"), format!("{y:e}")))
    };
    if let Some(d) =
        bits("residual", a.residual, b.residual).or_else(|| bits("condition", a.condition, b.condition))
    {
        return Some(d);
    }
    for (i, (x, y)) in a.slots().iter().zip(b.slots()).enumerate() {
        if x.center_index != y.center_index {
            return Some((
                format!("slots[{i}].center_index"),
                x.center_index.to_string(),
                y.center_index.to_string(),
            ));
        }
        for (name, u, v) in [("x", x.x, y.x), ("y", x.y, y.y), ("k", x.k, y.k)] {
            if let Some(d) = bits(&format!("slots[{i}].{name}"), u, v) {
                return Some(d);
            }
        }
    }
    None
}

fn rejection_difference(a: &Rejection, b: &Rejection) -> Option<(String, String, String)> {
    let fields = [
        ("kind", a.kind.to_string(), b.kind.to_string()),
        ("seq", a.seq.to_string(), b.seq.to_string()),
        ("reason", a.reason.to_string(), b.reason.to_string()),
        ("detail", a.detail_str().to_owned(), b.detail_str().to_owned()),
    ];
    fields.into_iter().find(|(_, x, y)| x != y).map(|(f, x, y)| (f.to_owned(), x, y))
}

/// How a replay ended.
#[derive(Debug)]
pub struct ReplayReport {
    /// None: identical; else the first divergence in one line.
    pub divergence: Option<String>,
    pub schedules: usize,
    pub rejections: usize,
    /// Every recorded rejection, as the core gave it.
    pub rejected: Vec<String>,
    pub recorded_s: f64,
    pub replay_s: f64,
}

impl ReplayReport {
    pub fn to_json(&self) -> Value {
        json!({
            "identical": self.divergence.is_none(),
            "divergence": self.divergence,
            "schedules": self.schedules,
            "rejections": self.rejections,
            "rejected": self.rejected,
            "recorded_s": self.recorded_s,
            "replay_s": self.replay_s,
            "speed_x_real_time": self.recorded_s / self.replay_s.max(1e-9),
        })
    }
}

/// `items` by (seq, stamp_ns), the key an output names its input by; the
/// first of identical keys wins.
fn by_key<'a, T>(
    items: impl IntoIterator<Item = &'a T>,
    key: impl Fn(&T) -> (u64, u64),
) -> HashMap<(u64, u64), &'a T> {
    let mut map = HashMap::new();
    for m in items {
        map.entry(key(m)).or_insert(m);
    }
    map
}

/// The recorded outputs in the order the core produced them (by the
/// instant it handled each; ties in recorded order), commands and picks
/// left out: they only move the motor or the feed cell, not the solver.
fn timeline(inputs: &Inputs) -> Vec<Output<'_>> {
    let mut outputs: Vec<(u64, usize, Output)> = Vec::new();
    let schedules = inputs.schedules.iter().map(|(i, s)| (*i, Output::Schedule(s)));
    let rejections = inputs
        .rejections
        .iter()
        .filter(|(_, r)| {
            !matches!(
                r.kind(),
                Some(RejectedKind::CoreCommand | RejectedKind::PickCommand | RejectedKind::RecipeCommand)
            )
        })
        .map(|(i, r)| (*i, Output::Rejection(r)));
    for (index, out) in schedules.chain(rejections) {
        outputs.push((out.handled_ns(), index, out));
    }
    outputs.sort_by_key(|(at, index, _)| (*at, *index));
    outputs.into_iter().map(|(_, _, o)| o).collect()
}

/// Replay `path`; see the module doc.
pub fn replay(path: &Path) -> anyhow::Result<ReplayReport> {
    let rec = Recording::open(path)?;
    let started = Instant::now();
    let gaps: Vec<String> =
        [service_names::PART_STATES, service_names::FORCE_REQUEST, service_names::EXPLICIT_SCHEDULE]
            .iter()
            .filter_map(|t| {
                rec.counts.get(&format!("lost {t}")).filter(|n| *n != "0").map(|n| format!("{n} on {t}"))
            })
            .collect();
    if !gaps.is_empty() {
        // The solver's warm start depends on every input it saw.
        bail!(
            "{}: cannot replay bit for bit: the recorder lost core inputs ({})",
            rec.shown,
            gaps.join(", ")
        );
    }
    let inputs = read_inputs(&rec)?;
    if let Some(t) = inputs.first_telemetry.filter(|t| t.counters.schedule_swaps > 0) {
        bail!(
            "{}: cannot replay bit for bit: the recording started after the core had played {} schedules, \
             and the solver's warm start carries that history (record from the core's start, as upm run does)",
            rec.shown,
            t.counters.schedule_swaps
        );
    }
    let outputs = timeline(&inputs);
    let Some(first) = outputs.first() else {
        bail!("{}: nothing to replay: no schedule or rejection was recorded", rec.shown);
    };
    let answered: std::collections::BTreeSet<(u64, u64)> = outputs
        .iter()
        .filter_map(Output::input)
        .filter(|(k, ..)| *k == RejectedKind::ForceRequest)
        .map(|(_, seq, stamp)| (seq, stamp))
        .collect();
    let unanswered = inputs.requests.iter().filter(|m| !answered.contains(&(m.seq, m.stamp_ns))).count();
    if unanswered > 0 {
        bail!(
            "{}: cannot replay bit for bit: {unanswered} recorded force requests have no recorded answer \
             (a schedule or rejection the recorder or the core's output ring lost)",
            rec.shown
        );
    }
    let parts = by_key(inputs.parts.iter().map(|(_, p)| p), |p| (p.seq, p.stamp_ns));
    let requests = by_key(&inputs.requests, |m| (m.seq, m.stamp_ns));
    let explicit = by_key(&inputs.explicit, |m| (m.seq, m.stamp_ns));
    let first_parts = inputs.parts.iter().map(|(_, p)| p.stamp_ns).min().unwrap_or(u64::MAX);
    let (_, mut core) = core_for(&rec, first.handled_ns().min(first_parts).saturating_sub(1))?;
    let missing =
        |what: String| anyhow::anyhow!("{}: cannot replay: {what} is not in the recording", rec.shown);
    let mut current_parts: Option<(u64, u64)> = None;
    let (mut n_sched, mut n_rej) = (0, 0);
    let mut divergence = None;
    for out in &outputs {
        let now = out.handled_ns();
        if let Some(key) = out.parts()
            && current_parts != Some(key)
        {
            let p = parts
                .get(&key)
                .ok_or_else(|| missing(format!("part states seq {} stamp {}", key.0, key.1)))?;
            core.inbox().push_parts(p);
            // Accepted by the core at some instant before `now`, not before
            // its stamp (handle_at never goes back).
            core.handle_at(p.stamp_ns.min(now));
            current_parts = Some(key);
        }
        let (seen_s, seen_r) = (core.published().len(), core.rejections().len());
        let Some((kind, seq, stamp)) = out.input() else { continue };
        let what =
            || format!("the {} seq {seq} stamp {stamp} ({} answered it)", kind.as_str(), out.describe());
        let key = (seq, stamp);
        let found = match kind {
            RejectedKind::PartStates => parts.get(&key).map(|m| core.inbox().push_parts(m)),
            RejectedKind::ForceRequest => requests.get(&key).map(|m| core.inbox().push_request(m)),
            RejectedKind::ExplicitSchedule => explicit.get(&key).map(|m| core.inbox().push_explicit(m)),
            RejectedKind::CoreCommand | RejectedKind::PickCommand | RejectedKind::RecipeCommand => continue,
        };
        found.ok_or_else(|| missing(what()))?;
        core.handle_at(now);
        let new_s = &core.published()[seen_s..];
        let new_r = &core.rejections()[seen_r..];
        let diff = match (out, new_s, new_r) {
            (Output::Schedule(want), [got], []) => {
                n_sched += 1;
                schedule_difference(want, got)
                    .map(|(f, a, b)| format!("schedule seq {}: {f}: recorded {a}, replayed {b}", want.seq))
            }
            (Output::Rejection(want), [], [got]) => {
                n_rej += 1;
                rejection_difference(want, got).map(|(f, a, b)| {
                    format!("rejection of seq {}: {f}: recorded {a}, replayed {b}", want.seq)
                })
            }
            (_, s, r) => Some(format!(
                "{}: recorded one answer, replayed {} schedules and {} rejections{}",
                out.describe(),
                s.len(),
                r.len(),
                r.first().map_or(String::new(), |r| format!(" ({r})"))
            )),
        };
        if diff.is_some() {
            divergence = diff;
            break;
        }
    }
    let (t0, t1) = rec.span_ns;
    Ok(ReplayReport {
        divergence,
        schedules: n_sched,
        rejections: n_rej,
        rejected: inputs.rejections.iter().map(|(_, r)| r.to_string()).collect(),
        recorded_s: t1.saturating_sub(t0) as f64 / 1e9,
        replay_s: started.elapsed().as_secs_f64(),
    })
}

/// What `--planner` produced.
#[derive(Debug)]
pub struct PlannerReplay {
    pub planner: String,
    pub part_states: usize,
    pub requests: usize,
    pub schedules: usize,
    pub rejections: usize,
    pub saturated: usize,
    pub mean_residual: f64,
    /// The recording's own schedules, for comparison.
    pub recorded_schedules: usize,
    pub recorded_saturated: usize,
    pub recorded_mean_residual: f64,
}

impl PlannerReplay {
    pub fn to_json(&self) -> Value {
        json!({
            "planner": self.planner, "part_states": self.part_states, "requests": self.requests,
            "schedules": self.schedules, "rejections": self.rejections, "saturated": self.saturated,
            "mean_residual_n": self.mean_residual,
            "recorded": {"schedules": self.recorded_schedules, "saturated": self.recorded_saturated,
                         "mean_residual_n": self.recorded_mean_residual},
        })
    }
}

fn mean_residual<'a>(s: impl ExactSizeIterator<Item = &'a Schedule>) -> f64 {
    let n = s.len().max(1) as f64;
    s.map(|s| s.residual).sum::<f64>() / n
}

/// Feed the recorded part states to `planner` and a lock-step core; write
/// part states, requests, schedules and rejections to `out` (MCAP).
pub fn replay_with_planner(path: &Path, planner: &str, out: &Path) -> anyhow::Result<PlannerReplay> {
    let rec = Recording::open(path)?;
    let inputs = read_inputs(&rec)?;
    let first = inputs.parts.iter().map(|(_, p)| p.stamp_ns).min().unwrap_or(1);
    let (config, mut core) = core_for(&rec, first.saturating_sub(1))?;
    let chosen = if config.planner.name() == planner {
        config.planner.clone()
    } else {
        upm_planner::PlannerConfig::by_name(planner).map_err(anyhow::Error::msg)?
    };
    let mut p = chosen.build().map_err(|m| anyhow::anyhow!("planner {planner}: {m}"))?;
    if out.exists() {
        bail!("{} exists; the replay never overwrites a recording", out.display());
    }
    let mut info = rec.run.clone();
    info.insert("replayed_from".into(), rec.shown.clone());
    info.insert("planner".into(), planner.into());
    let plate = PlateView {
        half_extent: config.plate.half_extent,
        mu_m_g: config.plate.mu_m_g,
        centers: config.plate.centers.clone(),
    };
    let mut log = RigLog::open(&LogOptions {
        plate,
        mcap: Some(out.to_path_buf()),
        serve_port: None,
        config_text: rec.config_text.clone(),
        info,
        segment: None,
    })?;
    let mut req = ForceRequest::new();
    let mut requests = 0;
    let t0 = first;
    for (log_time, parts) in &inputs.parts {
        let (seen_s, seen_r) = (core.published().len(), core.rejections().len());
        let now = parts.stamp_ns.max(core.now_ns());
        core.inbox().push_parts(parts);
        core.handle_at(now);
        log.log(PartStates::SERVICE, parts, &[], *log_time);
        if p.plan(parts, now.saturating_sub(t0) as f64 / 1e9, &mut req) {
            requests += 1;
            req.seq = requests as u64;
            req.stamp_ns = now;
            req.deadline_ns = now + upm_planner::run::REQUEST_LIFETIME_NS;
            core.inbox().push_request(&req);
            core.handle_at(now);
            log.log(ForceRequest::SERVICE, &req, &[], *log_time);
        }
        for s in &core.published()[seen_s..] {
            log.log(Schedule::SERVICE, s, &[], *log_time);
        }
        for r in &core.rejections()[seen_r..] {
            log.log(Rejection::SERVICE, r, &[], *log_time);
        }
        log.view(*log_time);
    }
    log.finish().with_context(|| format!("writing {}", out.display()))?;
    let schedules = core.published();
    Ok(PlannerReplay {
        planner: planner.into(),
        part_states: inputs.parts.len(),
        requests,
        schedules: schedules.len(),
        rejections: core.rejections().len(),
        saturated: schedules.iter().filter(|s| s.is_saturated()).count(),
        mean_residual: mean_residual(schedules.iter()),
        recorded_schedules: inputs.schedules.len(),
        recorded_saturated: inputs.schedules.iter().filter(|(_, s)| s.is_saturated()).count(),
        recorded_mean_residual: mean_residual(inputs.schedules.iter().map(|(_, s)| s)),
    })
}

/// `upm replay`: prints the verdict; a divergence is exit status 1, a
/// file that cannot be replayed 2 (one line).
pub fn run_command(file: &Path, planner: Option<&str>, out: &Path, as_json: bool) -> anyhow::Result<()> {
    let unreadable = |e: anyhow::Error| crate::exit::Exit { code: 2, message: format!("{e:#}") };
    if let Some(name) = planner {
        let r = replay_with_planner(file, name, out).map_err(unreadable)?;
        if as_json {
            println!("{}", serde_json::to_string_pretty(&r.to_json())?);
        } else {
            println!(
                "planner {}: {} part states -> {} requests, {} schedules ({} saturated, mean residual {:.3e}), \
                 {} rejections; recorded: {} schedules ({} saturated, mean residual {:.3e}); residuals in N, \
                 curl rows in N/m; wrote {}",
                r.planner,
                r.part_states,
                r.requests,
                r.schedules,
                r.saturated,
                r.mean_residual,
                r.rejections,
                r.recorded_schedules,
                r.recorded_saturated,
                r.recorded_mean_residual,
                out.display()
            );
        }
        return Ok(());
    }
    let r = replay(file).map_err(unreadable)?;
    if as_json {
        println!("{}", serde_json::to_string_pretty(&r.to_json())?);
    } else {
        match &r.divergence {
            None => println!(
                "identical: {} schedules and {} rejections reproduced bit for bit ({:.1} s recorded, replayed in {:.2} s)",
                r.schedules, r.rejections, r.recorded_s, r.replay_s
            ),
            Some(d) => println!("diverged: {d}"),
        }
        for line in &r.rejected {
            println!("  recorded: {line}");
        }
    }
    match r.divergence {
        Some(_) => Err(crate::exit::Exit { code: 1, message: String::new() }.into()),
        None => Ok(()),
    }
}
