//! The error type of the plotting library.

use std::path::PathBuf;

use vibrissa_io::IoError;

/// Errors of drawing and writing a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A figure could not be drawn (rendered to SVG or rasterised to PNG).
    #[error("{}: cannot draw the figure: {reason}", path.display())]
    Draw {
        /// The SVG file being produced.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// A figure's file could not be written.
    #[error(transparent)]
    Io(#[from] IoError),
}
