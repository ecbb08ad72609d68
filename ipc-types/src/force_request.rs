//! ForceRequest: planner → core, the average force (and optional curl) each
//! part should feel during the next cycles.

use crate::header::{HeaderError, OldStamps};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::capacity::{CapacityError, MAX_CURLS, MAX_PARTS};
use crate::reject_reason::RejectReason;
use crate::validation::{ValidationLimits, first_non_finite, is_flag};

/// What one part should feel. A curl is optional per entry (`curl_flag`),
/// at most [`MAX_CURLS`] entries of a request may set it; the curl point is
/// the part's position. `force_flag` = 0 leaves the part's force free (only
/// its curl is constrained), as in `upm solve`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::ForceEntry.v6"))]
pub struct ForceEntry {
    /// Id of a part in the core's latest [`crate::PartStates`].
    pub part_id: u32,
    /// 1: (fx, fy) is requested; 0: the force is unconstrained.
    pub force_flag: u32,
    /// 1: `curl` is requested; 0: the curl is unconstrained.
    pub curl_flag: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// Desired average force (N).
    pub fx: f64,
    pub fy: f64,
    /// Desired curl of the friction field at the part (N/m).
    pub curl: f64,
}

const _: () = assert!(size_of::<ForceEntry>() == 4 * 4 + 3 * 8);

impl ForceEntry {
    pub const ZERO: Self =
        Self { part_id: 0, force_flag: 0, curl_flag: 0, reserved: 0, fx: 0.0, fy: 0.0, curl: 0.0 };

    /// Request force `f` = (fx, fy) on a part, curl free.
    pub const fn force(part_id: u32, f: [f64; 2]) -> Self {
        Self { part_id, force_flag: 1, fx: f[0], fy: f[1], ..Self::ZERO }
    }

    /// Request only a curl at a part, force free.
    pub const fn curl(part_id: u32, curl: f64) -> Self {
        Self { part_id, curl_flag: 1, curl, ..Self::ZERO }
    }

    /// Request both a force and a curl at a part.
    pub const fn force_and_curl(part_id: u32, f: [f64; 2], curl: f64) -> Self {
        Self { part_id, force_flag: 1, curl_flag: 1, reserved: 0, fx: f[0], fy: f[1], curl }
    }

    /// Requested force, if `force_flag` is exactly 1.
    pub const fn requested_force(&self) -> Option<[f64; 2]> {
        if self.force_flag == 1 { Some([self.fx, self.fy]) } else { None }
    }

    /// Requested curl, if `curl_flag` is exactly 1.
    pub const fn requested_curl(&self) -> Option<f64> {
        if self.curl_flag == 1 { Some(self.curl) } else { None }
    }
}

/// Planner → core: desired forces for up to [`MAX_PARTS`] parts.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::ForceRequest.v6"))]
pub struct ForceRequest {
    pub protocol_version: u32,
    /// Number of used entries of `entries`.
    pub count: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when the planner computed the request.
    pub stamp_ns: u64,
    /// CLOCK_MONOTONIC ns after which the request is stale (the core holds).
    pub deadline_ns: u64,
    pub entries: [ForceEntry; MAX_PARTS],
}

const _: () = assert!(size_of::<ForceRequest>() == 4 + 4 + 3 * 8 + MAX_PARTS * size_of::<ForceEntry>());

/// Why a [`ForceRequest`] was rejected. Indices refer to `entries`.
///
/// Whether `part_id` names a part the core currently sees is checked by the
/// core against its latest [`crate::PartStates`], not here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForceRequestError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    DeadlineBeforeStamp {
        deadline_ns: u64,
        stamp_ns: u64,
    },
    NotAFlag {
        index: usize,
        field: &'static str,
        value: u32,
    },
    NonFinite {
        index: usize,
        field: &'static str,
    },
    /// Neither a force nor a curl is requested.
    ConstrainsNothing {
        index: usize,
    },
    /// This entry sets the (MAX_CURLS + 1)-th curl.
    TooManyCurls {
        index: usize,
    },
    DuplicatePartId {
        index: usize,
        first_index: usize,
        part_id: u32,
    },
}

