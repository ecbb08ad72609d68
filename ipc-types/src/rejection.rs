//! Rejection: core → all, on `upm/rejection`. Every inbound message the
//! core refuses is answered here with its kind, `seq`, stamp, the reason
//! code and a one-line text naming the field, so a client learns why, not
//! only that telemetry's counter rose. Every subscriber receives every
//! rejection: a client keeps those whose kind, `seq` and
//! `message_stamp_ns` are those of a message it sent.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::health::{HEALTH_DETAIL_BYTES, detail_str};
use crate::reject_reason::RejectReason;

crate::wire_code::wire_code! {
    /// Which kind of message a [`Rejection`] answers; its name is the
    /// message's service without `upm/`.
    pub enum RejectedKind {
        PartStates = 0 => "part_states",
        ForceRequest = 1 => "force_request",
        ExplicitSchedule = 2 => "explicit_schedule",
        CoreCommand = 3 => "core_command",
        PickCommand = 4 => "pick",
        RecipeCommand = 5 => "recipe",
    }
}

impl RejectedKind {
    /// The service the rejected message came on.
    pub const fn service(self) -> &'static str {
        match self {
            Self::PartStates => crate::service_names::PART_STATES,
            Self::ForceRequest => crate::service_names::FORCE_REQUEST,
            Self::ExplicitSchedule => crate::service_names::EXPLICIT_SCHEDULE,
            Self::CoreCommand => crate::service_names::CORE_COMMAND,
            Self::PickCommand => crate::service_names::PICK,
            Self::RecipeCommand => crate::service_names::RECIPE,
        }
    }
}

/// Core → all: one refused message.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::Rejection.v6"))]
pub struct Rejection {
    pub protocol_version: u32,
    /// [`RejectedKind`] code of the refused message.
    pub kind: u32,
    /// The refused message's `seq` (as sent, whatever it was).
    pub seq: u64,
    /// The refused message's `stamp_ns` (as sent).
    pub message_stamp_ns: u64,
    /// CLOCK_MONOTONIC ns when the core refused it.
    pub stamp_ns: u64,
    /// `seq` and `stamp_ns` of the newest part states the core had
    /// accepted then (0 and 0: none): what a request was checked against.
    pub parts_seq: u64,
    pub parts_stamp_ns: u64,
    /// [`RejectReason`] code.
    pub reason: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// Why, one line naming the field, UTF-8, NUL-padded.
    pub detail: [u8; HEALTH_DETAIL_BYTES],
}

const _: () = assert!(size_of::<Rejection>() == 4 + 4 + 5 * 8 + 4 + 4 + HEALTH_DETAIL_BYTES);

impl Rejection {
    /// A rejection of a `kind` message with `seq` and `message_stamp_ns`,
    /// refused at `stamp_ns` for `reason`; `detail` is written straight into
    /// the message (cut to fit; no allocation).
    pub fn new(
        kind: RejectedKind,
        seq: u64,
        message_stamp_ns: u64,
        stamp_ns: u64,
        reason: RejectReason,
        detail: fmt::Arguments<'_>,
    ) -> Self {
        let mut text = crate::health::DetailText::new();
        let _ = fmt::write(&mut text, detail);
        Self {
            protocol_version: PROTOCOL_VERSION,
            kind: kind.code(),
            seq,
            message_stamp_ns,
            stamp_ns,
            parts_seq: 0,
            parts_stamp_ns: 0,
            reason: reason.index() as u32,
            reserved: 0,
            detail: text.bytes,
        }
    }

    pub fn kind(&self) -> Option<RejectedKind> {
        RejectedKind::from_code(self.kind)
    }

    pub fn reason(&self) -> Option<RejectReason> {
        RejectReason::ALL.get(self.reason as usize).copied()
    }

    /// The text, up to the first NUL (invalid UTF-8 is cut).
    pub fn detail_str(&self) -> &str {
        detail_str(&self.detail)
    }
}

impl fmt::Display for Rejection {
    /// `force_request seq 42 rejected: wrong_protocol_version (force_request.protocol_version is 2, expected 5)`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = self.kind().map_or("unknown", RejectedKind::as_str);
        let reason = self.reason().map_or("unknown", RejectReason::as_str);
        write!(f, "{kind} seq {} rejected: {reason} ({})", self.seq, self.detail_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kind_is_named_after_its_service() {
        for k in RejectedKind::ALL {
            assert_eq!(k.service(), format!("upm/{}", k.as_str()));
        }
    }
}
