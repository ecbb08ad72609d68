//! The channels of a rig's log, on one foxglove `Context`: each service's
//! raw messages (topic = the service name, message encoding `upm-repr-c`,
//! schema name = the type name: their exact bytes, what `upm replay`
//! reads), a decoded JSON companion per service (topic + `/json`, with a
//! JSON schema), a `foxglove.SceneUpdate` and the core's latency figures.
//! The sinks are an MCAP file (zstd chunks, index, statistics, the rig's
//! TOML attached), a Foxglove WebSocket server on localhost, or both.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context as _;
use foxglove::messages::{SceneUpdate, Timestamp};
use foxglove::{
    Channel, ChannelBuilder, Context, McapAttachment, McapCompression, McapWriteOptions, McapWriterHandle,
    PartialMetadata, RawChannel, Schema, WebSocketServer, WebSocketServerHandle,
};
use ipc_types::{
    CoreCommand, ExplicitSchedule, FeedStatus, ForceRequest, FrameHeader, LineStatus, PartStates,
    PickCommand, RecipeCommand, Rejection, RigInfo, Schedule, Telemetry, WireMessage, service_names,
};

use crate::decoded::{Decoded, latencies, schema, schema_of};
use crate::scene::{PlateView, Scene};

/// Message encoding of the raw channels: the payload's bytes as in shared
/// memory (little-endian, layout in docs/protocol.md).
pub const RAW_ENCODING: &str = "upm-repr-c";
/// Suffix of the decoded companion of a raw topic.
pub const JSON_SUFFIX: &str = "/json";
pub const SCENE_TOPIC: &str = "upm/scene";
pub const LATENCY_TOPIC: &str = "upm/latency";
/// MCAP profile of a UPM recording.
pub const PROFILE: &str = "upm";
/// Metadata written at start (protocol version, prefix, clocks, run info)
/// and at the end (messages received and lost per topic, `unknown` where
/// the source cannot tell).
pub const RUN_METADATA: &str = "upm";
pub const COUNTS_METADATA: &str = "upm.recorder";
/// Attachment holding the rig's TOML (what the core ran with).
pub const CONFIG_ATTACHMENT: &str = "config.toml";

/// Uncompressed bytes per MCAP chunk.
const CHUNK_BYTES: u64 = 1 << 20;
/// Scene at most this often; decoded ground truth (1 kHz raw) likewise.
const VIEW_PERIOD_NS: u64 = 100_000_000;
const TRUTH_JSON_PERIOD_NS: u64 = 20_000_000;

/// Where the log goes and what it says about itself.
#[derive(Debug, Clone, Default)]
pub struct LogOptions {
    pub plate: PlateView,
    /// Write an MCAP file here (must not exist).
    pub mcap: Option<PathBuf>,
    /// Serve the Foxglove WebSocket protocol on this localhost port (0: any free one).
    pub serve_port: Option<u16>,
    /// Attached as `config.toml` (replay needs it).
    pub config_text: Option<String>,
    /// The run metadata's key/values (prefix, scenario, seed, clocks, …);
    /// the protocol version is added.
    pub info: BTreeMap<String, String>,
    /// Start a new file after this long (None: one file). The writer keeps
    /// each chunk's index entry in memory until its file ends, so a long
    /// run's recorder grows unless its files do end.
    pub segment: Option<Duration>,
}

/// The file of segment `n` (0: `first` itself; then `NAME.001.mcap`, …
/// beside it).
pub fn segment_path(first: &Path, n: u32) -> PathBuf {
    if n == 0 {
        return first.to_path_buf();
    }
    let stem = first.file_stem().map_or_else(|| "recording".into(), |s| s.to_string_lossy().into_owned());
    let ext = first.extension().map_or_else(|| "mcap".into(), |s| s.to_string_lossy().into_owned());
    first.with_file_name(format!("{stem}.{n:03}.{ext}"))
}

/// The MCAP file being written, and what the next segment needs.
#[derive(Debug)]
struct McapOut {
    writer: McapWriterHandle<BufWriter<File>>,
    first: PathBuf,
    segment: u32,
    /// Log time (Unix ns) the segment's first message may have; 0: not yet.
    started_ns: u64,
    every: Option<Duration>,
    info: BTreeMap<String, String>,
    config_text: Option<String>,
}

