//! Why a plan or a bake stopped: bad input (naming the file, the object and
//! the field), an output that cannot be written, or the caller's cancel.
//! Front doors map the kinds to their own codes (the CLI's exit codes, the
//! C ABI's statuses) and never parse the message.

use crate::control::Cancelled;
use std::fmt;

/// The request's fields that bound a bake's work
/// ([`crate::limits::Limits`]): the memory it may hold, bytes, and the
/// shadow rays, kernel evaluations and probes it may take.
pub const LIMIT_FIELDS: [&str; 2] = ["max_memory", "max_evaluations"];

/// Why a plan or a bake stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// Input the bake cannot use; says where.
    #[error("{0}")]
    Input(InputError),
    /// A setting of the request out of its range.
    #[error("{field}: {message}")]
    Setting {
        /// The setting, such as `resolution` or `octree.epsilon`.
        field: String,
        /// What is wrong with its value.
        message: String,
    },
    /// An output that cannot be written.
    #[error("{path}: {message}")]
    Output {
        /// The file or folder.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The caller cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// Input the bake cannot use, with as much of where as is known.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputError {
    /// The file the input came from, if any.
    pub file: Option<String>,
    /// The object it concerns, if any.
    pub object: Option<String>,
    /// The field or option, such as `layers[0].ior` or `resolution`.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{file}: ")?;
        }
        if let Some(object) = &self.object {
            write!(f, "object `{object}`: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl Error {
    /// Bad input described by `message` alone.
    pub fn input(message: impl Into<String>) -> Self {
        Error::Input(InputError {
            message: message.into(),
            ..InputError::default()
        })
    }

    /// A bad value of the request's `field`.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Setting {
            field: field.into(),
            message: message.into(),
        }
    }

    /// An output at `path` that cannot be written.
    pub fn output(path: impl fmt::Display, message: impl Into<String>) -> Self {
        Error::Output {
            path: path.to_string(),
            message: message.into(),
        }
    }

    /// The same error, said of `file` where no file is named yet.
    pub fn in_file(self, file: impl Into<String>) -> Self {
        match self {
            Error::Input(mut e) if e.file.is_none() => {
                e.file = Some(file.into());
                Error::Input(e)
            }
            other => other,
        }
    }

    /// The same error with a front door's name for a work limit appended,
    /// `name(field)` in brackets (the command line's `--max-memory`, the C
    /// ABI's `max_memory_bytes`), when it is about one of [`LIMIT_FIELDS`]:
    /// the library says which limit and that it may be raised, each door
    /// how.
    pub fn naming_limit(self, name: impl Fn(&str) -> String) -> Self {
        match self {
            Error::Setting { field, message } if LIMIT_FIELDS.contains(&field.as_str()) => {
                let message = format!("{message} ({})", name(&field));
                Error::Setting { field, message }
            }
            other => other,
        }
    }

    /// The same error, said of `object` where no object is named yet.
    pub fn for_object(self, object: impl Into<String>) -> Self {
        match self {
            Error::Input(mut e) if e.object.is_none() => {
                e.object = Some(object.into());
                Error::Input(e)
            }
            other => other,
        }
    }
}

impl From<Cancelled> for Error {
    fn from(_: Cancelled) -> Self {
        Error::Cancelled
    }
}

impl From<sssbake_profile::material::MaterialError> for Error {
    fn from(e: sssbake_profile::material::MaterialError) -> Self {
        Error::Input(InputError {
            file: Some(e.source),
            object: None,
            field: (!e.field.is_empty()).then_some(e.field),
            message: e.message,
        })
    }
}

impl From<sssbake_profile::model::ModelError> for Error {
    fn from(e: sssbake_profile::model::ModelError) -> Self {
        Error::input(e.to_string())
    }
}

impl From<crate::mesh::MeshError> for Error {
    fn from(e: crate::mesh::MeshError) -> Self {
        Error::input(e.to_string())
    }
}

impl From<crate::surface::unwrap::UnwrapError> for Error {
    fn from(e: crate::surface::unwrap::UnwrapError) -> Self {
        Error::Input(InputError {
            object: Some(e.object),
            message: format!("cannot unwrap: {}", e.reason),
            ..InputError::default()
        })
    }
}
