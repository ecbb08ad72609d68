//! What every fixed-capacity message shares: its capacity and constructor,
//! its used entries (the `count` clamped to the capacity, so a corrupt count
//! never reads out of bounds), their mutable view, their number, appending
//! and clearing, and the header check on its version, count and stamp.

/// At module level: `counted_message!(Msg, entries / entries_mut: [Item;
/// CAPACITY], new { other_field: value, … });` defines `Msg::new()` (current
/// protocol version, count, seq and stamp 0, the other fields as given),
/// `Default`, `CAPACITY`, `entries()`, `entries_mut()`, `len()`,
/// `is_empty()`, `clear()`, `push()` and the crate's
/// `check_counted_header()`; with a trailing `own_push`, all but `push()`.
macro_rules! counted_message {
    ($msg:ident, $field:ident / $field_mut:ident: [$item:ty; $capacity:expr], new { $($extra:ident: $val:expr),* $(,)? }) => {
        $crate::counted_message::counted_message!(
            $msg, $field / $field_mut: [$item; $capacity], new { $($extra: $val),* }, own_push
        );

        impl $msg {
            /// Append one entry, or fail when the message is full.
            pub fn push(&mut self, item: $item) -> Result<(), $crate::CapacityError> {
                let n = $crate::validation::clamped_len(self.count, $capacity);
                let slot = self.$field.get_mut(n).ok_or($crate::CapacityError::Full { capacity: $capacity })?;
                *slot = item;
                self.count = n as u32 + 1;
                Ok(())
            }
        }
    };
    // A message whose `push` checks more than the capacity defines its own.
    ($msg:ident, $field:ident / $field_mut:ident: [$item:ty; $capacity:expr], new { $($extra:ident: $val:expr),* $(,)? }, own_push) => {
        impl $msg {
            pub const CAPACITY: usize = $capacity;

            #[doc = concat!(
                "Current protocol version; count, seq and stamp 0",
                $(", `", stringify!($extra), "` ", stringify!($val),)*
                "; no entries."
            )]
            pub const fn new() -> Self {
                Self {
                    protocol_version: $crate::PROTOCOL_VERSION,
                    count: 0,
                    seq: 0,
                    stamp_ns: 0,
                    $($extra: $val,)*
                    $field: [<$item>::ZERO; $capacity],
                }
            }

            /// Used entries; a corrupt `count` is clamped to the capacity.
            pub fn $field(&self) -> &[$item] {
                &self.$field[..$crate::validation::clamped_len(self.count, $capacity)]
            }

            /// Used entries, mutable; a corrupt `count` is clamped to the capacity.
            pub fn $field_mut(&mut self) -> &mut [$item] {
                let n = $crate::validation::clamped_len(self.count, $capacity);
                &mut self.$field[..n]
            }

            /// Number of used entries (`count` clamped to the capacity).
            pub fn len(&self) -> usize {
                $crate::validation::clamped_len(self.count, $capacity)
            }

            pub fn is_empty(&self) -> bool {
                self.len() == 0
            }

            /// Forget every entry (the entries keep their old bytes).
            pub fn clear(&mut self) {
                self.count = 0;
            }

            /// Protocol version, count against the capacity, and stamp.
            fn check_counted_header(
                &self,
                old: $crate::header::OldStamps,
                limits: &$crate::validation::ValidationLimits,
            ) -> Result<(), $crate::header::HeaderError> {
                let count = Some((self.count, $capacity));
                $crate::header::check_header(self.protocol_version, count, self.stamp_ns, old, limits)
            }
        }

        impl Default for $msg {
            fn default() -> Self {
                Self::new()
            }
        }
    };
}

pub(crate) use counted_message;