impl McapOut {
    /// Segment `n`'s file, with the run metadata and the rig's TOML, so that
    /// every segment is a recording of its own.
    fn open(
        ctx: &Arc<Context>,
        first: &Path,
        n: u32,
        every: Option<Duration>,
        info: &BTreeMap<String, String>,
        config_text: Option<&str>,
    ) -> anyhow::Result<Self> {
        let path = segment_path(first, n);
        // The writer keeps each chunk's index entry (≈ 0.8 kB) in memory
        // until the file ends (hence segments): at 1 MiB a feed run's
        // recorder grows 8 MB an hour (1 MB at 8 MiB, but an 8 MiB chunk's
        // compression is one long burst on the clients' CPU).
        let options = McapWriteOptions::new()
            .compression(Some(McapCompression::Zstd))
            .chunk_size(Some(CHUNK_BYTES))
            .use_chunks(true)
            .emit_statistics(true)
            .emit_metadata_indexes(true)
            .emit_attachment_indexes(true)
            .profile(PROFILE);
        let writer = ctx
            .mcap_writer_with_options(options)
            .create_new_buffered_file(&path)
            .with_context(|| format!("creating {}", path.display()))?;
        let mut run = info.clone();
        run.insert("protocol_version".into(), ipc_types::PROTOCOL_VERSION.to_string());
        if every.is_some() {
            run.insert("segment".into(), n.to_string());
        }
        writer.write_metadata(RUN_METADATA, run)?;
        if let Some(text) = config_text {
            writer.attach(&McapAttachment {
                log_time: 0,
                create_time: 0,
                name: CONFIG_ATTACHMENT.into(),
                media_type: "application/toml".into(),
                data: std::borrow::Cow::Borrowed(text.as_bytes()),
            })?;
        }
        Ok(Self {
            writer,
            first: first.to_path_buf(),
            segment: n,
            started_ns: 0,
            every,
            info: info.clone(),
            config_text: config_text.map(str::to_owned),
        })
    }

    /// The counts so far into the file's metadata, then close it.
    fn close(self, counts: BTreeMap<String, String>) -> anyhow::Result<()> {
        self.writer.write_metadata(COUNTS_METADATA, counts)?;
        self.writer.close()?;
        Ok(())
    }
}

/// One service: its raw and decoded channels and what was seen on it.
#[derive(Debug)]
struct Topic {
    raw: Arc<RawChannel>,
    json: Arc<RawChannel>,
    received: u64,
    /// Messages the source knows it missed; None: it cannot tell.
    lost: Option<u64>,
    json_period_ns: u64,
    last_json_ns: u64,
}

impl Topic {
    /// `T` on `service`.
    fn new<T: WireMessage + Decoded>(ctx: &Arc<Context>, service: &'static str) -> anyhow::Result<Self> {
        let layout = format!(
            "{} as #[repr(C)] bytes, {} bytes, little-endian; docs/protocol.md",
            T::wire_type_name(),
            size_of::<T>()
        );
        let raw = ChannelBuilder::new(service)
            .context(ctx)
            .message_encoding(RAW_ENCODING)
            .schema(Schema::new(T::wire_type_name(), RAW_ENCODING, layout.into_bytes()))
            .add_metadata("type_name", T::wire_type_name())
            .add_metadata("size", &size_of::<T>().to_string())
            .build_raw()?;
        let json = ChannelBuilder::new(format!("{service}{JSON_SUFFIX}"))
            .context(ctx)
            .message_encoding("json")
            .schema(Schema::new(T::wire_type_name(), "jsonschema", serde_json::to_vec(&schema::<T>())?))
            .build_raw()?;
        let json_period_ns =
            if service == service_names::SIM_GROUND_TRUTH { TRUTH_JSON_PERIOD_NS } else { 0 };
        Ok(Self { raw, json, received: 0, lost: Some(0), json_period_ns, last_json_ns: 0 })
    }
}

/// The log of one rig; see the module doc.
#[derive(Debug)]
pub struct RigLog {
    topics: BTreeMap<&'static str, Topic>,
    scene: Scene,
    scene_channel: Channel<SceneUpdate>,
    latency: Arc<RawChannel>,
    last_view_ns: u64,
    mcap: Option<McapOut>,
    ws: Option<WebSocketServerHandle>,
    /// More key/values for the counts metadata.
    notes: BTreeMap<String, String>,
    ctx: Arc<Context>,
}

