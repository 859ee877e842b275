//! The error type of the command line layer.
//!
//! Every variant carries what a user needs to find the culprit: the file, the 1-based line
//! and column, the field or flag and the offending value. `Display` renders one line that
//! the binary prints to stderr as is.

use std::error::Error as StdError;
use std::fmt;
use std::path::PathBuf;

/// Boxed error of a lower layer (a model crate), kept as the source of [`CliError::Solver`].
pub type BoxedSource = Box<dyn StdError + Send + Sync + 'static>;

/// Errors of the `vibrissa` command line: input files, arguments, outputs and solvers.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
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
    /// A figure could not be drawn.
    #[error("{}: cannot draw the figure: {reason}", path.display())]
    Plot {
        /// The SVG file being produced.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// Standard output did not take the command's output: its reader closed the pipe
    /// early, or the device is full (exit [`EXIT_OUTPUT`](crate::printer::EXIT_OUTPUT)).
    #[error(
        "cannot write to standard output: {}{}",
        crate::printer::stdout_failure(source),
        Published(published.as_deref())
    )]
    Stdout {
        /// The operating system's error.
        #[source]
        source: std::io::Error,
        /// The output folder already published whole before the write failed, if any.
        published: Option<PathBuf>,
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

impl CliError {
    /// The process exit code for this error (spec/cli.md): 3 when the whisker never touches
    /// the obstacle, 1 for other solver failures (and figures that could not be drawn), 2 for
    /// usage and input errors, 4 ([`EXIT_OUTPUT`](crate::printer::EXIT_OUTPUT)) when standard
    /// output did not take the output.
    pub fn exit_code(&self) -> i32 {
        match self {
            _ if self.is_no_contact() => 3,
            CliError::Stdout { .. } => crate::printer::EXIT_OUTPUT,
            CliError::Solver { .. } | CliError::Plot { .. } => 1,
            CliError::Io { .. }
            | CliError::Csv { .. }
            | CliError::Scene { .. }
            | CliError::InvalidArgument { .. }
            | CliError::Usage { .. } => 2,
        }
    }

    /// Whether this is a sweep whose whisker never touches the obstacle
    /// ([`contact_sim::ContactError::NoContact`]).
    pub fn is_no_contact(&self) -> bool {
        matches!(
            self,
            CliError::Solver { source: Some(src), .. }
                if matches!(
                    src.downcast_ref::<contact_sim::ContactError>(),
                    Some(contact_sim::ContactError::NoContact { .. })
                )
        )
    }

    /// Wraps an error of a model crate as [`CliError::Solver`], using its message as reason.
    pub fn solver<E>(err: E) -> Self
    where
        E: StdError + Send + Sync + 'static,
    {
        CliError::Solver {
            reason: err.to_string(),
            source: Some(Box::new(err)),
        }
    }

    /// Shorthand for [`CliError::Io`].
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        CliError::Io {
            path: path.into(),
            source,
        }
    }

    /// Shorthand for [`CliError::InvalidArgument`].
    pub fn invalid_argument(
        flag: impl Into<String>,
        value: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        CliError::InvalidArgument {
            flag: flag.into(),
            value: value.into(),
            reason: reason.into(),
        }
    }
}

impl From<vibrissa_io::IoError> for CliError {
    /// The same error, variant for variant (same message, same exit code).
    fn from(e: vibrissa_io::IoError) -> Self {
        use vibrissa_io::IoError as E;
        match e {
            E::Io { path, source } => CliError::Io { path, source },
            E::Csv {
                path,
                line,
                column,
                reason,
            } => CliError::Csv {
                path,
                line,
                column,
                reason,
            },
            E::Scene {
                path,
                line,
                column,
                field,
                reason,
            } => CliError::Scene {
                path,
                line,
                column,
                field,
                reason,
            },
            E::InvalidArgument {
                flag,
                value,
                reason,
            } => CliError::InvalidArgument {
                flag,
                value,
                reason,
            },
            E::Usage { reason } => CliError::Usage { reason },
            // an output folder refused: a usage error, its message as is
            e @ (E::Locked { .. } | E::ForeignFile { .. }) => CliError::Usage {
                reason: e.to_string(),
            },
            E::Solver { reason, source } => CliError::Solver { reason, source },
        }
    }
}

impl From<vibrissa_plot::PlotError> for CliError {
    /// A figure that could not be drawn is [`CliError::Plot`]; one that could not be
    /// written, the I/O error.
    fn from(e: vibrissa_plot::PlotError) -> Self {
        match e {
            vibrissa_plot::PlotError::Draw { path, reason } => CliError::Plot { path, reason },
            vibrissa_plot::PlotError::Io(e) => e.into(),
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

/// Renders "; the files in DIR are complete" or nothing.
struct Published<'a>(Option<&'a std::path::Path>);

impl fmt::Display for Published<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(d) => write!(
                f,
                "; the files in {} were written before and are complete",
                d.display()
            ),
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
        let e = CliError::Csv {
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
        let e = CliError::Scene {
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
        let e = CliError::invalid_argument("--theta", "2", "must be in (0, 1]");
        assert_eq!(
            e.to_string(),
            "invalid value `2` for `--theta`: must be in (0, 1]"
        );
        let e = CliError::solver(std::io::Error::other("shooting: residual 1e-3"));
        assert_eq!(e.to_string(), "shooting: residual 1e-3");
        assert_eq!(e.exit_code(), 1);
        assert!(e.source().is_some());
    }
}
