//! What the rig's non-RT clients with servers (the line interface, the
//! operator page) share: the rig's view over iceoryx2 and the commands it
//! passes on ([`rig_view`]), which rig to serve ([`rig_prefix`]), what a
//! server reads at start and when it stops ([`server_start`]), and how to
//! stay off the motor's CPU ([`motor_cpu`]). See README.md.

pub mod client_counters;
pub mod motor_cpu;
pub mod rig_prefix;
pub mod rig_view;
pub mod server_start;