impl fmt::Display for ForceRequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("force_request", f),
            Self::DeadlineBeforeStamp { deadline_ns, stamp_ns } => {
                write!(f, "force_request.deadline_ns {deadline_ns} is before stamp_ns {stamp_ns}")
            }
            Self::NotAFlag { index, field, value } => {
                write!(f, "force_request.entries[{index}].{field} is {value}, expected 0 or 1")
            }
            Self::NonFinite { index, field } => {
                write!(f, "force_request.entries[{index}].{field} is not finite")
            }
            Self::ConstrainsNothing { index } => {
                write!(f, "force_request.entries[{index}] requests neither a force nor a curl")
            }
            Self::TooManyCurls { index } => {
                write!(f, "force_request.entries[{index}].curl_flag exceeds the {MAX_CURLS} curls allowed")
            }
            Self::DuplicatePartId { index, first_index, part_id } => {
                write!(
                    f,
                    "force_request.entries[{index}].part_id {part_id} duplicates entries[{first_index}]"
                )
            }
        }
    }
}

impl core::error::Error for ForceRequestError {}

impl ForceRequestError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::DeadlineBeforeStamp { .. } => RejectReason::DeadlineBeforeStamp,
            Self::NotAFlag { .. } => RejectReason::NotAFlag,
            Self::NonFinite { .. } => RejectReason::NonFinite,
            Self::ConstrainsNothing { .. } => RejectReason::ConstrainsNothing,
            Self::TooManyCurls { .. } => RejectReason::TooManyCurls,
            Self::DuplicatePartId { .. } => RejectReason::DuplicateId,
        }
    }
}

crate::counted_message::counted_message!(
    ForceRequest,
    entries / entries_mut: [ForceEntry; MAX_PARTS],
    new { deadline_ns: 0 },
    own_push
);

impl ForceRequest {
    /// Number of used entries whose `curl_flag` is 1.
    pub fn curl_count(&self) -> usize {
        self.entries().iter().filter(|e| e.curl_flag == 1).count()
    }

    /// Append one entry, or fail when the entries or the curls are full.
    pub fn push(&mut self, entry: ForceEntry) -> Result<(), CapacityError> {
        let n = self.count as usize;
        if n >= MAX_PARTS {
            return Err(CapacityError::Full { capacity: MAX_PARTS });
        }
        if entry.curl_flag == 1 && self.curl_count() >= MAX_CURLS {
            return Err(CapacityError::CurlsFull { capacity: MAX_CURLS });
        }
        self.entries[n] = entry;
        self.count += 1;
        Ok(())
    }

    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, O(count²) for the duplicate-id check.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), ForceRequestError> {
        self.check_counted_header(OldStamps::Reject, limits).map_err(ForceRequestError::Header)?;
        if self.deadline_ns < self.stamp_ns {
            return Err(ForceRequestError::DeadlineBeforeStamp {
                deadline_ns: self.deadline_ns,
                stamp_ns: self.stamp_ns,
            });
        }
        let entries = self.entries();
        let mut curls = 0usize;
        for (index, e) in entries.iter().enumerate() {
            if !is_flag(e.force_flag) {
                return Err(ForceRequestError::NotAFlag { index, field: "force_flag", value: e.force_flag });
            }
            if !is_flag(e.curl_flag) {
                return Err(ForceRequestError::NotAFlag { index, field: "curl_flag", value: e.curl_flag });
            }
            if let Some(field) = first_non_finite([("fx", e.fx), ("fy", e.fy), ("curl", e.curl)]) {
                return Err(ForceRequestError::NonFinite { index, field });
            }
            if e.force_flag == 0 && e.curl_flag == 0 {
                return Err(ForceRequestError::ConstrainsNothing { index });
            }
            if e.curl_flag == 1 {
                curls += 1;
                if curls > MAX_CURLS {
                    return Err(ForceRequestError::TooManyCurls { index });
                }
            }
            if let Some(first_index) = entries[..index].iter().position(|q| q.part_id == e.part_id) {
                return Err(ForceRequestError::DuplicatePartId { index, first_index, part_id: e.part_id });
            }
        }
        Ok(())
    }
}
