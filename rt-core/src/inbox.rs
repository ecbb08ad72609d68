//! Where the solver thread's messages come from: iceoryx2 in the real
//! process, an in-memory queue in lock-step runs. Either way a message is
//! copied into a preallocated buffer and handed to the solve stage.

use std::collections::VecDeque;

use ipc_types::{CoreCommand, ExplicitSchedule, ForceRequest, PartStates};

/// Which buffer `Inbox::next` filled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Inbound {
    PartStates,
    Request,
    Explicit,
    Command,
}

/// One buffer per message kind, allocated once.
#[derive(Debug)]
pub struct InboxBuffers {
    pub parts: Box<PartStates>,
    pub request: Box<ForceRequest>,
    pub explicit: Box<ExplicitSchedule>,
    pub command: CoreCommand,
    /// When the message reached the core (monotonic ns), if the inbox knows;
    /// 0: it arrived just now.
    pub received_ns: u64,
}

impl Default for InboxBuffers {
    fn default() -> Self {
        Self {
            parts: Box::new(PartStates::new()),
            request: Box::new(ForceRequest::new()),
            explicit: Box::new(ExplicitSchedule::new()),
            command: CoreCommand::new(0, 0, 0),
            received_ns: 0,
        }
    }
}

/// A source of inbound messages. `next` must not allocate or block.
pub trait Inbox {
    /// Copy the next pending message into `buf`; `None` when nothing waits.
    fn next(&mut self, buf: &mut InboxBuffers) -> Option<Inbound>;
}

/// In-memory inbox for lock-step runs and tests (allocates when pushed to,
/// never in `next`).
#[derive(Debug, Default)]
pub struct QueueInbox {
    queue: VecDeque<Message>,
}

#[derive(Debug)]
enum Message {
    Parts(Box<PartStates>),
    Request(Box<ForceRequest>),
    Explicit(Box<ExplicitSchedule>),
    Command(CoreCommand),
}

impl QueueInbox {
    pub fn push_parts(&mut self, m: &PartStates) {
        self.queue.push_back(Message::Parts(Box::new(*m)));
    }
    pub fn push_request(&mut self, m: &ForceRequest) {
        self.queue.push_back(Message::Request(Box::new(*m)));
    }
    pub fn push_explicit(&mut self, m: &ExplicitSchedule) {
        self.queue.push_back(Message::Explicit(Box::new(*m)));
    }
    pub fn push_command(&mut self, m: &CoreCommand) {
        self.queue.push_back(Message::Command(*m));
    }
}

impl Inbox for QueueInbox {
    fn next(&mut self, buf: &mut InboxBuffers) -> Option<Inbound> {
        // Dropping the popped Box frees; lock-step tests count allocations,
        // not frees.
        buf.received_ns = 0;
        Some(match self.queue.pop_front()? {
            Message::Parts(m) => {
                *buf.parts = *m;
                Inbound::PartStates
            }
            Message::Request(m) => {
                *buf.request = *m;
                Inbound::Request
            }
            Message::Explicit(m) => {
                *buf.explicit = *m;
                Inbound::Explicit
            }
            Message::Command(m) => {
                buf.command = m;
                Inbound::Command
            }
        })
    }
}

/// One inbound message and when the receiver got it, moved through a ring
/// by value.
#[derive(Debug, Clone, Copy)]
pub struct Received {
    pub msg: InboundMessage,
    pub at_ns: u64,
}

/// One inbound message.
#[derive(Debug, Clone, Copy)]
#[allow(clippy::large_enum_variant)] // fixed-size by design: the ring is preallocated
pub enum InboundMessage {
    Parts(PartStates),
    Request(ForceRequest),
    Explicit(ExplicitSchedule),
    Command(CoreCommand),
}

/// Ring capacity between the iceoryx2 receiver thread and the solver.
pub const INBOUND_RING: usize = 64;

/// The solver side of the receiver thread's ring: no iceoryx2 call, no
/// allocation. (iceoryx2 0.10 allocates inside `receive()` whenever a new
/// publisher connects, so `receive()` runs on a non-RT receiver thread.)
#[derive(Debug)]
pub struct RingInbox(pub rtrb::Consumer<Received>);

impl Inbox for RingInbox {
    fn next(&mut self, buf: &mut InboxBuffers) -> Option<Inbound> {
        let Received { msg, at_ns } = self.0.pop().ok()?;
        buf.received_ns = at_ns;
        Some(match msg {
            InboundMessage::Parts(m) => {
                *buf.parts = m;
                Inbound::PartStates
            }
            InboundMessage::Request(m) => {
                *buf.request = m;
                Inbound::Request
            }
            InboundMessage::Explicit(m) => {
                *buf.explicit = m;
                Inbound::Explicit
            }
            InboundMessage::Command(m) => {
                buf.command = m;
                Inbound::Command
            }
        })
    }
}

/// Move everything `source` has into `ring`; returns how many messages went
/// into the ring and how many were dropped because it was full (the solver
/// is a full ring behind).
pub fn forward<I: Inbox>(
    source: &mut I,
    buf: &mut InboxBuffers,
    ring: &mut rtrb::Producer<Received>,
) -> (u64, u64) {
    let (mut forwarded, mut dropped) = (0, 0);
    while let Some(kind) = source.next(buf) {
        let msg = match kind {
            Inbound::PartStates => InboundMessage::Parts(*buf.parts),
            Inbound::Request => InboundMessage::Request(*buf.request),
            Inbound::Explicit => InboundMessage::Explicit(*buf.explicit),
            Inbound::Command => InboundMessage::Command(buf.command),
        };
        if ring.push(Received { msg, at_ns: buf.received_ns }).is_err() {
            dropped += 1;
        } else {
            forwarded += 1;
        }
    }
    (forwarded, dropped)
}
