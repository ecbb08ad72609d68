//! UPM's line interface (`upm line`): the rig's state, counters and pick
//! poses for robots and PLCs, over OPC UA ([`opcua_server`]) and Modbus
//! TCP ([`modbus_server`]), read from the rig over iceoryx2 by
//! `upm_rig_client`'s view. See README.md and docs/line.md.

pub mod args;
pub mod counters;
pub mod modbus_map;
pub mod modbus_server;
pub mod opcua_server;

/// async-opcua's library name.
extern crate opcua;
