//! The accessors every fixed-capacity message shares: its used entries (the
//! `count` clamped to the capacity, so a corrupt count never reads out of
//! bounds), their mutable view, their number, and appending and clearing.

/// Inside a message's `impl`: `used_entries!(field, field_mut, Item,
/// CAPACITY);` defines `field()`, `field_mut()`, `len()`, `is_empty()`,
/// `clear()` and `push()`; with a trailing `own_push`, all but `push()`.
macro_rules! used_entries {
    ($field:ident, $field_mut:ident, $item:ty, $capacity:expr) => {
        $crate::used_entries::used_entries!($field, $field_mut, $item, $capacity, own_push);

        /// Append one entry, or fail when the message is full.
        pub fn push(&mut self, item: $item) -> Result<(), $crate::CapacityError> {
            let n = $crate::validation::clamped_len(self.count, $capacity);
            let slot = self.$field.get_mut(n).ok_or($crate::CapacityError::Full { capacity: $capacity })?;
            *slot = item;
            self.count = n as u32 + 1;
            Ok(())
        }
    };
    // A message whose `push` checks more than the capacity defines its own.
    ($field:ident, $field_mut:ident, $item:ty, $capacity:expr, own_push) => {
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
    };
}

pub(crate) use used_entries;
