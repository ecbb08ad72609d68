//! RecipeCommand: line process → core and planner, "load this recipe"
//! (a changeover). The recipe is named by its file's absolute path. The
//! line sends it on `upm/recipe`; a core running a feed cell switches and
//! announces the recipe it runs on `upm/recipe/active` (history 1), which
//! the planner follows.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::header::{HeaderError, OldStamps, check_header};
use crate::reject_reason::RejectReason;
use crate::validation::ValidationLimits;

/// Capacity of the field `RecipeCommand.path` in bytes.
pub const RECIPE_PATH_BYTES: usize = 240;

/// Line process → core (`upm/recipe`): load a recipe; core → all
/// (`upm/recipe/active`): the recipe the feed cell runs.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::RecipeCommand.v6"))]
pub struct RecipeCommand {
    pub protocol_version: u32,
    /// Used bytes of `path`.
    pub path_len: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when it was sent.
    pub stamp_ns: u64,
    /// The recipe file: an absolute path, UTF-8, `path_len` bytes used, the rest 0.
    pub path: [u8; RECIPE_PATH_BYTES],
}

const _: () = assert!(size_of::<RecipeCommand>() == 4 + 4 + 8 + 8 + RECIPE_PATH_BYTES);

/// Why a [`RecipeCommand`] was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RecipeCommandError {
    /// Protocol version or stamp.
    Header(HeaderError),
    /// `path_len` (or the path given to [`RecipeCommand::new`]) exceeds
    /// [`RECIPE_PATH_BYTES`].
    PathTooLong { len: u32 },
    /// The used bytes of `path` are not UTF-8.
    NotUtf8,
    /// The path does not start with `/` (an empty path included).
    NotAbsolute,
}

impl fmt::Display for RecipeCommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("recipe_command", f),
            Self::PathTooLong { len } => {
                write!(f, "recipe_command.path_len {len} exceeds the capacity {RECIPE_PATH_BYTES}")
            }
            Self::NotUtf8 => f.write_str("recipe_command.path is not UTF-8"),
            Self::NotAbsolute => f.write_str("recipe_command.path is not absolute: it must start with '/'"),
        }
    }
}

impl core::error::Error for RecipeCommandError {}

impl RecipeCommandError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::PathTooLong { .. } => RejectReason::CountExceedsCapacity,
            Self::NotUtf8 | Self::NotAbsolute => RejectReason::BadPath,
        }
    }
}

impl RecipeCommand {
    /// A command to load the recipe at `path`; refused if `path` is longer
    /// than [`RECIPE_PATH_BYTES`] or not absolute.
    pub fn new(path: &str, seq: u64, stamp_ns: u64) -> Result<Self, RecipeCommandError> {
        let bytes = path.as_bytes();
        if bytes.len() > RECIPE_PATH_BYTES {
            return Err(RecipeCommandError::PathTooLong {
                len: u32::try_from(bytes.len()).unwrap_or(u32::MAX),
            });
        }
        if !path.starts_with('/') {
            return Err(RecipeCommandError::NotAbsolute);
        }
        let mut m = Self {
            protocol_version: PROTOCOL_VERSION,
            path_len: bytes.len() as u32,
            seq,
            stamp_ns,
            path: [0; RECIPE_PATH_BYTES],
        };
        m.path[..bytes.len()].copy_from_slice(bytes);
        Ok(m)
    }

    /// The used bytes of `path` as text: `path_len` within the capacity and
    /// UTF-8 (whether it is absolute is [`Self::validate`]'s to say).
    pub fn path(&self) -> Result<&str, RecipeCommandError> {
        let used = self
            .path
            .get(..self.path_len as usize)
            .ok_or(RecipeCommandError::PathTooLong { len: self.path_len })?;
        core::str::from_utf8(used).map_err(|_| RecipeCommandError::NotUtf8)
    }

    /// Check the whole message: the header (version, stamp not in the
    /// future, not stale), then `path_len`, UTF-8, a leading `/`.
    /// Allocation-free. Whether the file exists and is a recipe is the
    /// receiver's to find out.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), RecipeCommandError> {
        check_header(self.protocol_version, None, self.stamp_ns, OldStamps::Reject, limits)
            .map_err(RecipeCommandError::Header)?;
        if !self.path()?.starts_with('/') {
            return Err(RecipeCommandError::NotAbsolute);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recipe_is_an_absolute_utf8_path_within_the_capacity() {
        let limits = ValidationLimits::new([1.0, 1.0], 1_000);
        let m = RecipeCommand::new("/srv/recipes/gears.toml", 1, 1_000).expect("absolute, short");
        assert_eq!((m.path_len, m.path()), (23, Ok("/srv/recipes/gears.toml")));
        assert!(m.path[23..].iter().all(|&b| b == 0), "the rest is 0");
        assert_eq!(m.validate(&limits), Ok(()));

        let longest = format!("/{}", "é".repeat((RECIPE_PATH_BYTES - 1) / 2));
        assert_eq!(longest.len(), RECIPE_PATH_BYTES - 1);
        assert_eq!(RecipeCommand::new(&longest, 1, 1_000).map(|m| m.validate(&limits)), Ok(Ok(())));
        let full = format!("/{}", "a".repeat(RECIPE_PATH_BYTES - 1));
        assert_eq!(RecipeCommand::new(&full, 1, 1_000).map(|m| m.path_len), Ok(240));
        let over = format!("/{}", "a".repeat(RECIPE_PATH_BYTES));
        assert_eq!(RecipeCommand::new(&over, 1, 1_000), Err(RecipeCommandError::PathTooLong { len: 241 }));
        assert_eq!(RecipeCommand::new("gears.toml", 1, 1_000), Err(RecipeCommandError::NotAbsolute));
        assert_eq!(RecipeCommand::new("", 1, 1_000), Err(RecipeCommandError::NotAbsolute));

        let mut bad = m;
        bad.path_len = RECIPE_PATH_BYTES as u32 + 1;
        assert_eq!(bad.path(), Err(RecipeCommandError::PathTooLong { len: 241 }));
        assert_eq!(bad.validate(&limits), Err(RecipeCommandError::PathTooLong { len: 241 }));
        let mut bad = m;
        bad.path[1] = 0xFF;
        assert_eq!(bad.validate(&limits), Err(RecipeCommandError::NotUtf8));
        let mut bad = m;
        bad.path[0] = b's';
        assert_eq!(bad.path(), Ok("ssrv/recipes/gears.toml"));
        assert_eq!(bad.validate(&limits), Err(RecipeCommandError::NotAbsolute));
        bad.path_len = 0;
        assert_eq!(bad.validate(&limits), Err(RecipeCommandError::NotAbsolute), "an empty path");
        let mut old = m;
        old.protocol_version = 5;
        assert!(matches!(old.validate(&limits), Err(RecipeCommandError::Header(_))));
    }

    #[test]
    fn each_error_is_one_line_naming_the_field_and_counted() {
        let cases = [
            (
                RecipeCommandError::PathTooLong { len: 300 },
                RejectReason::CountExceedsCapacity,
                "path_len 300",
            ),
            (RecipeCommandError::NotUtf8, RejectReason::BadPath, "path is not UTF-8"),
            (RecipeCommandError::NotAbsolute, RejectReason::BadPath, "path is not absolute"),
        ];
        for (e, reason, text) in cases {
            assert_eq!(e.reason(), reason, "{e:?}");
            let line = e.to_string();
            assert!(line.starts_with(&format!("recipe_command.{text}")) && !line.contains('\n'), "{line}");
        }
    }
}
