//! The error type of the command line layer.
//!
//! Every variant carries what a user needs to find the culprit: the file, the 1-based line
//! and column, the field or flag and the offending value. `Display` renders one line that
//! the binary prints to stderr as is.

use std::error::Error as StdError;
use std::fmt;
use std::io;
use std::path::PathBuf;

use vibrissa_io::IoError;

/// Boxed error of a lower layer (a model crate), kept as the source of a solver's failure.
pub use vibrissa_io::error::BoxedSource;

/// The exit code of a command whose output could not be delivered (standard output closed
/// by its reader or full): not one of 0 (success), 1 (solver failure), 2 (usage or input
/// error), 3 (no contact), so that a script tells it from a failed computation.
pub const EXIT_OUTPUT: i32 = 4;

/// Errors of the `vibrissa` command line: the library's input/output errors (files, CSV and
/// scene lines, values, solvers: [`IoError`], as they are), figures, and standard output.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// An error of the library layer, its message and exit code unchanged: a file, a CSV
    /// or scene line, a value refused naming its flag or field, something missing, a
    /// solver's failure.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A figure could not be drawn.
    #[error("{}: cannot draw the figure: {reason}", path.display())]
    Plot {
        /// The SVG file being produced.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// Standard output did not take the command's output: its reader closed the pipe
    /// early, or the device is full (exit [`EXIT_OUTPUT`]).
    #[error(
        "cannot write to standard output: {}{}",
        stdout_failure(source),
        Published(published.as_deref())
    )]
    Stdout {
        /// The operating system's error.
        #[source]
        source: std::io::Error,
        /// The output folder already published whole before the write failed, if any.
        published: Option<PathBuf>,
    },
}

impl CliError {
    /// The process exit code for this error (spec/cli.md): 3 when the whisker never touches
    /// the obstacle, 1 for other solver failures (and figures that could not be drawn), 2 for
    /// usage and input errors, 4 ([`EXIT_OUTPUT`]) when standard
    /// output did not take the output.
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Io(e) => e.exit_code(),
            CliError::Stdout { .. } => EXIT_OUTPUT,
            CliError::Plot { .. } => 1,
        }
    }

    /// Whether this is a sweep whose whisker never touches the obstacle
    /// ([`contact_sim::ContactError::NoContact`]).
    pub fn is_no_contact(&self) -> bool {
        matches!(self, CliError::Io(e) if e.is_no_contact())
    }

    /// Wraps an error of a model crate as [`IoError::Solver`], using its message as reason.
    pub fn solver<E>(err: E) -> Self
    where
        E: StdError + Send + Sync + 'static,
    {
        CliError::Io(IoError::solver(err))
    }

    /// Shorthand for [`IoError::Io`]: a file or folder that could not be read or written.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        CliError::Io(IoError::io(path, source))
    }

    /// Shorthand for [`IoError::InvalidArgument`].
    pub fn invalid_argument(
        flag: impl Into<String>,
        value: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        CliError::Io(IoError::invalid_argument(flag, value, reason))
    }

    /// Shorthand for [`IoError::Usage`]: something the command needs was not given.
    pub fn usage(reason: impl Into<String>) -> Self {
        CliError::Io(IoError::Usage {
            reason: reason.into(),
        })
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

/// What a failed write to standard output means, in words: "the reader closed the pipe"
/// (`EPIPE`), "the device is full" (`ENOSPC`), else the operating system's message.
pub fn stdout_failure(e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::BrokenPipe => format!("its reader closed the pipe early ({e})"),
        io::ErrorKind::StorageFull => format!("the device is full ({e})"),
        _ => e.to_string(),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_culprit() {
        let e: CliError = IoError::Csv {
            path: "obs.csv".into(),
            line: 4,
            column: Some("Ax".into()),
            reason: "`abc` is not a number".into(),
        }
        .into();
        assert_eq!(
            e.to_string(),
            "obs.csv:4: column `Ax`: `abc` is not a number"
        );
        assert_eq!(e.exit_code(), 2);
        let e: CliError = IoError::Scene {
            path: "s.ron".into(),
            line: 3,
            column: 15,
            field: Some("whisker.theta".into()),
            reason: "must be in (0, 1], got -0.5".into(),
        }
        .into();
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
