//! The error type of all file IO: every variant names the file, and parse errors name the
//! line (text formats) or byte offset (binary formats) and the problem.

use std::path::PathBuf;

/// An error while reading or writing a mesh file.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused to open, read or write the file.
    #[error("{}: {source}", path.display())]
    Os {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A text file is malformed at a given line.
    #[error("{file}:{line}: {msg}")]
    Parse {
        /// File name as given by the caller.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A binary file is malformed at a given byte offset.
    #[error("{file}: byte {offset}: {msg}")]
    Binary {
        /// File name as given by the caller.
        file: String,
        /// 0-based byte offset.
        offset: u64,
        /// What is wrong.
        msg: String,
    },
    /// A file is malformed as a whole (e.g. an element refers to a missing vertex).
    #[error("{file}: {msg}")]
    Invalid {
        /// File name as given by the caller.
        file: String,
        /// What is wrong.
        msg: String,
    },
    /// The file uses a variant of its format that is not supported.
    #[error("{file}: unsupported: {msg}")]
    Unsupported {
        /// File name as given by the caller.
        file: String,
        /// What is not supported.
        msg: String,
    },
    /// The file extension does not name a supported format.
    #[error("{}: unknown {kind} format (supported extensions: {supported})", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// "surface" or "volume mesh".
        kind: &'static str,
        /// The supported extensions.
        supported: &'static str,
    },
}

impl IoError {
    /// A [`IoError::Parse`] error.
    pub(crate) fn parse(file: &str, line: usize, msg: impl Into<String>) -> IoError {
        IoError::Parse {
            file: file.to_string(),
            line,
            msg: msg.into(),
        }
    }

    /// An [`IoError::Invalid`] error.
    pub(crate) fn invalid(file: &str, msg: impl Into<String>) -> IoError {
        IoError::Invalid {
            file: file.to_string(),
            msg: msg.into(),
        }
    }

    /// An [`IoError::Unsupported`] error.
    pub(crate) fn unsupported(file: &str, msg: impl Into<String>) -> IoError {
        IoError::Unsupported {
            file: file.to_string(),
            msg: msg.into(),
        }
    }

    /// An [`IoError::Os`] error.
    pub(crate) fn os(path: impl Into<PathBuf>, source: std::io::Error) -> IoError {
        IoError::Os {
            path: path.into(),
            source,
        }
    }
}
