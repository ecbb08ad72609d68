//! The accessors every fixed-capacity message shares: its used entries (the
//! `count` clamped to the capacity, so a corrupt count never reads out of
//! bounds), their mutable view, and their number.

/// Inside a message's `impl`: `used_entries!(field, field_mut, Item,
/// CAPACITY);` defines `field()`, `field_mut()`, `len()` and `is_empty()`.
macro_rules! used_entries {
    ($field:ident, $field_mut:ident, $item:ty, $capacity:expr) => {
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
    };
}

pub(crate) use used_entries;
