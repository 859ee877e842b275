//! [`Error`], the one error type of the facade: invalid input, solver failure, no contact.

use vibrissa_io::IoError;

/// Boxed error of a model crate, kept as the source of [`Error::Solver`].
pub type BoxedSource = Box<dyn std::error::Error + Send + Sync + 'static>;

/// What went wrong, in the three classes of the command line's exit codes (2, 1, 3;
/// [`Error::exit_code`]). The message is one line naming the culprit, as the CLI prints it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Invalid input: a file, a scene field (with its line and column), a value, a log's
    /// line and column; the [`IoError`] says which.
    #[error(transparent)]
    InvalidInput(IoError),
    /// A solver failed: the message names the solver and its numbers (residual, estimate).
    #[error("{reason}")]
    Solver {
        /// One line naming the solver and what failed.
        reason: String,
        /// The error of the model crate, if any.
        #[source]
        source: Option<BoxedSource>,
    },
    /// The whisker never touches the obstacle ([`contact_sim::ContactError::NoContact`]).
    #[error("{reason}")]
    NoContact {
        /// Why, with the lengths of the scene.
        reason: String,
        /// The error of the sweep.
        #[source]
        source: Option<BoxedSource>,
    },
}

impl Error {
    /// The command line's exit code of this error: 2 invalid input, 1 solver failure, 3 no
    /// contact.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::InvalidInput(_) => 2,
            Error::Solver { .. } => 1,
            Error::NoContact { .. } => 3,
        }
    }
}

impl From<IoError> for Error {
    /// A solver failure of the input layer (a model error it could not pin on an input)
    /// becomes [`Error::Solver`] or [`Error::NoContact`]; everything else is invalid input.
    fn from(e: IoError) -> Self {
        let no_contact = e.is_no_contact();
        match e {
            IoError::Solver { reason, source } if no_contact => Error::NoContact { reason, source },
            IoError::Solver { reason, source } => Error::Solver { reason, source },
            other => Error::InvalidInput(other),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_follow_the_exit_codes() {
        let e: Error = IoError::invalid_argument("theta", "2", "must be in (0, 1]").into();
        assert_eq!(e.exit_code(), 2);
        assert_eq!(
            e.to_string(),
            "invalid value `2` for `theta`: must be in (0, 1]"
        );
        let e: Error = IoError::solver(std::io::Error::other("shooting: residual 1e-3")).into();
        assert_eq!(e.exit_code(), 1);
        let e: Error = IoError::solver(contact_sim::ContactError::NoContact {
            reason: "never touches".into(),
        })
        .into();
        assert_eq!(e.exit_code(), 3);
        assert!(matches!(e, Error::NoContact { .. }));
    }
}
