//! A simulated EtherCAT chain: N CiA 402 servo drives that answer EtherCAT
//! frames (EtherType 0x88A4) as a chain of real SubDevices would, so that a
//! MainDevice (ethercrab, in UPM's EtherCAT driver) runs its whole start-up
//! and cyclic exchange against it. No software EtherCAT SubDevice exists to
//! reuse; this one implements the subset of an EtherCAT slave controller
//! (ESC) a MainDevice uses:
//!
//! - datagrams (`chain`): every command (APxx, FPxx, Bxx, Lxx, ARMW, FRMW)
//!   with auto-increment, configured-station and logical addressing and the
//!   working counter as an ESC counts it;
//! - registers (`subdevice`): type, features, station address, DL status,
//!   AL control/status/code with the state machine INIT → PRE-OP → SAFE-OP
//!   → OP (refused transitions set the error bit and a code), the SII
//!   EEPROM interface (`sii`: identity, mailbox, strings, general, FMMU,
//!   SyncManager and PDO categories), 16 FMMUs and 16 SyncManagers;
//! - the CoE mailbox (`coe`): expedited SDO upload and download on an
//!   object dictionary with the CiA 402 objects and the PDO mapping and
//!   assignment (`pdo_map`), which a MainDevice may rewrite in PRE-OP;
//! - the drive (`cia402`): the controlword/statusword state machine and
//!   cyclic synchronous position mode, its position following the target.
//!
//! A frame that is not EtherCAT, or whose datagrams overrun it, is refused
//! with a [`FrameError`] and left as it was; nothing panics on any input.

pub mod abort;
pub mod chain;
pub mod cia402;
pub mod coe;
pub mod logical_kind;
pub mod pdo_map;
pub mod rig;
pub mod serve;
pub mod sii;
pub mod subdevice;
pub mod veth;

pub use chain::{Chain, FrameError};
pub use rig::{ChainTime, SimulatedRig};
pub use subdevice::SubDevice;
