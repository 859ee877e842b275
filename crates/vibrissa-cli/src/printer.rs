//! Standard output that may refuse what is written to it.
//!
//! A command's summary, its JSON object or the rows of `reconstruct --stream` go to a
//! reader that may close early (`vibrissa sweep ... --json | head -c 1`) or to a device that
//! is full (`> /dev/full`). `println!` panics then ("failed printing to stdout", exit 101
//! and a backtrace); a [`Printer`] instead returns the operating system's error as
//! [`CliError::Stdout`], which the binary prints as one line and exits with
//! [`EXIT_OUTPUT`].
//!
//! SIGPIPE stays ignored, as Rust sets it up: a write to a closed pipe returns `EPIPE`
//! (`io::ErrorKind::BrokenPipe`) rather than killing the process, so the command says what
//! happened, and whether the files of its `--out` folder, published before anything is
//! printed, are complete.

use std::fmt::Display;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use crate::error::CliError;
pub use crate::error::{stdout_failure, EXIT_OUTPUT};

/// Lines to standard output (or any writer, for tests), each write's error returned as
/// [`CliError::Stdout`] naming the output folder already published, if any.
pub struct Printer<W: Write = io::StdoutLock<'static>> {
    out: W,
    published: Option<PathBuf>,
}

impl Printer {
    /// A printer to this process's standard output (locked for the printer's life).
    pub fn stdout() -> Self {
        Printer::to(io::stdout().lock())
    }
}

impl<W: Write> Printer<W> {
    /// A printer to `out`.
    pub fn to(out: W) -> Self {
        Printer {
            out,
            published: None,
        }
    }

    /// Names `dir`, an output folder already published whole, in the error of a failed
    /// write (the user learns that its files need not be written again).
    pub fn published(mut self, dir: Option<&Path>) -> Self {
        self.published = dir.map(Path::to_path_buf);
        self
    }

    /// Writes `text` and a newline, and flushes: the line has reached the reader (or the
    /// file) when this returns `Ok`.
    pub fn line(&mut self, text: impl Display) -> Result<(), CliError> {
        writeln!(self.out, "{text}")
            .and_then(|()| self.out.flush())
            .map_err(|e| self.error(e))
    }

    /// Writes `text` as it is (its own newlines included) and flushes.
    pub fn text(&mut self, text: &str) -> Result<(), CliError> {
        self.out
            .write_all(text.as_bytes())
            .and_then(|()| self.out.flush())
            .map_err(|e| self.error(e))
    }

    /// The writer (for tests).
    pub fn into_inner(self) -> W {
        self.out
    }

    fn error(&self, source: io::Error) -> CliError {
        CliError::Stdout {
            source,
            published: self.published.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that takes `room` bytes, then fails with `kind`.
    struct Failing {
        taken: Vec<u8>,
        room: usize,
        kind: io::ErrorKind,
    }

    impl Write for Failing {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            let n = buf.len().min(self.room - self.taken.len());
            if n == 0 && !buf.is_empty() {
                return Err(io::Error::from(self.kind));
            }
            self.taken.extend_from_slice(&buf[..n]);
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn lines_reach_the_writer_in_order() {
        let mut p = Printer::to(Vec::new());
        p.line("a = 1").unwrap();
        p.text("b\nc\n").unwrap();
        p.line(format_args!("{} rows", 3)).unwrap();
        assert_eq!(p.into_inner(), b"a = 1\nb\nc\n3 rows\n");
    }

    #[test]
    fn a_closed_pipe_is_an_error_with_its_own_exit_code_naming_the_folder() {
        let out = Failing {
            taken: Vec::new(),
            room: 4,
            kind: io::ErrorKind::BrokenPipe,
        };
        let mut p = Printer::to(out).published(Some(Path::new("out/g1")));
        let e = p.line("first line, longer than 4 bytes").unwrap_err();
        assert_eq!(e.exit_code(), EXIT_OUTPUT);
        let text = e.to_string();
        assert!(
            text.starts_with("cannot write to standard output"),
            "{text}"
        );
        assert!(text.contains("reader closed the pipe"), "{text}");
        assert!(text.contains("out/g1"), "{text}");
        assert_eq!(text.lines().count(), 1, "{text}");
        assert_eq!(p.into_inner().taken, b"firs");
    }

    #[test]
    fn a_full_device_says_so() {
        let out = Failing {
            taken: Vec::new(),
            room: 0,
            kind: io::ErrorKind::StorageFull,
        };
        let e = Printer::to(out).text("x").unwrap_err();
        assert_eq!(e.exit_code(), EXIT_OUTPUT);
        assert!(e.to_string().contains("the device is full"), "{e}");
        assert!(!e.to_string().contains("files in"), "{e}");
    }
}
