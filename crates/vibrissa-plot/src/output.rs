//! Writing figures: how they are written ([`FigureStyle`]: the printed size `--size` and the
//! formats `--figures`), atomic SVG and PNG files (the PNG at 300 dpi of the print), figures
//! drawn two at a time.
//!
//! The style is a value handed to each figure writer, never a setting of the process: two
//! threads (or two tests) may write figures at different sizes and formats at once.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use crate::chart::*;
use crate::error::PlotError;
use crate::layout::*;
use crate::svg::*;
use vibrissa_io::atomic::write_atomic;

/// Which files a figure is written as: `--figures none|svg|png|all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum FigureFormats {
    /// No figures (the fastest run; the CSVs and `scene.ron` only).
    None,
    /// SVG only (the command line's default: small, vector, for papers).
    Svg,
    /// PNG only (twice the SVG's size, for slides).
    Png,
    /// SVG and PNG (the library's default, as `cargo xtask reproduce` writes them).
    #[default]
    All,
}

impl FigureFormats {
    /// Whether the SVG is written.
    pub fn svg(self) -> bool {
        matches!(self, FigureFormats::Svg | FigureFormats::All)
    }

    /// Whether the PNG is written.
    pub fn png(self) -> bool {
        matches!(self, FigureFormats::Png | FigureFormats::All)
    }
}

/// How figures are written: the printed size they are drawn for ([`FigureSize`], `--size`)
/// and the files written ([`FigureFormats`], `--figures`). The default is the library's: one
/// journal column, SVG and PNG.
///
/// Each figure writer is a method of this value, so the size and formats travel with the
/// call (no process-wide setting):
///
/// ```
/// use vibrissa_plot::{Chart, FigureFormats, FigureSize, FigureStyle, Series, Style};
/// let chart = Chart::new("t", "x", "y").with(Series::new("s", vec![(0.0, 0.0), (1.0, 1.0)], Style::Line));
/// let dir = std::env::temp_dir().join(format!("vibrissa-plot-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let style = FigureStyle::new(FigureSize::Page, FigureFormats::Svg);
/// style.write_svg(&chart, &dir.join("t.svg"), (640, 480)).unwrap();
/// let svg = std::fs::read_to_string(dir.join("t.svg")).unwrap();
/// assert!(svg.contains("width=\"175mm\"")); // printed on both columns of a page
/// assert!(!dir.join("t.png").exists()); // SVG only
/// std::fs::remove_dir_all(&dir).unwrap();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FigureStyle {
    /// The printed size: the canvas width in points and the PNG's resolution.
    pub size: FigureSize,
    /// Which files each figure is written as.
    pub formats: FigureFormats,
}

impl FigureStyle {
    /// The style of figures printed at `size`, written as `formats`.
    pub const fn new(size: FigureSize, formats: FigureFormats) -> Self {
        FigureStyle { size, formats }
    }

    /// The same formats, printed at `size` (e.g. a one-panel figure one column wide among
    /// page-wide ones).
    pub const fn sized(self, size: FigureSize) -> Self {
        FigureStyle { size, ..self }
    }

    /// Whether any file is written ([`FigureFormats::None`] writes none, and a caller may
    /// skip computing what only a figure would show).
    pub fn draws(self) -> bool {
        self.formats != FigureFormats::None
    }

    /// Writes `chart` as an SVG of `size` pixels (width, height; the design's aspect) to
    /// `path` and a PNG twin beside it ([`png_path`]), atomically, as the style says.
    pub fn write_svg(self, chart: &Chart, path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
        self.write_figure(&[Panel::Chart(chart)], 1, path, size)
    }

    /// Writes several charts as panels of one figure, `cols` per row, row by row.
    pub fn write_svg_panels(
        self,
        charts: &[Chart],
        cols: usize,
        path: &Path,
        size: (u32, u32),
    ) -> Result<(), PlotError> {
        let panels: Vec<Panel<'_>> = charts.iter().map(Panel::Chart).collect();
        self.write_figure(&panels, cols, path, size)
    }

