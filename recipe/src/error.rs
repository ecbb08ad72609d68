use thiserror::Error;

/// Why a recipe is refused: one line naming the file and the field.
#[derive(Debug, Error)]
pub enum RecipeError {
    #[error("{path}: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{path}: {message}")]
    Invalid { path: String, message: String },
}
