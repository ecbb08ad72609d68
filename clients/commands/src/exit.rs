//! A command's exit status with what it has already said.

/// An error with its own exit status (1 for every other error); an empty
/// message prints nothing (the command said it already).
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct Exit {
    pub code: u8,
    pub message: String,
}
