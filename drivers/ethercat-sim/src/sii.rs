//! The SII EEPROM image of the simulated drive, as ETG.2010 lays it out:
//! identity at words 0x08–0x0F, the standard mailbox at 0x18–0x1C, then
//! categories from word 0x40 (`type u16, length in words u16, data`),
//! ended by type 0xFFFF: strings (10), general (30), FMMU (40),
//! SyncManager (41), TxPDO (50) and RxPDO (51).

use crate::cia402::{INPUT_BYTES, OUTPUT_BYTES, RX_PDO, TX_PDO};
use crate::coe::Identity;

/// Mailbox and process-data buffers in the ESC's memory.
pub const MAILBOX_OUT: u16 = 0x1000;
pub const MAILBOX_IN: u16 = 0x1080;
pub const MAILBOX_BYTES: u16 = 128;
pub const OUTPUTS_AT: u16 = 0x1100;
pub const INPUTS_AT: u16 = 0x1400;

/// The name the drive reports.
pub const NAME: &str = "UPM simulated CiA 402 servo";

fn category(out: &mut Vec<u8>, kind: u16, mut data: Vec<u8>) {
    if data.len() % 2 == 1 {
        data.push(0);
    }
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(&((data.len() / 2) as u16).to_le_bytes());
    out.extend_from_slice(&data);
}

/// A SyncManager entry: start, length, control, status, enable, usage.
fn sm(start: u16, len: u16, control: u8, usage: u8) -> [u8; 8] {
    let [s0, s1] = start.to_le_bytes();
    let [l0, l1] = len.to_le_bytes();
    [s0, s1, l0, l1, control, 0, 0x01, usage]
}

/// A PDO description: header, then its entries.
fn pdo(index: u16, sm: u8, entries: &[u32]) -> Vec<u8> {
    let mut d = index.to_le_bytes().to_vec();
    d.extend_from_slice(&[entries.len() as u8, sm, 0, 0, 0, 0]);
    for e in entries {
        let [bits, sub, i0, i1] = e.to_le_bytes();
        // index, subindex, name, data type, bit length, flags
        d.extend_from_slice(&[i0, i1, sub, 0, 0, bits, 0, 0]);
    }
    d
}

/// The EEPROM bytes of a drive with `id`.
pub fn image(id: &Identity) -> Vec<u8> {
    let mut e = vec![0u8; 0x80];
    for (k, v) in [id.vendor, id.product, id.revision, id.serial].into_iter().enumerate() {
        e[0x10 + 4 * k..0x14 + 4 * k].copy_from_slice(&v.to_le_bytes());
    }
    // Standard mailbox: out (MainDevice → drive), in, sizes; CoE only.
    for (k, v) in [MAILBOX_OUT, MAILBOX_BYTES, MAILBOX_IN, MAILBOX_BYTES, 0x0004].into_iter().enumerate() {
        e[0x30 + 2 * k..0x32 + 2 * k].copy_from_slice(&v.to_le_bytes());
    }
    let mut strings = vec![1, NAME.len() as u8];
    strings.extend_from_slice(NAME.as_bytes());
    category(&mut e, 10, strings);
    // General: order and name are string 1; CoE with SDO (byte 5 bit 0).
    let mut general = vec![0u8; 32];
    general[2] = 1;
    general[3] = 1;
    general[5] = 0x01;
    category(&mut e, 30, general);
    // FMMUs: outputs, inputs, SyncManager status.
    category(&mut e, 40, vec![1, 2, 3, 0xFF]);
    let mut sms = Vec::new();
    sms.extend_from_slice(&sm(MAILBOX_OUT, MAILBOX_BYTES, 0x26, 1));
    sms.extend_from_slice(&sm(MAILBOX_IN, MAILBOX_BYTES, 0x22, 2));
    sms.extend_from_slice(&sm(OUTPUTS_AT, OUTPUT_BYTES as u16, 0x64, 3));
    sms.extend_from_slice(&sm(INPUTS_AT, INPUT_BYTES as u16, 0x20, 4));
    category(&mut e, 41, sms);
    category(&mut e, 50, pdo(0x1A00, 3, &TX_PDO));
    category(&mut e, 51, pdo(0x1600, 2, &RX_PDO));
    e.extend_from_slice(&0xFFFFu16.to_le_bytes());
    e.extend_from_slice(&[0xFF; 6]);
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_mailbox_and_categories_sit_where_the_standard_puts_them() {
        let id = Identity { vendor: 0x1111_2222, product: 0x402, revision: 3, serial: 9 };
        let e = image(&id);
        let word = |w: usize| u16::from_le_bytes([e[2 * w], e[2 * w + 1]]);
        assert_eq!((word(0x08), word(0x09), word(0x0A)), (0x2222, 0x1111, 0x402));
        assert_eq!((word(0x18), word(0x19), word(0x1C)), (MAILBOX_OUT, MAILBOX_BYTES, 4));
        // Walk the categories.
        let mut w = 0x40;
        let mut kinds = Vec::new();
        while word(w) != 0xFFFF {
            kinds.push(word(w));
            w += 2 + usize::from(word(w + 1));
        }
        assert_eq!(kinds, [10, 30, 40, 41, 50, 51]);
    }
}
