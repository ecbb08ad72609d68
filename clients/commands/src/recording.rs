//! A UPM recording (the MCAP file upm-recorder writes), opened and checked:
//! an unreadable, truncated, corrupt or foreign file, or one from another
//! protocol version, is a one-line error naming what is wrong.

use std::collections::BTreeMap;
use std::path::Path;

use ipc_types::{PROTOCOL_VERSION, WireMessage};
use serde_json::{Value, json};
use upm_recorder::{CONFIG_ATTACHMENT, COUNTS_METADATA, RAW_ENCODING, RUN_METADATA};

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    #[error("{0}: cannot read: {1}")]
    Read(String, std::io::Error),
    #[error("{0}: not an MCAP file (it does not start with the MCAP magic)")]
    NotMcap(String),
    #[error("{0}: truncated or corrupt: {1} (a recorder that was killed leaves no summary)")]
    Damaged(String, String),
    #[error("{0}: an MCAP file, but not a UPM recording (no \"{RUN_METADATA}\" metadata)")]
    Foreign(String),
    #[error(
        "{path}: recorded with protocol version {found}; this upm speaks protocol version {PROTOCOL_VERSION}"
    )]
    Version { path: String, found: String },
    #[error("{path}: channel {topic} carries {found}; this upm reads {expected}")]
    TypeName { path: String, topic: String, found: String, expected: &'static str },
    #[error("{0}: no {CONFIG_ATTACHMENT} attached (the rig's config, which replay needs)")]
    NoConfig(String),
    #[error("{path}: message {index} on {topic}: {why}")]
    Message { path: String, index: u64, topic: String, why: String },
}

/// One raw message of the recording.
#[derive(Debug, Clone, Copy)]
pub struct RawMessage<'a> {
    pub topic: &'a str,
    /// Unix ns when the recorder received it.
    pub log_time: u64,
    pub bytes: &'a [u8],
}

/// A checked recording, in memory.
#[derive(Debug)]
pub struct Recording {
    pub shown: String,
    bytes: memmap2::Mmap,
    /// The run metadata (protocol version, prefix, scenario, seed, clocks).
    pub run: BTreeMap<String, String>,
    /// Received and lost per topic, as the recorder counted them.
    pub counts: BTreeMap<String, String>,
    pub config_text: Option<String>,
    pub message_count: u64,
    /// First and last log time (Unix ns).
    pub span_ns: (u64, u64),
    /// Raw topic → type name.
    pub topics: BTreeMap<String, String>,
}

impl Recording {
    pub fn open(path: &Path) -> Result<Self, RecordingError> {
        let shown = path.display().to_string();
        let read = |e| RecordingError::Read(shown.clone(), e);
        let file = std::fs::File::open(path).map_err(read)?;
        // SAFETY: a recording is written once and never changed after the
        // recorder closes it (it never opens an existing file); a file
        // shortened under us would end the process with SIGBUS, as any
        // mapped reader.
        let bytes = unsafe { memmap2::Mmap::map(&file) }.map_err(read)?;
        if !bytes.starts_with(MAGIC) {
            return Err(RecordingError::NotMcap(shown));
        }
        let damaged = |e: mcap::McapError| RecordingError::Damaged(shown.clone(), e.to_string());
        let summary = mcap::Summary::read(&bytes).map_err(damaged)?.ok_or_else(|| {
            RecordingError::Damaged(shown.clone(), "the file has no summary section".into())
        })?;
        let mut run = None;
        let mut counts = BTreeMap::new();
        for index in &summary.metadata_indexes {
            let m = mcap::read::metadata(&bytes, index).map_err(damaged)?;
            match m.name.as_str() {
                RUN_METADATA => run = Some(m.metadata),
                COUNTS_METADATA => counts = m.metadata,
                _ => {}
            }
        }
        let run = run.ok_or_else(|| RecordingError::Foreign(shown.clone()))?;
        let version = run.get("protocol_version").cloned().unwrap_or_else(|| "(none)".into());
        if version != PROTOCOL_VERSION.to_string() {
            return Err(RecordingError::Version { path: shown, found: version });
        }
        let mut config_text = None;
        for index in &summary.attachment_indexes {
            let a = mcap::read::attachment(&bytes, index).map_err(damaged)?;
            if a.name == CONFIG_ATTACHMENT {
                config_text = Some(String::from_utf8_lossy(&a.data).into_owned());
            }
        }
        let topics = summary
            .channels
            .values()
            .filter(|c| c.message_encoding == RAW_ENCODING)
            .map(|c| (c.topic.clone(), c.schema.as_ref().map_or_else(String::new, |s| s.name.clone())))
            .collect();
        let stats = summary.stats.as_ref();
        Ok(Self {
            message_count: stats.map_or(0, |s| s.message_count),
            span_ns: stats.map_or((0, 0), |s| (s.message_start_time, s.message_end_time)),
            shown,
            bytes,
            run,
            counts,
            config_text,
            topics,
        })
    }

