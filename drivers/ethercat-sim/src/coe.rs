//! CoE (CANopen over EtherCAT) in the mailbox: expedited SDO upload and
//! download on the drive's object dictionary. Anything else (segmented
//! transfers, complete access, SDO information, unknown objects, writes to
//! read-only objects, a PDO mapping the drive cannot hold) is answered
//! with an SDO abort and its standard code, never left unanswered. The
//! PDO mapping and assignment objects are the drive's [`crate::pdo_map`].
//!
//! Mailbox layout: `length u16, address u16, channel u8, type|counter u8`
//! (type 3 = CoE), then the CoE header u16 (service in bits 12–15: 2 SDO
//! request, 3 SDO response), the SDO command byte, `index u16, subindex
//! u8`, and 4 data bytes.

use crate::abort;
use crate::cia402::Drive;

/// Mailbox type of CoE.
pub const MAILBOX_COE: u8 = 3;
const SERVICE_SDO_REQUEST: u16 = 2;
const SERVICE_SDO_RESPONSE: u16 = 3;
/// Bytes of an expedited SDO request or reply (mailbox header included).
pub const SDO_BYTES: usize = 16;

/// The identity object 0x1018: vendor, product, revision, serial.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Identity {
    pub vendor: u32,
    pub product: u32,
    pub revision: u32,
    pub serial: u32,
}

/// A value of at most 4 bytes and its size.
type Value = (u32, u8);

/// Read object `index:sub`.
pub fn read(index: u16, sub: u8, drive: &Drive, id: &Identity) -> Result<Value, u32> {
    let only = |v: Value| if sub == 0 { Ok(v) } else { Err(abort::NO_SUBINDEX) };
    match index {
        // Device type: CiA 402 servo drive.
        0x1000 => only((0x0002_0192, 4)),
        0x1018 => match sub {
            0 => Ok((4, 1)),
            1 => Ok((id.vendor, 4)),
            2 => Ok((id.product, 4)),
            3 => Ok((id.revision, 4)),
            4 => Ok((id.serial, 4)),
            _ => Err(abort::NO_SUBINDEX),
        },
        0x1600 => drive.rx.read_mapping(sub),
        0x1A00 => drive.tx.read_mapping(sub),
        0x1C12 => drive.rx.read_assignment(sub),
        0x1C13 => drive.tx.read_assignment(sub),
        0x6040 => only((u32::from(drive.controlword), 2)),
        0x6041 => only((u32::from(drive.statusword()), 2)),
        0x6060 | 0x6061 => only((u32::from(drive.mode as u8), 1)),
        0x6064 => only((drive.actual as u32, 4)),
        0x6065 => only((drive.following_error_window, 4)),
        0x6076 => only((drive.rated_torque, 4)),
        0x6077 => only((u32::from(drive.torque_actual as u16), 2)),
        0x607A => only((drive.target as u32, 4)),
        0x60B1 => only((drive.velocity_offset as u32, 4)),
        0x60B2 => only((u32::from(drive.torque_offset as u16), 2)),
        _ => Err(abort::NO_OBJECT),
    }
}

/// Write object `index:sub` with `size` bytes of `value`.
pub fn write(index: u16, sub: u8, value: u32, size: u8, drive: &mut Drive, id: &Identity) -> Result<(), u32> {
    let (_, expected) = read(index, sub, drive, id)?;
    if size != expected && matches!(index, 0x1600 | 0x1A00 | 0x1C12 | 0x1C13) {
        return Err(abort::LENGTH_MISMATCH);
    }
    match index {
        0x1600 => return drive.rx.write_mapping(sub, value),
        0x1A00 => return drive.tx.write_mapping(sub, value),
        0x1C12 => return drive.rx.write_assignment(sub, value),
        0x1C13 => return drive.tx.write_assignment(sub, value),
        _ => {}
    }
    let writable = sub == 0 && matches!(index, 0x6040 | 0x6060 | 0x6065 | 0x607A | 0x60B1 | 0x60B2);
    if !writable {
        return Err(abort::READ_ONLY);
    }
    if size != expected {
        return Err(abort::LENGTH_MISMATCH);
    }
    match index {
        0x6040 => drive.command(value as u16),
        0x6060 => drive.mode = value as u8 as i8,
        0x6065 => drive.following_error_window = value,
        0x60B1 => drive.velocity_offset = value as i32,
        0x60B2 => drive.torque_offset = value as u16 as i16,
        _ => drive.target = value as i32,
    }
    Ok(())
}