impl RigLog {
    pub fn open(opts: &LogOptions) -> anyhow::Result<Self> {
        let ctx = Context::new();
        let mut topics = BTreeMap::new();
        topics.insert(PartStates::SERVICE, Topic::new::<PartStates>(&ctx, PartStates::SERVICE)?);
        topics.insert(ForceRequest::SERVICE, Topic::new::<ForceRequest>(&ctx, ForceRequest::SERVICE)?);
        topics.insert(
            ExplicitSchedule::SERVICE,
            Topic::new::<ExplicitSchedule>(&ctx, ExplicitSchedule::SERVICE)?,
        );
        topics.insert(CoreCommand::SERVICE, Topic::new::<CoreCommand>(&ctx, CoreCommand::SERVICE)?);
        topics.insert(PickCommand::SERVICE, Topic::new::<PickCommand>(&ctx, PickCommand::SERVICE)?);
        topics.insert(RecipeCommand::SERVICE, Topic::new::<RecipeCommand>(&ctx, RecipeCommand::SERVICE)?);
        topics.insert(LineStatus::SERVICE, Topic::new::<LineStatus>(&ctx, LineStatus::SERVICE)?);
        topics.insert(Schedule::SERVICE, Topic::new::<Schedule>(&ctx, Schedule::SERVICE)?);
        topics.insert(Telemetry::SERVICE, Topic::new::<Telemetry>(&ctx, Telemetry::SERVICE)?);
        topics.insert(Rejection::SERVICE, Topic::new::<Rejection>(&ctx, Rejection::SERVICE)?);
        topics.insert(RigInfo::SERVICE, Topic::new::<RigInfo>(&ctx, RigInfo::SERVICE)?);
        topics.insert(FeedStatus::SERVICE, Topic::new::<FeedStatus>(&ctx, FeedStatus::SERVICE)?);
        topics.insert(FrameHeader::SERVICE, Topic::new::<FrameHeader>(&ctx, FrameHeader::SERVICE)?);
        // The simulator's ground truth is PartStates on a service of its own,
        // the core's active recipe a RecipeCommand.
        let truth = service_names::SIM_GROUND_TRUTH;
        topics.insert(truth, Topic::new::<PartStates>(&ctx, truth)?);
        let active = service_names::RECIPE_ACTIVE;
        topics.insert(active, Topic::new::<RecipeCommand>(&ctx, active)?);
        let scene_channel = ChannelBuilder::new(SCENE_TOPIC).context(&ctx).build::<SceneUpdate>();
        let latency_schema = serde_json::to_vec(&schema_of(&latencies(&Telemetry::new())))?;
        let latency = ChannelBuilder::new(LATENCY_TOPIC)
            .context(&ctx)
            .message_encoding("json")
            .schema(Schema::new("upm.Latency", "jsonschema", latency_schema))
            .build_raw()?;
        let mcap = match &opts.mcap {
            Some(path) => {
                Some(McapOut::open(&ctx, path, 0, opts.segment, &opts.info, opts.config_text.as_deref())?)
            }
            None => None,
        };
        let ws = match opts.serve_port {
            Some(port) => Some(
                WebSocketServer::new()
                    .context(&ctx)
                    .name("upm")
                    .bind("127.0.0.1", port)
                    .start_blocking()
                    .context("starting the Foxglove WebSocket server")?,
            ),
            None => None,
        };
        Ok(Self {
            topics,
            scene: Scene::new(opts.plate.clone()),
            scene_channel,
            latency,
            last_view_ns: 0,
            mcap,
            ws,
            notes: BTreeMap::new(),
            ctx,
        })
    }

    /// The WebSocket server's port, if serving.
    pub fn port(&self) -> Option<u16> {
        self.ws.as_ref().map(WebSocketServerHandle::port)
    }

    /// Log `m` (followed by `extra` bytes: a frame's pixels) as received on
    /// `service` at `log_ns` (Unix ns); the scene follows part states,
    /// requests and schedules. A service without a topic is ignored.
    pub fn log<T: WireMessage + Decoded>(&mut self, service: &'static str, m: &T, extra: &[u8], log_ns: u64) {
        let Some(t) = self.topics.get_mut(service) else { return };
        t.received += 1;
        let meta = PartialMetadata::with_log_time(log_ns);
        if extra.is_empty() {
            t.raw.log_with_meta(m.as_bytes(), meta);
        } else {
            let mut bytes = Vec::with_capacity(size_of::<T>() + extra.len());
            bytes.extend_from_slice(m.as_bytes());
            bytes.extend_from_slice(extra);
            t.raw.log_with_meta(&bytes, meta);
        }
        if log_ns >= t.last_json_ns.saturating_add(t.json_period_ns) && t.json.has_sinks() {
            t.last_json_ns = log_ns;
            if let Ok(text) = serde_json::to_vec(&m.decoded()) {
                t.json.log_with_meta(&text, PartialMetadata::with_log_time(log_ns));
            }
        }
        let any: &dyn core::any::Any = m;
        if service == service_names::PART_STATES
            && let Some(p) = any.downcast_ref::<PartStates>()
        {
            self.scene.on_parts(p);
        } else if let Some(r) = any.downcast_ref::<ForceRequest>() {
            self.scene.on_request(r);
        } else if let Some(s) = any.downcast_ref::<Schedule>() {
            self.scene.on_schedule(s);
        } else if let Some(t) = any.downcast_ref::<Telemetry>()
            && self.latency.has_sinks()
            && let Ok(text) = serde_json::to_vec(&latencies(t))
        {
            self.latency.log_with_meta(&text, PartialMetadata::with_log_time(log_ns));
        }
    }

