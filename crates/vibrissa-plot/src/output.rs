//! Writing figures: the formats (`--figures`), atomic SVG and PNG files (the PNG at 300
//! dpi of the print), figures drawn two at a time.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::*;
use crate::error::PlotError;
use vibrissa_io::atomic::write_atomic;

/// Writes `chart` as an SVG of `size` pixels (width, height) to `path` and a PNG twin
/// beside it ([`png_path`]), atomically.
pub fn write_svg(chart: &Chart, path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    write_figure(&[Panel::Chart(chart)], 1, path, size)
}

/// Writes several charts as panels of one figure, `cols` per row, row by row.
pub fn write_svg_panels(
    charts: &[Chart],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let panels: Vec<Panel<'_>> = charts.iter().map(Panel::Chart).collect();
    write_figure(&panels, cols, path, size)
}

/// Which files a figure is written as: `--figures none|svg|png|all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum FigureFormats {
    /// No figures (the fastest run; the CSVs and `scene.ron` only).
    None,
    /// SVG only (the command line's default: small, vector, for papers).
    Svg,
    /// PNG only (twice the SVG's size, for slides).
    Png,
    /// SVG and PNG (the library's default, as `cargo xtask reproduce` writes them).
    All,
}

impl FigureFormats {
    fn code(self) -> u8 {
        self as u8
    }

    fn from_code(c: u8) -> Self {
        match c {
            0 => FigureFormats::None,
            1 => FigureFormats::Svg,
            2 => FigureFormats::Png,
            _ => FigureFormats::All,
        }
    }

    /// Whether the SVG is written.
    pub fn svg(self) -> bool {
        matches!(self, FigureFormats::Svg | FigureFormats::All)
    }

    /// Whether the PNG is written.
    pub fn png(self) -> bool {
        matches!(self, FigureFormats::Png | FigureFormats::All)
    }
}

static FORMATS: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(3);

/// Sets the formats every figure of this process is written in (the binary sets it once
/// from `--figures` before running a command).
pub fn set_figure_formats(f: FigureFormats) {
    FORMATS.store(f.code(), std::sync::atomic::Ordering::Relaxed);
}

/// The formats figures are written in ([`FigureFormats::All`] unless set).
pub fn figure_formats() -> FigureFormats {
    FigureFormats::from_code(FORMATS.load(std::sync::atomic::Ordering::Relaxed))
}

/// Writes a rendered SVG at `path` and/or its PNG twin (twice the size) at [`png_path`], as
/// [`figure_formats`] says; nothing is written if the PNG cannot be rendered.
fn write_rendered(svg: &str, path: &Path) -> Result<(), PlotError> {
    let formats = figure_formats();
    let png = if formats.png() {
        Some(
            render_png(svg, (figure_size().png_dpi() / 96.0) as f32).map_err(|reason| {
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

/// The heading of a multi-panel figure: a title, a note and one legend for all panels (the
/// entries of the first chart), above the panels.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Heading {
    /// The figure's title.
    pub title: String,
    /// A note line under it (scene, units).
    pub note: String,
}

/// Writes charts as panels of one figure under a common [`Heading`] with one legend for
/// all panels (taken from the first chart), SVG and PNG.
pub fn write_panels_with_heading(
    charts: &[Chart],
    cols: usize,
    heading: &Heading,
    path: &Path,
    size: (u32, u32),
) -> Result<(), PlotError> {
    render_and_write(path, || render_figure_with(charts, cols, size, heading))
}

/// Writes a figure made of charts and maps, `cols` panels per row: the SVG at `path` and
/// its PNG twin (twice the size) at [`png_path`], as [`figure_formats`] says. Nothing is
/// written if either fails.
pub fn write_figure(
    panels: &[Panel<'_>],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), PlotError> {
    render_and_write(path, || render_figure(panels, cols, size))
}

/// Renders a figure's SVG (unless no figures are wanted) and writes it with its PNG twin
/// at `path`; a rendering failure names the path.
fn render_and_write(
    path: &Path,
    render: impl FnOnce() -> Result<String, String>,
) -> Result<(), PlotError> {
    if figure_formats() == FigureFormats::None {
        return Ok(());
    }
    let svg = render().map_err(|reason| PlotError::Draw {
        path: path.to_path_buf(),
        reason,
    })?;
    write_rendered(&svg, path)
}

/// Renders an SVG text (as written by [`render_figure`]) to PNG at `scale` times its size
/// at 96 dpi (so `300 / 96` gives a 300 dpi print), with the embedded font only.
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
