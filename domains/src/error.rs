//! The error type shared by the stillpoint crates: every refusal names the argument,
//! the value it got and what is accepted.

/// Result with the workspace [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Why an input was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An argument outside its accepted range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidArgument {
        /// The argument's name as the user wrote it (`n`, `--q`, `point 3, coordinate 2`).
        name: String,
        /// The value received.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// A computation that could not produce a finite result.
    #[error("{0}")]
    Numerical(String),
}

impl Error {
    /// Builds an [`Error::InvalidArgument`].
    pub fn invalid(
        name: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Error::InvalidArgument {
            name: name.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}