    /// Log the scene if its period has passed.
    pub fn view(&mut self, log_ns: u64) {
        if log_ns < self.last_view_ns.saturating_add(VIEW_PERIOD_NS) {
            return;
        }
        self.last_view_ns = log_ns;
        if self.scene_channel.has_sinks() {
            let stamp = Timestamp::new((log_ns / 1_000_000_000) as u32, (log_ns % 1_000_000_000) as u32);
            self.scene_channel
                .log_with_meta(&self.scene.update(stamp), PartialMetadata::with_log_time(log_ns));
        }
    }

    /// What the source lost on `service` (None: it cannot tell); 0 until set.
    pub fn set_lost(&mut self, service: &str, lost: Option<u64>) {
        if let Some(t) = self.topics.get_mut(service) {
            t.lost = lost;
        }
    }

    /// Messages received and lost per topic so far.
    pub fn counts(&self) -> BTreeMap<String, (u64, Option<u64>)> {
        self.topics.iter().map(|(k, t)| ((*k).to_owned(), (t.received, t.lost))).collect()
    }

    /// A key/value for the counts metadata written at the end.
    pub fn note(&mut self, key: &str, value: String) {
        self.notes.insert(key.into(), value);
    }

    /// Write the counts into the file's metadata, close the file and stop
    /// the server. Returns the counts.
    pub fn finish(mut self) -> anyhow::Result<BTreeMap<String, (u64, Option<u64>)>> {
        let counts = self.counts();
        if let Some(out) = self.mcap.take() {
            let mut m = counts_metadata(&counts);
            m.extend(std::mem::take(&mut self.notes));
            out.close(m)?;
        }
        if let Some(ws) = self.ws.take() {
            ws.stop().wait_blocking();
        }
        Ok(counts)
    }

    /// Whether this segment has run its length (the first call starts it).
    pub fn segment_due(&mut self, log_ns: u64) -> bool {
        let Some(out) = &mut self.mcap else { return false };
        let Some(every) = out.every else { return false };
        if out.started_ns == 0 {
            out.started_ns = log_ns;
        }
        log_ns >= out.started_ns.saturating_add(every.as_nanos() as u64)
    }

    /// Close this segment with the counts so far (set the losses first,
    /// [`RigLog::set_lost`]) and start the next with the run's metadata and
    /// TOML. Nothing is logged in between (one thread logs), so no message
    /// falls between two files.
    pub fn next_segment(&mut self, log_ns: u64) -> anyhow::Result<()> {
        let Some(out) = self.mcap.take() else { return Ok(()) };
        let (first, n, every, info, config_text) =
            (out.first.clone(), out.segment + 1, out.every, out.info.clone(), out.config_text.clone());
        out.close(counts_metadata(&self.counts()))?;
        let mut next = McapOut::open(&self.ctx, &first, n, every, &info, config_text.as_deref())?;
        next.started_ns = log_ns;
        self.mcap = Some(next);
        Ok(())
    }

    /// The file being written now.
    pub fn current_file(&self) -> Option<PathBuf> {
        self.mcap.as_ref().map(|o| segment_path(&o.first, o.segment))
    }
}

/// Messages received and lost per topic, as the counts metadata says them.
fn counts_metadata(counts: &BTreeMap<String, (u64, Option<u64>)>) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let mut lost_total = 0;
    for (topic, (received, lost)) in counts {
        m.insert(format!("received {topic}"), received.to_string());
        m.insert(format!("lost {topic}"), lost.map_or_else(|| "unknown".into(), |n| n.to_string()));
        lost_total += lost.unwrap_or(0);
    }
    m.insert("lost_total".into(), lost_total.to_string());
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A topic for every service of the protocol, and none else: a service
    /// without one would be silently dropped by [`RigLog::log`].
    #[test]
    fn every_service_has_a_topic() -> anyhow::Result<()> {
        let log = RigLog::open(&LogOptions::default())?;
        let topics: Vec<String> = log.counts().into_keys().collect();
        let mut services: Vec<String> = service_names::ALL.iter().map(|s| (*s).to_owned()).collect();
        services.sort_unstable();
        assert_eq!(topics, services);
        log.finish()?;
        Ok(())
    }
}
