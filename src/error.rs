//! The library's one error type. Every variant names the file (or input) it is about, so the
//! binary can print it as is; `anyhow` lives only in the binary.

use std::path::PathBuf;

/// Result alias used throughout the library.
pub type Result<T, E = XylemError> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum XylemError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A TOML config could not be parsed (syntax, unknown key, wrong type). The message from
    /// the TOML parser already names the key and the line.
    #[error("{path}: {message}")]
    ConfigParse { path: PathBuf, message: String },

    /// A config value parsed but is out of range or inconsistent.
    #[error("{path}: `{key}` {message}")]
    ConfigValue {
        path: PathBuf,
        key: String,
        message: String,
    },

    /// An image could not be decoded or has the wrong size or layout.
    #[error("{path}: {message}")]
    Image { path: PathBuf, message: String },

    /// A command-line argument or other in-memory input is malformed.
    #[error("{what}: {message}")]
    Input { what: String, message: String },

    /// A sample folder (Mokume layout) is incomplete or inconsistent.
    #[error("{path}: {message}")]
    Sample { path: PathBuf, message: String },

    /// Something a numerical stage could not do (diverged, empty data, ...).
    #[error("{stage}: {message}")]
    Numeric { stage: String, message: String },

    /// A step of a longer job failed; `what` says which step and on what (`fitting DIR`).
    #[error("{what}: {source}")]
    During {
        what: String,
        #[source]
        source: Box<XylemError>,
    },
}

impl XylemError {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    pub fn input(what: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Input {
            what: what.into(),
            message: message.into(),
        }
    }

    pub fn image(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Image {
            path: path.into(),
            message: message.into(),
        }
    }

    pub fn sample(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Sample {
            path: path.into(),
            message: message.into(),
        }
    }

    /// This error, said to have happened during `what` (the job's step and its input).
    pub fn during(self, what: impl Into<String>) -> Self {
        Self::During {
            what: what.into(),
            source: Box::new(self),
        }
    }

    pub fn numeric(stage: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Numeric {
            stage: stage.into(),
            message: message.into(),
        }
    }
}
