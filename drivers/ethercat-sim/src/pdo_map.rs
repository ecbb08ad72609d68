//! A drive's PDO mapping and its assignment to a SyncManager, as a
//! MainDevice rewrites them by SDO in PRE-OP (CiA 301 / ETG.1000.6):
//! the mapping object (0x1600 outputs, 0x1A00 inputs) lists entries
//! `index << 16 | subindex << 8 | bits`, changed only while its count
//! (sub 0) is 0 and checked against what the drive can map when the count
//! is written; the assignment (0x1C12 / 0x1C13) names the one mapping
//! object in use (sub 1) and is on while its count is 1. The process
//! image is the assigned entries, packed little-endian in order.

use crate::abort;

/// Entries a mapping object holds at most.
pub const MAX_ENTRIES: usize = 8;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PdoMap {
    /// The mapping object (0x1600 or 0x1A00).
    pub object: u16,
    entries: [u32; MAX_ENTRIES],
    count: u8,
    /// The assignment's count (0x1C1x sub 0): 1 = this mapping in use.
    assigned: u8,
    /// What the drive can map here.
    mappable: [u32; MAX_ENTRIES],
    mappable_count: u8,
}

fn bits(entry: u32) -> usize {
    (entry & 0xFF) as usize
}

impl PdoMap {
    /// `object` mapping `entries` (assigned); the drive can map exactly
    /// `mappable` (at most [`MAX_ENTRIES`] of each are kept).
    pub fn new(object: u16, entries: &[u32], mappable: &[u32]) -> Self {
        let mut m = Self {
            object,
            entries: [0; MAX_ENTRIES],
            count: entries.len().min(MAX_ENTRIES) as u8,
            assigned: 1,
            mappable: [0; MAX_ENTRIES],
            mappable_count: mappable.len().min(MAX_ENTRIES) as u8,
        };
        m.entries[..usize::from(m.count)].copy_from_slice(&entries[..usize::from(m.count)]);
        m.mappable[..usize::from(m.mappable_count)]
            .copy_from_slice(&mappable[..usize::from(m.mappable_count)]);
        m
    }

    /// The entries in the process image (none while unassigned).
    pub fn active(&self) -> &[u32] {
        if self.assigned == 1 { &self.entries[..usize::from(self.count)] } else { &[] }
    }

    /// Bytes of the process image.
    pub fn bytes(&self) -> usize {
        self.active().iter().map(|e| bits(*e)).sum::<usize>() / 8
    }

    /// Where `index` sits in the image (byte offset, bytes), if mapped.
    pub fn find(&self, index: u16) -> Option<(usize, usize)> {
        let mut at = 0;
        for e in self.active() {
            if (e >> 16) as u16 == index {
                return Some((at, bits(*e) / 8));
            }
            at += bits(*e) / 8;
        }
        None
    }

    /// SDO upload of the mapping object: (value, size in bytes).
    pub fn read_mapping(&self, sub: u8) -> Result<(u32, u8), u32> {
        match sub {
            0 => Ok((u32::from(self.count), 1)),
            s if usize::from(s) <= MAX_ENTRIES => Ok((self.entries[usize::from(s) - 1], 4)),
            _ => Err(abort::NO_SUBINDEX),
        }
    }

    /// SDO download to the mapping object.
    pub fn write_mapping(&mut self, sub: u8, value: u32) -> Result<(), u32> {
        match sub {
            0 => {
                let n = usize::try_from(value).unwrap_or(usize::MAX);
                if n > MAX_ENTRIES {
                    return Err(abort::VALUE_TOO_HIGH);
                }
                let mappable = &self.mappable[..usize::from(self.mappable_count)];
                if !self.entries[..n].iter().all(|e| mappable.contains(e)) {
                    return Err(abort::CANNOT_MAP);
                }
                self.count = n as u8;
                Ok(())
            }
            s if usize::from(s) <= MAX_ENTRIES => {
                if self.count != 0 {
                    // Entries change only while the mapping is off.
                    return Err(abort::DEVICE_STATE);
                }
                self.entries[usize::from(s) - 1] = value;
                Ok(())
            }
            _ => Err(abort::NO_SUBINDEX),
        }
    }

    /// SDO upload of the assignment object.
    pub fn read_assignment(&self, sub: u8) -> Result<(u32, u8), u32> {
        match sub {
            0 => Ok((u32::from(self.assigned), 1)),
            1 => Ok((u32::from(self.object), 2)),
            _ => Err(abort::NO_SUBINDEX),
        }
    }

    /// SDO download to the assignment object: sub 1 may only name this
    /// drive's one mapping object.
    pub fn write_assignment(&mut self, sub: u8, value: u32) -> Result<(), u32> {
        match sub {
            0 if value <= 1 => {
                self.assigned = value as u8;
                Ok(())
            }
            0 => Err(abort::VALUE_TOO_HIGH),
            1 if self.assigned != 0 => Err(abort::DEVICE_STATE),
            1 if value == u32::from(self.object) => Ok(()),
            1 => Err(abort::VALUE_INVALID),
            _ => Err(abort::NO_SUBINDEX),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CAN: [u32; 3] = [0x6040_0010, 0x607A_0020, 0x6060_0008];

    #[test]
    fn remapping_goes_through_a_zero_count_and_checks_every_entry() {
        let mut m = PdoMap::new(0x1600, &CAN[..2], &CAN);
        assert_eq!((m.bytes(), m.find(0x607A)), (6, Some((2, 4))));
        assert_eq!(m.write_mapping(3, CAN[2]), Err(abort::DEVICE_STATE), "count not 0");
        assert_eq!(m.write_mapping(0, 0), Ok(()));
        assert_eq!(m.bytes(), 0);
        assert_eq!(m.write_mapping(3, CAN[2]), Ok(()));
        assert_eq!(m.write_mapping(0, 3), Ok(()));
        assert_eq!((m.bytes(), m.find(0x6060)), (7, Some((6, 1))));
        // Not mappable here (0x60B2), or too many.
        assert_eq!(m.write_mapping(0, 0), Ok(()));
        assert_eq!(m.write_mapping(1, 0x60B2_0010), Ok(()));
        assert_eq!(m.write_mapping(0, 3), Err(abort::CANNOT_MAP));
        assert_eq!(m.write_mapping(0, 9), Err(abort::VALUE_TOO_HIGH));
        assert_eq!(m.write_mapping(9, 0), Err(abort::NO_SUBINDEX));
    }

    #[test]
    fn the_assignment_names_the_one_mapping_object_while_off() {
        let mut m = PdoMap::new(0x1A00, &CAN, &CAN);
        assert_eq!(m.write_assignment(1, 0x1A00), Err(abort::DEVICE_STATE));
        assert_eq!(m.write_assignment(0, 0), Ok(()));
        assert_eq!(m.bytes(), 0, "unassigned: no image");
        assert_eq!(m.write_assignment(1, 0x1A01), Err(abort::VALUE_INVALID));
        assert_eq!(m.write_assignment(1, 0x1A00), Ok(()));
        assert_eq!(m.write_assignment(0, 2), Err(abort::VALUE_TOO_HIGH));
        assert_eq!(m.write_assignment(0, 1), Ok(()));
        assert_eq!(m.bytes(), 7);
    }
}
