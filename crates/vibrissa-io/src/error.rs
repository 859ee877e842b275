//! The error type of the input/output layer (scenes, CSV files, units, output folders).
//!
//! Every variant carries what a user needs to find the culprit: the file, the 1-based line
//! and column, the field or flag and the offending value. `Display` renders one line (the
//! command line prints it to stderr as is).

use std::error::Error as StdError;
use std::fmt;
use std::path::PathBuf;

/// Boxed error of a lower layer (a model crate), kept as the source of [`IoError::Solver`].
pub type BoxedSource = Box<dyn StdError + Send + Sync + 'static>;

/// Errors of vibrissa's inputs and outputs: files, values given, outputs, and the solvers
/// a scene is checked against.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// A file or directory could not be read, written, created or renamed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path the operation was applied to.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A CSV file is malformed or lacks what the command needs.
    #[error("{}:{line}: {}{reason}", path.display(), OptColumn(column.as_deref()))]
    Csv {
        /// The CSV file.
        path: PathBuf,
        /// The 1-based line of the problem.
        line: usize,
        /// The column (header name) concerned, if the problem is in one column.
        column: Option<String>,
        /// What is wrong.
        reason: String,
    },
    /// A RON scene file is malformed or holds a value out of range.
    #[error("{}:{line}:{column}: {}{reason}", path.display(), OptField(field.as_deref()))]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// The 1-based line of the problem.
        line: usize,
        /// The 1-based column of the problem.
        column: usize,
        /// The dotted field path concerned (`whisker.theta`), if known.
        field: Option<String>,
        /// What is wrong.
        reason: String,
    },
    /// A command line flag has an unusable value.
    #[error("invalid value `{value}` for `{flag}`: {reason}")]
    InvalidArgument {
        /// The flag, spelled as on the command line (`--theta`).
        flag: String,
        /// The value given.
        value: String,
        /// Why it was refused.
        reason: String,
    },
    /// Something the command needs was not given (neither as a flag nor in the scene file).
    #[error("{reason}")]
    Usage {
        /// What is missing and how to give it.
        reason: String,
    },
    /// An output folder (`--out`) is being written by another live process, which holds its
    /// lock ([`crate::atomic::lock`]).
    #[error(
        "{} is being written by another vibrissa process; wait for it to end or choose another --out",
        dir.display()
    )]
    Locked {
        /// The output folder, as named by the user.
        dir: PathBuf,
    },
    /// An existing output folder (`--out`) holds an entry vibrissa did not write (not listed
    /// in its manifest, [`crate::atomic::manifest`]): it is not replaced.
    #[error(
        "invalid value `{}` for `--out`: it holds {}, which vibrissa did not write (not listed \
         in its {}); the folder would be replaced as a whole: move that file away or choose \
         another folder",
        dir.display(),
        file.display(),
        crate::atomic::MANIFEST
    )]
    ForeignFile {
        /// The output folder, as named by the user.
        dir: PathBuf,
        /// One entry in it that vibrissa did not write.
        file: PathBuf,
    },
    /// A model or solver failed (no convergence, singular system, ...).
    #[error("{reason}")]
    Solver {
        /// One line naming the solver and what failed (for instance its residual).
        reason: String,
        /// The underlying error of the model crate, if any.
        #[source]
        source: Option<BoxedSource>,
    },
}

impl IoError {
    /// The process exit code for this error (spec/cli.md): 3 when the whisker never touches
    /// the obstacle, 1 for other solver failures, 2 for usage and input errors.
    pub fn exit_code(&self) -> i32 {
        match self {
            _ if self.is_no_contact() => 3,
            IoError::Solver { .. } => 1,
            IoError::Io { .. }
            | IoError::Csv { .. }
            | IoError::Scene { .. }
            | IoError::InvalidArgument { .. }
            | IoError::Usage { .. }
            | IoError::Locked { .. }
            | IoError::ForeignFile { .. } => 2,
        }
    }

    /// Whether this is a sweep whose whisker never touches the obstacle
    /// ([`contact_sim::ContactError::NoContact`]).
    pub fn is_no_contact(&self) -> bool {
        matches!(
            self,
            IoError::Solver { source: Some(src), .. }
                if matches!(
                    src.downcast_ref::<contact_sim::ContactError>(),
                    Some(contact_sim::ContactError::NoContact { .. })
                )
        )
    }

    /// Wraps an error of a model crate as [`IoError::Solver`], using its message as reason.
    pub fn solver<E>(err: E) -> Self
    where
        E: StdError + Send + Sync + 'static,
    {
        IoError::Solver {
            reason: err.to_string(),
            source: Some(Box::new(err)),
        }
    }

    /// Shorthand for [`IoError::Io`].
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        IoError::Io {
            path: path.into(),
            source,
        }
    }

    /// Shorthand for [`IoError::InvalidArgument`].
    pub fn invalid_argument(
        flag: impl Into<String>,
        value: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        IoError::InvalidArgument {
            flag: flag.into(),
            value: value.into(),
            reason: reason.into(),
        }
    }
}

/// Renders "column `name`: " or nothing.
struct OptColumn<'a>(Option<&'a str>);

impl fmt::Display for OptColumn<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(c) => write!(f, "column `{c}`: "),
            None => Ok(()),
        }
    }
}

/// Renders "field `name`: " or nothing.
struct OptField<'a>(Option<&'a str>);

impl fmt::Display for OptField<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(c) => write!(f, "field `{c}`: "),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_culprit() {
        let e = IoError::Csv {
            path: "obs.csv".into(),
            line: 4,
            column: Some("Ax".into()),
            reason: "`abc` is not a number".into(),
        };
        assert_eq!(
            e.to_string(),
            "obs.csv:4: column `Ax`: `abc` is not a number"
        );
        assert_eq!(e.exit_code(), 2);
        let e = IoError::Scene {
            path: "s.ron".into(),
            line: 3,
            column: 15,
            field: Some("whisker.theta".into()),
            reason: "must be in (0, 1], got -0.5".into(),
        };
        assert_eq!(
            e.to_string(),
            "s.ron:3:15: field `whisker.theta`: must be in (0, 1], got -0.5"
        );
        let e = IoError::invalid_argument("--theta", "2", "must be in (0, 1]");
        assert_eq!(
            e.to_string(),
            "invalid value `2` for `--theta`: must be in (0, 1]"
        );
        let e = IoError::solver(std::io::Error::other("shooting: residual 1e-3"));
        assert_eq!(e.to_string(), "shooting: residual 1e-3");
        assert_eq!(e.exit_code(), 1);
        assert!(e.source().is_some());
    }
}