    /// The recorded rig config.
    pub fn config_text(&self) -> Result<&str, RecordingError> {
        self.config_text.as_deref().ok_or_else(|| RecordingError::NoConfig(self.shown.clone()))
    }

    /// Messages the recorder counted as lost (seq gaps), all topics.
    pub fn lost_total(&self) -> u64 {
        self.counts.get("lost_total").and_then(|v| v.parse().ok()).unwrap_or(0)
    }

    /// Check that `topic` carries `T` (if recorded at all).
    pub fn check_type<T: WireMessage>(&self, topic: &str) -> Result<(), RecordingError> {
        match self.topics.get(topic) {
            Some(found) if found != T::wire_type_name() => Err(RecordingError::TypeName {
                path: self.shown.clone(),
                topic: topic.into(),
                found: found.clone(),
                expected: T::wire_type_name(),
            }),
            _ => Ok(()),
        }
    }

    /// Every raw message in log-time order.
    pub fn for_each_raw(
        &self,
        mut f: impl FnMut(u64, RawMessage<'_>) -> Result<(), RecordingError>,
    ) -> Result<(), RecordingError> {
        let stream = mcap::MessageStream::new(&self.bytes)
            .map_err(|e| RecordingError::Damaged(self.shown.clone(), e.to_string()))?;
        for (index, m) in (0u64..).zip(stream) {
            let m = m.map_err(|e| {
                RecordingError::Damaged(self.shown.clone(), format!("after {index} messages: {e}"))
            })?;
            if m.channel.message_encoding == RAW_ENCODING {
                f(index, RawMessage { topic: &m.channel.topic, log_time: m.log_time, bytes: &m.data })?;
            }
        }
        Ok(())
    }

    /// `bytes` as a `T` (exactly its size), or an error naming the message.
    pub fn decode<T: WireMessage>(&self, index: u64, m: RawMessage<'_>) -> Result<T, RecordingError> {
        T::from_bytes(m.bytes).map_err(|e| RecordingError::Message {
            path: self.shown.clone(),
            index,
            topic: m.topic.into(),
            why: e.to_string(),
        })
    }
}

/// What metrics.json says about a run's recording.
pub fn summary_json(path: &Path, recorder_exit_ok: bool) -> Value {
    // The recorder's segments follow the first file (`run.001.mcap`, …);
    // the last one's counts cover the whole run.
    let mut files = vec![path.to_path_buf()];
    files.extend((1..).map(|n| upm_recorder::segment_path(path, n)).take_while(|p| p.is_file()));
    let bytes: u64 = files.iter().map(|f| std::fs::metadata(f).map_or(0, |m| m.len())).sum();
    let (mut messages, mut lost) = (0, 0);
    for f in &files {
        match Recording::open(f) {
            Ok(r) => (messages, lost) = (messages + r.message_count, r.lost_total()),
            Err(e) => {
                return json!({ "file": path.display().to_string(), "bytes": bytes, "error": e.to_string(),
                               "recorder_exit_ok": recorder_exit_ok });
            }
        }
    }
    json!({
        "file": path.display().to_string(),
        "segments": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
        "bytes": bytes,
        "messages": messages,
        "lost": lost,
        "recorder_exit_ok": recorder_exit_ok,
    })
}