    /// Writes a figure made of charts and maps, `cols` panels per row: the SVG at `path`
    /// and its PNG twin at [`png_path`], as the style says. Nothing is written if either
    /// fails.
    pub fn write_figure(
        self,
        panels: &[Panel<'_>],
        cols: usize,
        path: &Path,
        size: (u32, u32),
    ) -> Result<(), PlotError> {
        render_and_write(path, self, || render_figure(panels, cols, size, self.size))
    }

    /// Writes charts as panels of one figure under a common [`Heading`] with one legend
    /// for all panels (taken from the first chart), as the style says.
    pub fn write_panels_with_heading(
        self,
        charts: &[Chart],
        cols: usize,
        heading: &Heading,
        path: &Path,
        size: (u32, u32),
    ) -> Result<(), PlotError> {
        render_and_write(path, self, || {
            render_figure_with(charts, cols, size, heading, self.size)
        })
    }
}

/// Writes a rendered SVG at `path` and/or its PNG twin (at the print's resolution) at
/// [`png_path`], as `style` says; nothing is written if the PNG cannot be rendered.
fn write_rendered(svg: &str, path: &Path, style: FigureStyle) -> Result<(), PlotError> {
    let formats = style.formats;
    let png = if formats.png() {
        Some(
            render_png(svg, (style.size.png_dpi() / 96.0) as f32).map_err(|reason| {
                PlotError::Draw {
                    path: path.to_path_buf(),
                    reason,
                }
            })?,
        )
    } else {
        None
    };
    if formats.svg() {
        write_atomic(path, svg.as_bytes())?;
    }
    match png {
        Some(png) => Ok(write_atomic(&png_path(path), &png)?),
        None => Ok(()),
    }
}

/// Runs two figure writers at once (`a` on another thread of rayon's pool,
/// [`bvp_solvers::parallel::both`]; rasterising a PNG is the
/// costly part) and returns the first error (`a`'s before `b`'s); a panic in either is
/// passed on.
pub fn both<A, B, E>(a: A, b: B) -> Result<(), E>
where
    A: FnOnce() -> Result<(), E> + Send,
    B: FnOnce() -> Result<(), E>,
    E: Send,
{
    let (rb, ra) = bvp_solvers::parallel::both(b, a);
    ra.and(rb)
}

/// The PNG written beside the SVG `svg`: same name, extension `png`.
pub fn png_path(svg: &Path) -> PathBuf {
    svg.with_extension("png")
}

/// Renders a figure's SVG (unless no figures are wanted) and writes it with its PNG twin
/// at `path`, as `style` says; a rendering failure names the path.
fn render_and_write(
    path: &Path,
    style: FigureStyle,
    render: impl FnOnce() -> Result<String, String>,
) -> Result<(), PlotError> {
    if !style.draws() {
        return Ok(());
    }
    let svg = render().map_err(|reason| PlotError::Draw {
        path: path.to_path_buf(),
        reason,
    })?;
    write_rendered(&svg, path, style)
}

/// Renders an SVG text (as written by [`render_figure`]) to PNG at `scale` times its size
/// at 96 dpi (so `300 / 96` gives a 300 dpi print), with the embedded font only.
///
/// The font database is built once per process from the embedded font and kept in a
/// `OnceLock`: an immutable cache (every call would build the same database), not state
/// that a caller can set or observe.
pub fn render_png(svg: &str, scale: f32) -> Result<Vec<u8>, String> {
    static FONTS: OnceLock<std::sync::Arc<resvg::usvg::fontdb::Database>> = OnceLock::new();
    let fonts = FONTS.get_or_init(|| {
        let mut db = resvg::usvg::fontdb::Database::new();
        db.load_font_data(font_data().to_vec());
        db.set_sans_serif_family("DejaVu Sans");
        std::sync::Arc::new(db)
    });
    let opt = resvg::usvg::Options {
        font_family: "DejaVu Sans".to_string(),
        fontdb: fonts.clone(),
        ..resvg::usvg::Options::default()
    };
    let tree = resvg::usvg::Tree::from_str(svg, &opt).map_err(|e| format!("SVG: {e}"))?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * scale).ceil() as u32,
        (size.height() * scale).ceil() as u32,
    );
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| format!("cannot allocate a {w}x{h} image"))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| format!("PNG: {e}"))
}
