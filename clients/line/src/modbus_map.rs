//! The Modbus register map (docs/line.md): what a PLC reads, computed from
//! a [`RigSnapshot`]. Pure functions: the server only adds the sockets.

use ipc_types::MAX_PICK_POSES;
use tokio_modbus::ExceptionCode;

use upm_rig_client::rig_view::RigSnapshot;

/// Input registers 0.. : the rig.
pub const RIG_BLOCK: u16 = 0;
pub const RIG_REGISTERS: u16 = 8;
/// Input registers 100 + 10 n.. : pose n.
pub const POSE_BLOCK: u16 = 100;
pub const POSE_STRIDE: u16 = 10;
pub const POSE_REGISTERS: u16 = POSE_STRIDE * MAX_PICK_POSES as u16;
/// Coil 0: run (1 start, 0 stop).
pub const RUN_COIL: u16 = 0;
/// Holding register 10: write n to acknowledge the pick from pose n.
pub const PICK_ACK_REGISTER: u16 = 10;
/// Modbus's own limit on registers per read.
pub const MAX_READ: u16 = 125;

/// A u32 as two registers, high word first.
fn words(v: u32) -> [u16; 2] {
    [(v >> 16) as u16, v as u16]
}

/// A length in m as i32 hundredths of a mm (saturating).
fn centi_mm(m: f64) -> u32 {
    (m * 1e5).round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32 as u32
}

/// An angle in rad as i32 thousandths of a degree (saturating).
fn milli_deg(rad: f64) -> u32 {
    (rad.to_degrees() * 1e3).round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32 as u32
}

/// Input register `addr`.
fn input_register(s: &RigSnapshot, addr: u16) -> Option<u16> {
    if (RIG_BLOCK..RIG_BLOCK + RIG_REGISTERS).contains(&addr) {
        let [picked_hi, picked_lo] = words(s.picked as u32);
        let [lost_hi, lost_lo] = words(s.lost as u32);
        let ppm = (s.parts_per_minute * 100.0).round().clamp(0.0, f64::from(u16::MAX)) as u16;
        let poses = s.poses.len() as u16;
        return Some(
            [s.state.code() as u16, picked_hi, picked_lo, lost_hi, lost_lo, ppm, poses, 0][usize::from(addr)],
        );
    }
    if (POSE_BLOCK..POSE_BLOCK + POSE_REGISTERS).contains(&addr) {
        let (n, k) =
            (usize::from((addr - POSE_BLOCK) / POSE_STRIDE), usize::from((addr - POSE_BLOCK) % POSE_STRIDE));
        let Some(p) = s.poses.get(n) else { return Some(0) };
        let [x_hi, x_lo] = words(centi_mm(p.x));
        let [y_hi, y_lo] = words(centi_mm(p.y));
        let [t_hi, t_lo] = words(milli_deg(p.theta));
        let [id_hi, id_lo] = words(p.part_id);
        return Some(
            [u16::from(p.ready), p.class as u16, x_hi, x_lo, y_hi, y_lo, t_hi, t_lo, id_hi, id_lo][k],
        );
    }
    None
}

/// `count` input registers from `addr`: all inside one block, or an
/// exception as Modbus defines it.
pub fn input_registers(s: &RigSnapshot, addr: u16, count: u16) -> Result<Vec<u16>, ExceptionCode> {
    if count == 0 || count > MAX_READ {
        return Err(ExceptionCode::IllegalDataValue);
    }
    let end = addr.checked_add(count - 1).ok_or(ExceptionCode::IllegalDataAddress)?;
    let in_block = |start: u16, len: u16| addr >= start && end < start + len;
    if !(in_block(RIG_BLOCK, RIG_REGISTERS) || in_block(POSE_BLOCK, POSE_REGISTERS)) {
        return Err(ExceptionCode::IllegalDataAddress);
    }
    (addr..=end).map(|a| input_register(s, a).ok_or(ExceptionCode::IllegalDataAddress)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc_types::CoreState;
    use upm_rig_client::rig_view::PoseView;

    fn snapshot() -> RigSnapshot {
        RigSnapshot {
            state: CoreState::Hold,
            health: String::new(),
            recipe: String::new(),
            recipe_path: String::new(),
            recipe_error: String::new(),
            plate_half_extent: None,
            picked: 0x0001_0002,
            lost: 3,
            parts_per_minute: 7.25,
            poses: vec![
                PoseView { ready: true, class: 1, part_id: 70_000, x: 0.7, y: -0.25, theta: -0.5 },
                PoseView { ready: false, class: 0, part_id: 0, x: 0.85, y: 0.25, theta: 0.0 },
            ],
            sent: [0; ipc_types::MAX_PICK_POSES],
            telemetry_seen: 1,
            feed_seen: 1,
            invalid_messages: 0,
            telemetry: None,
            feed: None,
            parts: None,
        }
    }

    #[test]
    fn registers_follow_the_map() -> Result<(), ExceptionCode> {
        let s = snapshot();
        assert_eq!(input_registers(&s, 0, 8)?, [2, 1, 2, 0, 3, 725, 2, 0]);
        let p = input_registers(&s, 100, 10)?;
        assert_eq!(p[..2], [1, 1]);
        let join = |hi: u16, lo: u16| ((u32::from(hi) << 16) | u32::from(lo)) as i32;
        assert_eq!(join(p[2], p[3]), 70_000, "x in 0.01 mm");
        assert_eq!(join(p[4], p[5]), -25_000);
        assert_eq!(join(p[6], p[7]), -28_648, "theta in 0.001°");
        assert_eq!(join(p[8], p[9]) as u32, 70_000);
        assert_eq!(input_registers(&s, 110, 1)?, [0], "pose 1 not ready");
        assert_eq!(input_registers(&s, 120, 10)?, [0; 10], "no pose 2: zeros");
        Ok(())
    }

    #[test]
    fn reads_off_the_map_are_exceptions() {
        let s = snapshot();
        assert_eq!(input_registers(&s, 0, 0), Err(ExceptionCode::IllegalDataValue));
        assert_eq!(input_registers(&s, 100, 126), Err(ExceptionCode::IllegalDataValue));
        assert_eq!(input_registers(&s, 7, 2), Err(ExceptionCode::IllegalDataAddress));
        assert_eq!(input_registers(&s, 8, 1), Err(ExceptionCode::IllegalDataAddress));
        assert_eq!(input_registers(&s, 259, 2), Err(ExceptionCode::IllegalDataAddress));
        assert_eq!(input_registers(&s, u16::MAX, 1), Err(ExceptionCode::IllegalDataAddress));
        assert_eq!(input_registers(&s, u16::MAX, 2), Err(ExceptionCode::IllegalDataAddress));
    }
}