/// Answer one mailbox `request` into `reply` (at least [`SDO_BYTES`]);
/// `None` for a mailbox that is not CoE (no reply, as an ESC without that
/// protocol would give none).
pub fn answer(request: &[u8], reply: &mut [u8], drive: &mut Drive, id: &Identity) -> Option<usize> {
    if request.len() < SDO_BYTES || reply.len() < SDO_BYTES || request[5] & 0x0F != MAILBOX_COE {
        return None;
    }
    let service = u16::from_le_bytes([request[6], request[7]]) >> 12;
    let command = request[8];
    let (index, sub) = (u16::from_le_bytes([request[9], request[10]]), request[11]);
    let data = u32::from_le_bytes([request[12], request[13], request[14], request[15]]);
    let outcome: Result<(u8, u32), u32> = if service != SERVICE_SDO_REQUEST {
        Err(abort::COMMAND_INVALID)
    } else if command & 0x10 != 0 {
        Err(abort::UNSUPPORTED_ACCESS) // complete access
    } else {
        match command >> 5 {
            // Initiate download, expedited only.
            1 if command & 0x02 != 0 => {
                let size = if command & 0x01 != 0 { 4 - ((command >> 2) & 0x03) } else { 4 };
                let value = data & (u32::MAX >> (8 * (4 - u32::from(size))));
                write(index, sub, value, size, drive, id).map(|()| (0x60, 0))
            }
            1 => Err(abort::UNSUPPORTED_ACCESS),
            // Initiate upload: expedited reply with the size indicated.
            2 => read(index, sub, drive, id).map(|(v, n)| (0x43 | ((4 - n) << 2), v)),
            _ => Err(abort::COMMAND_INVALID),
        }
    };
    let (command, value) = match outcome {
        Ok(r) => r,
        Err(code) => (0x80, code),
    };
    reply[..SDO_BYTES].fill(0);
    reply[0..2].copy_from_slice(&10u16.to_le_bytes());
    // Same counter as the request, CoE.
    reply[5] = (request[5] & 0x70) | MAILBOX_COE;
    reply[6..8].copy_from_slice(&(SERVICE_SDO_RESPONSE << 12).to_le_bytes());
    reply[8] = command;
    reply[9..12].copy_from_slice(&request[9..12]);
    reply[12..16].copy_from_slice(&value.to_le_bytes());
    Some(SDO_BYTES)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ID: Identity = Identity { vendor: 1, product: 2, revision: 3, serial: 4 };

    fn request(command: u8, index: u16, sub: u8, data: u32) -> [u8; SDO_BYTES] {
        let mut r = [0u8; SDO_BYTES];
        r[0..2].copy_from_slice(&10u16.to_le_bytes());
        r[5] = 0x10 | MAILBOX_COE;
        r[6..8].copy_from_slice(&(SERVICE_SDO_REQUEST << 12).to_le_bytes());
        r[8] = command;
        r[9..11].copy_from_slice(&index.to_le_bytes());
        r[11] = sub;
        r[12..16].copy_from_slice(&data.to_le_bytes());
        r
    }

    fn ask(drive: &mut Drive, req: [u8; SDO_BYTES]) -> (u8, u32) {
        let mut reply = [0u8; SDO_BYTES];
        assert_eq!(answer(&req, &mut reply, drive, &ID), Some(SDO_BYTES));
        assert_eq!(reply[5], 0x10 | MAILBOX_COE);
        assert_eq!(&reply[9..12], &req[9..12], "index and subindex echoed");
        (reply[8], u32::from_le_bytes([reply[12], reply[13], reply[14], reply[15]]))
    }

    #[test]
    fn uploads_give_the_size_and_downloads_reach_the_drive() {
        let mut d = Drive::default();
        assert_eq!(ask(&mut d, request(0x40, 0x1C12, 0, 0)), (0x4F, 1), "u8");
        assert_eq!(ask(&mut d, request(0x40, 0x1C12, 1, 0)), (0x4B, 0x1600), "u16");
        assert_eq!(ask(&mut d, request(0x40, 0x1A00, 2, 0)), (0x43, 0x6064_0020), "u32");
        assert_eq!(ask(&mut d, request(0x40, 0x1600, 0, 0)), (0x4F, 5), "five outputs mapped");
        // 0x6060 = 8 (one byte): 0x2F.
        assert_eq!(ask(&mut d, request(0x2F, 0x6060, 0, 8)), (0x60, 0));
        assert_eq!(d.mode, 8);
        assert_eq!(ask(&mut d, request(0x2B, 0x6040, 0, 0x0006)), (0x60, 0));
        assert_eq!(d.state, crate::cia402::PowerState::ReadyToSwitchOn);
    }

    #[test]
    fn what_is_not_there_or_not_writable_is_aborted_with_its_code() {
        let mut d = Drive::default();
        assert_eq!(ask(&mut d, request(0x40, 0x2000, 0, 0)), (0x80, abort::NO_OBJECT));
        assert_eq!(ask(&mut d, request(0x40, 0x1600, 9, 0)), (0x80, abort::NO_SUBINDEX));
        assert_eq!(ask(&mut d, request(0x23, 0x6041, 0, 0)), (0x80, abort::READ_ONLY));
        assert_eq!(ask(&mut d, request(0x23, 0x6060, 0, 8)), (0x80, abort::LENGTH_MISMATCH));
        assert_eq!(ask(&mut d, request(0x50, 0x1C12, 1, 0)), (0x80, abort::UNSUPPORTED_ACCESS));
        assert_eq!(ask(&mut d, request(0xE0, 0x1C12, 1, 0)), (0x80, abort::COMMAND_INVALID));
        let mut not_coe = request(0x40, 0x1000, 0, 0);
        not_coe[5] = 0x14;
        assert_eq!(answer(&not_coe, &mut [0u8; SDO_BYTES], &mut d, &ID), None);
    }
}
