//! The `upm` command line: the command tree and its dispatch. `upm run`
//! starts the RT core's own binary (`upm-core`) and each client's
//! (`upm-vision`, `upm-planner`, `upm-camera`, `upm-recorder`), or the
//! client's hidden subcommand of `upm` where its binary is not built.
//! What each command does lives in `upm-commands`; the benches in
//! `upm-bench`.

pub mod cli;
