//! A small declarative chart API with its own SVG renderer, used by the CLI and by
//! `cargo xtask reproduce` for every figure; each SVG gets a PNG twin rendered with resvg.
//!
//! A [`Chart`] is a titled x-y plot of [`Series`] (lines, dashed lines, points) with
//! automatic ranges, optional log axes (non-positive values are skipped), an optional equal
//! aspect ratio for beam shapes, [`Mark`]s (labelled vertical event lines, highlighted
//! points, arrows) and a note line under the title. NaN points are skipped and split lines.
//! [`write_svg_panels`] puts several charts in one figure; [`HeatMap`] draws categorical
//! maps (stability maps).
//!
//! What a reader of a paper needs: coordinates are written with 1/100 pixel resolution (no
//! jagged curves), text is measured with the embedded DejaVu Sans font, so legends and
//! labels are sized to their text and placed outside the plotting area (they never cover
//! data), event labels sit in a band above the plot, staggered when close. The PNG is
//! rendered at twice the SVG's size with the same embedded font (no system fonts).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use crate::atomic::write_atomic;
use crate::error::CliError;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// A solid line.
    #[default]
    Line,
    /// A dashed line.
    Dashed,
    /// Markers only.
    Points,
    /// A solid line with markers.
    LinePoints,
}

/// One data series of a chart.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend text; an empty name leaves the series out of the legend.
    pub name: String,
    /// The points; NaN (or, on log axes, non-positive) points are skipped and split lines.
    pub points: Vec<(f64, f64)>,
    /// How to draw it.
    pub style: Style,
    /// Index into [`PALETTE`] (taken modulo its length).
    pub color: usize,
}

impl Series {
    /// A series with colour 0.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series {
            name: name.into(),
            points,
            style,
            color: 0,
        }
    }

    /// Sets the colour index.
    pub fn color(mut self, color: usize) -> Self {
        self.color = color;
        self
    }
}

/// What a [`Mark`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarkKind {
    /// A dashed vertical line at `x` over the whole plot, labelled above the plot.
    VLine,
    /// A ring around the data point `(x, y)`, explained in the legend.
    Point,
    /// An arrow from `(x, y)` by `(dx, dy)` (data units), explained in the legend.
    Arrow {
        /// Arrow length along x.
        dx: f64,
        /// Arrow length along y.
        dy: f64,
    },
}

/// An annotation of a chart: an event line, a highlighted point or an arrow.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// What to draw.
    pub kind: MarkKind,
    /// Position x (data units).
    pub x: f64,
    /// Position y (data units; unused by [`MarkKind::VLine`]).
    pub y: f64,
    /// Its label (above the plot for lines, in the legend otherwise; empty for none).
    pub label: String,
    /// Index into [`PALETTE`].
    pub color: usize,
}

impl Mark {
    /// A labelled vertical event line at `x`.
    pub fn vline(x: f64, label: impl Into<String>, color: usize) -> Self {
        Mark {
            kind: MarkKind::VLine,
            x,
            y: f64::NAN,
            label: label.into(),
            color,
        }
    }

    /// A highlighted point, explained in the legend.
    pub fn point(x: f64, y: f64, label: impl Into<String>, color: usize) -> Self {
        Mark {
            kind: MarkKind::Point,
            x,
            y,
            label: label.into(),
            color,
        }
    }

    /// An arrow from `(x, y)` by `(dx, dy)`, explained in the legend.
    pub fn arrow(x: f64, y: f64, dx: f64, dy: f64, label: impl Into<String>, color: usize) -> Self {
        Mark {
            kind: MarkKind::Arrow { dx, dy },
            x,
            y,
            label: label.into(),
            color,
        }
    }
}

/// A titled x-y chart.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    /// The caption above the plot.
    pub title: String,
    /// The x axis label (symbol and unit, e.g. `x₀ [mm]`).
    pub x_label: String,
    /// The y axis label.
    pub y_label: String,
    /// Logarithmic x axis.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// The data.
    pub series: Vec<Series>,
    /// Same scale on both axes (for beam shapes); ignored with a log axis.
    pub aspect_equal: bool,
    /// Annotations.
    pub marks: Vec<Mark>,
    /// A small note under the title (e.g. the unit system), empty for none.
    pub note: String,
    /// Leave the legend out (a figure heading shows it for all panels).
    pub hide_legend: bool,
}

impl Chart {
    /// An empty linear chart.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Chart::default()
        }
    }

    /// Adds a series.
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a mark.
    pub fn mark(mut self, mark: Mark) -> Self {
        self.marks.push(mark);
        self
    }

    /// Sets the note under the title.
    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.note = note.into();
        self
    }

    /// Sets log scales on the axes.
    pub fn log(mut self, x_log: bool, y_log: bool) -> Self {
        self.x_log = x_log;
        self.y_log = y_log;
        self
    }

    /// Requests the same scale on both axes.
    pub fn equal_aspect(mut self) -> Self {
        self.aspect_equal = true;
        self
    }
}

/// A categorical map: each cell of a grid over (x, y) belongs to one category.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HeatMap {
    /// The caption.
    pub title: String,
    /// The x axis label.
    pub x_label: String,
    /// The y axis label.
    pub y_label: String,
    /// Cell centres along x, strictly increasing.
    pub x_values: Vec<f64>,
    /// Cell centres along y, strictly increasing.
    pub y_values: Vec<f64>,
    /// `cells[iy][ix]` is the category index of the cell at `(x_values[ix], y_values[iy])`.
    pub cells: Vec<Vec<u8>>,
    /// Category names and RGB colours, indexed by the cell values.
    pub categories: Vec<(String, (u8, u8, u8))>,
}

/// One panel of a multi-panel figure.
#[derive(Debug, Clone, Copy)]
pub enum Panel<'a> {
    /// An x-y chart.
    Chart(&'a Chart),
    /// A categorical map.
    HeatMap(&'a HeatMap),
}

/// The series colours (Tableau 10).
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// The colour of index `i` (modulo the palette length).
pub fn palette(i: usize) -> (u8, u8, u8) {
    PALETTE[i % PALETTE.len()]
}

fn rgb(c: (u8, u8, u8)) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// Writes `chart` as an SVG of `size` pixels (width, height) to `path` and a PNG twin
/// beside it ([`png_path`]), atomically.
pub fn write_svg(chart: &Chart, path: &Path, size: (u32, u32)) -> Result<(), CliError> {
    write_figure(&[Panel::Chart(chart)], 1, path, size)
}

/// Writes several charts as panels of one figure, `cols` per row, row by row.
pub fn write_svg_panels(
    charts: &[Chart],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), CliError> {
    let panels: Vec<Panel<'_>> = charts.iter().map(Panel::Chart).collect();
    write_figure(&panels, cols, path, size)
}

/// Writes `map` as an SVG (and PNG) of `size` pixels to `path`, atomically.
pub fn write_heatmap_svg(map: &HeatMap, path: &Path, size: (u32, u32)) -> Result<(), CliError> {
    write_figure(&[Panel::HeatMap(map)], 1, path, size)
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
) -> Result<(), CliError> {
    let fail = |reason: String| CliError::Plot {
        path: path.to_path_buf(),
        reason,
    };
    let svg = render_figure_with(charts, cols, size, heading).map_err(fail)?;
    let png = render_png(&svg, 2.0).map_err(fail)?;
    write_atomic(path, svg.as_bytes())?;
    write_atomic(&png_path(path), &png)
}

/// Renders charts under a [`Heading`] (what [`write_panels_with_heading`] writes).
pub fn render_figure_with(
    charts: &[Chart],
    cols: usize,
    size: (u32, u32),
    heading: &Heading,
) -> Result<String, String> {
    let Some(first) = charts.first() else {
        return Err("no panels to draw".to_string());
    };
    if cols == 0 {
        return Err("the number of panel columns must be at least 1".to_string());
    }
    let mut svg = Svg::new(size);
    let full = Rect {
        x: 0.0,
        y: 0.0,
        w: f64::from(size.0),
        h: f64::from(size.1),
    };
    let mut top = draw_heading(&mut svg, full, &heading.title, &heading.note);
    // One legend row (wrapped) for all panels.
    let entries = legend_entries(first);
    if !entries.is_empty() {
        let widths: Vec<f64> = entries
            .iter()
            .map(|e| SAMPLE_W + 6.0 + text_width(e.label(), LEGEND_SIZE) + 18.0)
            .collect();
        let mut rows: Vec<Vec<usize>> = vec![vec![]];
        let mut used = 0.0;
        for (i, w) in widths.iter().enumerate() {
            if used + w > full.w - 2.0 * PAD && !rows.last().is_some_and(Vec::is_empty) {
                rows.push(vec![]);
                used = 0.0;
            }
            used += w;
            if let Some(r) = rows.last_mut() {
                r.push(i);
            }
        }
        for r in &rows {
            let total: f64 = r.iter().map(|&i| widths[i]).sum();
            let mut x = (full.w - total) / 2.0;
            let cy = top + 4.0 + ROW_H / 2.0;
            for &i in r {
                draw_legend_entry(&mut svg, x, cy, &entries[i]);
                x += widths[i];
            }
            top += ROW_H;
        }
        top += 6.0;
    }
    let n = charts.len();
    let rows = n.div_ceil(cols);
    let cols = cols.min(n);
    let (pw, ph) = (full.w / cols as f64, (full.h - top) / rows as f64);
    for (i, chart) in charts.iter().enumerate() {
        let area = Rect {
            x: (i % cols) as f64 * pw,
            y: top + (i / cols) as f64 * ph,
            w: pw,
            h: ph,
        };
        let mut c = chart.clone();
        c.hide_legend = true;
        draw_chart(&mut svg, area, &c, i)?;
    }
    Ok(svg.finish())
}

/// Writes a figure made of charts and maps, `cols` panels per row: the SVG at `path` and
/// its PNG twin (twice the size) at [`png_path`]. Nothing is written if either fails.
pub fn write_figure(
    panels: &[Panel<'_>],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), CliError> {
    let fail = |reason: String| CliError::Plot {
        path: path.to_path_buf(),
        reason,
    };
    let svg = render_figure(panels, cols, size).map_err(fail)?;
    let png = render_png(&svg, 2.0).map_err(fail)?;
    write_atomic(path, svg.as_bytes())?;
    write_atomic(&png_path(path), &png)
}

/// The embedded font (DejaVu Sans, free licence, shipped by the `dejavu` crate).
fn font_data() -> &'static [u8] {
    dejavu::sans::regular()
}

fn face() -> Option<&'static ttf_parser::Face<'static>> {
    static FACE: OnceLock<Option<ttf_parser::Face<'static>>> = OnceLock::new();
    FACE.get_or_init(|| ttf_parser::Face::parse(font_data(), 0).ok())
        .as_ref()
}

/// The width in pixels of `text` set in the embedded font at `size` pixels.
pub fn text_width(text: &str, size: f64) -> f64 {
    let Some(face) = face() else {
        return 0.6 * size * text.chars().count() as f64;
    };
    let upem = f64::from(face.units_per_em());
    let units: f64 = text
        .chars()
        .map(|c| {
            face.glyph_index(c)
                .and_then(|g| face.glyph_hor_advance(g))
                .map_or(0.6 * upem, f64::from)
        })
        .sum();
    units / upem * size
}

/// Renders an SVG text (as written by [`render_figure`]) to PNG at `scale` times its size,
/// with the embedded font only.
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

/// Renders a figure to an SVG string (what [`write_figure`] writes).
pub fn render_figure(
    panels: &[Panel<'_>],
    cols: usize,
    size: (u32, u32),
) -> Result<String, String> {
    if panels.is_empty() {
        return Err("no panels to draw".to_string());
    }
    if cols == 0 {
        return Err("the number of panel columns must be at least 1".to_string());
    }
    if size.0 < 50 || size.1 < 50 {
        return Err(format!("size {}x{} is too small", size.0, size.1));
    }
    let rows = panels.len().div_ceil(cols);
    let cols = cols.min(panels.len());
    let (pw, ph) = (
        f64::from(size.0) / cols as f64,
        f64::from(size.1) / rows as f64,
    );
    let mut svg = Svg::new(size);
    for (i, panel) in panels.iter().enumerate() {
        let area = Rect {
            x: (i % cols) as f64 * pw,
            y: (i / cols) as f64 * ph,
            w: pw,
            h: ph,
        };
        match panel {
            Panel::Chart(c) => draw_chart(&mut svg, area, c, i)?,
            Panel::HeatMap(m) => draw_heatmap(&mut svg, area, m, i)?,
        }
    }
    Ok(svg.finish())
}

const FONT: &str = "DejaVu Sans, Verdana, sans-serif";
const TITLE_SIZE: f64 = 15.0;
const NOTE_SIZE: f64 = 11.0;
const LABEL_SIZE: f64 = 13.0;
const TICK_SIZE: f64 = 11.0;
const LEGEND_SIZE: f64 = 12.0;
const EVENT_SIZE: f64 = 11.0;
const PAD: f64 = 8.0;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

/// An SVG document under construction.
struct Svg {
    out: String,
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A coordinate with 1/100 pixel resolution.
fn c(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

impl Svg {
    fn new(size: (u32, u32)) -> Self {
        let mut out = String::new();
        let _ = write!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
             viewBox=\"0 0 {w} {h}\" font-family=\"{FONT}\">\n\
             <rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n",
            w = size.0,
            h = size.1
        );
        Svg { out }
    }

    fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }

    /// Text with its baseline at `y`; `anchor` is start, middle or end.
    #[allow(clippy::too_many_arguments)]
    fn text(&mut self, x: f64, y: f64, s: &str, size: f64, anchor: &str, fill: &str, rotate: bool) {
        let rot = if rotate {
            format!(" transform=\"rotate(-90 {} {})\"", c(x), c(y))
        } else {
            String::new()
        };
        let _ = writeln!(
            self.out,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{fill}\"{rot}>{}</text>",
            c(x),
            c(y),
            size,
            esc(s)
        );
    }

    fn line(&mut self, a: (f64, f64), b: (f64, f64), stroke: &str, width: f64, dash: Option<&str>) {
        let dash = dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
        let _ = writeln!(
            self.out,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{stroke}\" stroke-width=\"{width}\"{dash}/>",
            c(a.0),
            c(a.1),
            c(b.0),
            c(b.1)
        );
    }

    fn rect(&mut self, r: Rect, fill: &str, stroke: Option<&str>) {
        let stroke = stroke.map_or(String::new(), |s| {
            format!(" stroke=\"{s}\" stroke-width=\"1\"")
        });
        let _ = writeln!(
            self.out,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\"{stroke}/>",
            c(r.x),
            c(r.y),
            c(r.w),
            c(r.h)
        );
    }

    fn polyline(
        &mut self,
        pts: &[(f64, f64)],
        stroke: &str,
        width: f64,
        dash: Option<&str>,
        clip: &str,
    ) {
        if pts.len() < 2 {
            return;
        }
        let mut d = String::new();
        for (i, p) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{} {}",
                if i == 0 { "M" } else { " L" },
                c(p.0),
                c(p.1)
            );
        }
        let dash = dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
        let _ = writeln!(
            self.out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{width}\" \
             stroke-linejoin=\"round\" stroke-linecap=\"round\"{dash} clip-path=\"url(#{clip})\"/>"
        );
    }

    fn circle(&mut self, p: (f64, f64), r: f64, fill: &str, stroke: Option<(&str, f64)>) {
        let stroke = stroke.map_or(String::new(), |(s, w)| {
            format!(" stroke=\"{s}\" stroke-width=\"{w}\"")
        });
        let _ = writeln!(
            self.out,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\"{stroke}/>",
            c(p.0),
            c(p.1),
            r
        );
    }

    fn arrow(&mut self, a: (f64, f64), b: (f64, f64), color: &str) {
        self.line(a, b, color, 2.0, None);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy).max(1e-9);
        let (ux, uy) = (dx / len, dy / len);
        let (hl, hw) = (9.0, 4.5);
        let p1 = (b.0 - ux * hl - uy * hw, b.1 - uy * hl + ux * hw);
        let p2 = (b.0 - ux * hl + uy * hw, b.1 - uy * hl - ux * hw);
        let _ = writeln!(
            self.out,
            "<path d=\"M{} {} L{} {} L{} {} Z\" fill=\"{color}\"/>",
            c(b.0),
            c(b.1),
            c(p1.0),
            c(p1.1),
            c(p2.0),
            c(p2.1)
        );
    }

    fn clip(&mut self, id: &str, r: Rect) {
        let _ = writeln!(
            self.out,
            "<clipPath id=\"{id}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
            c(r.x - 4.0),
            c(r.y - 4.0),
            c(r.w + 8.0),
            c(r.h + 8.0)
        );
    }
}

fn is_valid(p: (f64, f64), x_log: bool, y_log: bool) -> bool {
    p.0.is_finite() && p.1.is_finite() && (!x_log || p.0 > 0.0) && (!y_log || p.1 > 0.0)
}

/// Splits the points into runs of consecutive valid points.
fn runs(points: &[(f64, f64)], x_log: bool, y_log: bool) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for &p in points {
        if is_valid(p, x_log, y_log) {
            cur.push(p);
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The padded range of `values` on a linear or log axis. A range narrower than 1e-9 of its
/// magnitude (a constant up to rounding) is widened so that its ticks stay distinct.
fn axis_range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        if hi / lo < 1.0 + 1e-9 {
            return (lo / 2.0, hi * 2.0);
        }
        let f = (hi / lo).powf(0.04);
        (lo / f, hi * f)
    } else {
        let mag = lo.abs().max(hi.abs());
        if hi - lo <= 1e-9 * mag || hi == lo {
            let mid = 0.5 * (lo + hi);
            let pad = if mag == 0.0 { 1.0 } else { mag * 0.1 };
            return (mid - pad, mid + pad);
        }
        let pad = (hi - lo) * 0.04;
        (lo - pad, hi + pad)
    }
}

/// A linear or logarithmic mapping from data to pixels.
#[derive(Debug, Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    p0: f64,
    p1: f64,
}

impl Axis {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    fn px(&self, v: f64) -> f64 {
        self.p0 + self.t(v) * (self.p1 - self.p0)
    }

    /// Tick values and labels, about `target` of them.
    fn ticks(&self, target: usize) -> Vec<(f64, String)> {
        if self.log {
            let (a, b) = (
                self.lo.log10().ceil() as i32,
                self.hi.log10().floor() as i32,
            );
            let decades = (b - a + 1).max(0) as usize;
            let step = decades.div_ceil(target.max(1)).max(1) as i32;
            // One notation per axis: plain numbers if every decade is between 0.01 and
            // 1000, else 1eN throughout.
            let plain = a >= -2 && b <= 3;
            let decade = |e: i32| {
                if plain {
                    format_tick(10f64.powi(e))
                } else {
                    format!("1e{e}")
                }
            };
            let mut out: Vec<(f64, String)> = (a..=b)
                .step_by(step as usize)
                .map(|e| (10f64.powi(e), decade(e)))
                .collect();
            if decades < 2 {
                for e in (a - 1)..=b {
                    for m in [2.0, 5.0] {
                        let v = m * 10f64.powi(e);
                        if v >= self.lo && v <= self.hi {
                            out.push((v, format_tick(v)));
                        }
                    }
                }
                out.sort_by(|x, y| x.0.total_cmp(&y.0));
            }
            return out;
        }
        let span = self.hi - self.lo;
        let raw = span / target.max(2) as f64;
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 2.5, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw * (1.0 - 1e-9))
            .unwrap_or(10.0 * mag);
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        let digits = (-(step.log10().floor()) as i32
            + if (step / mag - 2.5).abs() < 1e-9 {
                1
            } else {
                0
            })
        .max(0) as usize;
        let big = self.lo.abs().max(self.hi.abs());
        (first..=last)
            .map(|k| {
                let v = k as f64 * step;
                let v = if v.abs() < step * 1e-9 { 0.0 } else { v };
                let label = if big >= 1e5 || (big < 1e-3 && big > 0.0) {
                    format_tick(v)
                } else {
                    format!("{v:.digits$}")
                };
                (v, label.replace('-', "−"))
            })
            .collect()
    }
}

/// Compact tick labels: plain decimals for moderate magnitudes, scientific otherwise.
pub fn format_tick(v: f64) -> String {
    let a = v.abs();
    if a < 1e-300 {
        return "0".to_string();
    }
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    } else {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((m, e)) => {
                let m = if m.contains('.') {
                    m.trim_end_matches('0').trim_end_matches('.')
                } else {
                    m
                };
                format!("{m}e{e}")
            }
            None => s,
        }
    }
}

/// One legend entry.
enum Entry<'a> {
    Series(&'a Series),
    Point(&'a Mark),
    Arrow(&'a Mark),
    Swatch(&'a str, (u8, u8, u8)),
}

impl Entry<'_> {
    fn label(&self) -> &str {
        match self {
            Entry::Series(s) => &s.name,
            Entry::Point(m) | Entry::Arrow(m) => &m.label,
            Entry::Swatch(n, _) => n,
        }
    }
}

const SAMPLE_W: f64 = 26.0;
const ROW_H: f64 = 17.0;

fn legend_width(entries: &[Entry<'_>]) -> f64 {
    if entries.is_empty() {
        return 0.0;
    }
    let text = entries
        .iter()
        .map(|e| text_width(e.label(), LEGEND_SIZE))
        .fold(0.0, f64::max);
    PAD + 6.0 + SAMPLE_W + 6.0 + text + 8.0
}

/// Draws the legend box with its top-left corner at `(x, y)`.
fn draw_legend(svg: &mut Svg, x: f64, y: f64, entries: &[Entry<'_>]) {
    if entries.is_empty() {
        return;
    }
    let w = legend_width(entries) - PAD;
    let h = 6.0 + ROW_H * entries.len() as f64;
    svg.rect(Rect { x, y, w, h }, "#ffffff", Some("#b0b0b0"));
    for (i, e) in entries.iter().enumerate() {
        let cy = y + 3.0 + ROW_H * (i as f64 + 0.5);
        draw_legend_entry(svg, x + 6.0, cy, e);
    }
}

/// Draws one legend entry: its sample from `x` and its text after it, centred on `cy`.
fn draw_legend_entry(svg: &mut Svg, x: f64, cy: f64, e: &Entry<'_>) {
    {
        let (sx0, sx1) = (x, x + SAMPLE_W);
        match e {
            Entry::Series(s) => {
                let col = rgb(palette(s.color));
                match s.style {
                    Style::Line | Style::LinePoints => {
                        svg.line((sx0, cy), (sx1, cy), &col, 2.0, None)
                    }
                    Style::Dashed => svg.line((sx0, cy), (sx1, cy), &col, 2.0, Some("6 4")),
                    Style::Points => {}
                }
                if matches!(s.style, Style::Points | Style::LinePoints) {
                    svg.circle(((sx0 + sx1) / 2.0, cy), 3.0, &col, None);
                }
            }
            Entry::Point(m) => {
                let col = rgb(palette(m.color));
                svg.circle(((sx0 + sx1) / 2.0, cy), 5.0, "none", Some((&col, 2.0)));
            }
            Entry::Arrow(m) => {
                let col = rgb(palette(m.color));
                svg.arrow((sx0, cy), (sx1, cy), &col);
            }
            Entry::Swatch(_, col) => {
                svg.rect(
                    Rect {
                        x: sx0 + 6.0,
                        y: cy - 6.0,
                        w: 14.0,
                        h: 12.0,
                    },
                    &rgb(*col),
                    Some("#808080"),
                );
            }
        }
        svg.text(
            sx1 + 6.0,
            cy + 4.0,
            e.label(),
            LEGEND_SIZE,
            "start",
            "#202020",
            false,
        );
    }
}

/// The legend entries of a chart: named series, then labelled points and arrows.
fn legend_entries(chart: &Chart) -> Vec<Entry<'_>> {
    let mut entries: Vec<Entry<'_>> = chart
        .series
        .iter()
        .filter(|s| !s.name.is_empty())
        .map(Entry::Series)
        .collect();
    for m in &chart.marks {
        match m.kind {
            MarkKind::Point if !m.label.is_empty() => entries.push(Entry::Point(m)),
            MarkKind::Arrow { .. } if !m.label.is_empty() => entries.push(Entry::Arrow(m)),
            _ => {}
        }
    }
    entries
}

/// The heading of a panel (title and note); returns its height.
fn draw_heading(svg: &mut Svg, area: Rect, title: &str, note: &str) -> f64 {
    let mut y = area.y + PAD;
    if !title.is_empty() {
        y += TITLE_SIZE;
        svg.text(
            area.x + area.w / 2.0,
            y,
            title,
            TITLE_SIZE,
            "middle",
            "#000000",
            false,
        );
        y += 4.0;
    }
    if !note.is_empty() {
        y += NOTE_SIZE;
        svg.text(
            area.x + area.w / 2.0,
            y,
            note,
            NOTE_SIZE,
            "middle",
            "#555555",
            false,
        );
        y += 3.0;
    }
    y - area.y
}

/// The plot rectangle inside `area` below a heading of height `head`, leaving room for the
/// tick labels (`ytick_w` wide), axis labels, the legend (`legend_w`) and an event band.
fn plot_rect(area: Rect, head: f64, band: f64, ytick_w: f64, legend_w: f64) -> Rect {
    let left = PAD + LABEL_SIZE + 6.0 + ytick_w + 6.0;
    let bottom = TICK_SIZE + 6.0 + LABEL_SIZE + 6.0 + PAD;
    let top = head + band + 6.0;
    Rect {
        x: area.x + left,
        y: area.y + top,
        w: (area.w - left - legend_w - PAD - 4.0).max(20.0),
        h: (area.h - top - bottom).max(20.0),
    }
}

#[allow(clippy::too_many_arguments)]
fn draw_axes(
    svg: &mut Svg,
    r: Rect,
    xa: &Axis,
    ya: &Axis,
    xt: &[(f64, String)],
    yt: &[(f64, String)],
    x_label: &str,
    y_label: &str,
    grid: bool,
) {
    for (v, label) in xt {
        let px = xa.px(*v);
        if grid {
            svg.line((px, r.y), (px, r.y + r.h), "#e6e6e6", 1.0, None);
        }
        svg.line((px, r.y + r.h), (px, r.y + r.h + 4.0), "#404040", 1.0, None);
        svg.text(
            px,
            r.y + r.h + 6.0 + TICK_SIZE,
            label,
            TICK_SIZE,
            "middle",
            "#303030",
            false,
        );
    }
    let mut ytick_w: f64 = 0.0;
    for (v, label) in yt {
        let py = ya.px(*v);
        if grid {
            svg.line((r.x, py), (r.x + r.w, py), "#e6e6e6", 1.0, None);
        }
        svg.line((r.x - 4.0, py), (r.x, py), "#404040", 1.0, None);
        svg.text(
            r.x - 6.0,
            py + TICK_SIZE * 0.36,
            label,
            TICK_SIZE,
            "end",
            "#303030",
            false,
        );
        ytick_w = ytick_w.max(text_width(label, TICK_SIZE));
    }
    svg.rect(r, "none", Some("#404040"));
    svg.text(
        r.x + r.w / 2.0,
        r.y + r.h + 6.0 + TICK_SIZE + 6.0 + LABEL_SIZE,
        x_label,
        LABEL_SIZE,
        "middle",
        "#000000",
        false,
    );
    let lx = r.x - 6.0 - ytick_w - 6.0 - 3.0;
    svg.text(
        lx,
        r.y + r.h / 2.0,
        y_label,
        LABEL_SIZE,
        "middle",
        "#000000",
        true,
    );
}

/// The centre of an event label of width `w` over the line at `px`, kept inside `area`.
fn label_x(px: f64, w: f64, area: Rect) -> f64 {
    let (lo, hi) = (area.x + PAD + w / 2.0, area.x + area.w - PAD - w / 2.0);
    if lo > hi {
        px
    } else {
        px.clamp(lo, hi)
    }
}

fn tick_target(pixels: f64) -> usize {
    ((pixels / 70.0).round() as usize).clamp(4, 9)
}

fn draw_chart(svg: &mut Svg, area: Rect, chart: &Chart, id: usize) -> Result<(), String> {
    let (xl, yl) = (chart.x_log, chart.y_log);
    let valid = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .chain(
                chart
                    .marks
                    .iter()
                    .filter(|m| m.kind != MarkKind::VLine)
                    .flat_map(|m| {
                        let end = match m.kind {
                            MarkKind::Arrow { dx, dy } => (m.x + dx, m.y + dy),
                            _ => (m.x, m.y),
                        };
                        [(m.x, m.y), end]
                    }),
            )
            .filter(|&p| is_valid(p, xl, yl))
    };
    let mut xr = axis_range(valid().map(|p| p.0), xl);
    let mut yr = axis_range(valid().map(|p| p.1), yl);
    let entries = if chart.hide_legend {
        Vec::new()
    } else {
        legend_entries(chart)
    };
    let legend_w = legend_width(&entries);
    let head_h = {
        let mut h = PAD;
        if !chart.title.is_empty() {
            h += TITLE_SIZE + 4.0;
        }
        if !chart.note.is_empty() {
            h += NOTE_SIZE + 3.0;
        }
        h
    };
    // A first layout to find the tick labels' width, then the final one.
    let mut ytick_w = 40.0;
    let mut rect = plot_rect(area, head_h, 0.0, ytick_w, legend_w);
    let mut band_rows: Vec<usize> = Vec::new();
    for _pass in 0..2 {
        if chart.aspect_equal && !xl && !yl {
            let (xr0, yr0) = (
                axis_range(valid().map(|p| p.0), false),
                axis_range(valid().map(|p| p.1), false),
            );
            let u = ((xr0.1 - xr0.0) / rect.w).max((yr0.1 - yr0.0) / rect.h);
            let (cx, cy) = ((xr0.0 + xr0.1) / 2.0, (yr0.0 + yr0.1) / 2.0);
            xr = (cx - u * rect.w / 2.0, cx + u * rect.w / 2.0);
            yr = (cy - u * rect.h / 2.0, cy + u * rect.h / 2.0);
        }
        let ya = Axis {
            lo: yr.0,
            hi: yr.1,
            log: yl,
            p0: rect.y + rect.h,
            p1: rect.y,
        };
        ytick_w = ya
            .ticks(tick_target(rect.h))
            .iter()
            .map(|(_, l)| text_width(l, TICK_SIZE))
            .fold(0.0, f64::max);
        // Event labels: rows of the band above the plot, staggered where they would meet.
        let xa = Axis {
            lo: xr.0,
            hi: xr.1,
            log: xl,
            p0: rect.x,
            p1: rect.x + rect.w,
        };
        band_rows.clear();
        let mut row_ends: Vec<f64> = Vec::new();
        let mut order: Vec<usize> = (0..chart.marks.len())
            .filter(|&i| chart.marks[i].kind == MarkKind::VLine)
            .collect();
        order.sort_by(|&a, &b| chart.marks[a].x.total_cmp(&chart.marks[b].x));
        let mut rows_of = vec![0usize; chart.marks.len()];
        for i in order {
            let m = &chart.marks[i];
            let w = text_width(&m.label, EVENT_SIZE);
            let px = label_x(xa.px(m.x), w, area);
            let (a, _) = (px - w / 2.0, px + w / 2.0);
            let row = row_ends
                .iter()
                .position(|&e| e + 6.0 < a)
                .unwrap_or(row_ends.len());
            if row == row_ends.len() {
                row_ends.push(f64::NEG_INFINITY);
            }
            row_ends[row] = px + w / 2.0;
            rows_of[i] = row;
        }
        band_rows = rows_of;
        let band = if row_ends.is_empty() {
            0.0
        } else {
            row_ends.len() as f64 * (EVENT_SIZE + 4.0) + 2.0
        };
        rect = plot_rect(area, head_h, band, ytick_w, legend_w);
    }
    draw_heading(svg, area, &chart.title, &chart.note);
    let xa = Axis {
        lo: xr.0,
        hi: xr.1,
        log: xl,
        p0: rect.x,
        p1: rect.x + rect.w,
    };
    let ya = Axis {
        lo: yr.0,
        hi: yr.1,
        log: yl,
        p0: rect.y + rect.h,
        p1: rect.y,
    };
    let xt = xa.ticks(tick_target(rect.w));
    let yt = ya.ticks(tick_target(rect.h));
    draw_axes(
        svg,
        rect,
        &xa,
        &ya,
        &xt,
        &yt,
        &chart.x_label,
        &chart.y_label,
        true,
    );
    let clip = format!("plot{id}");
    svg.clip(&clip, rect);
    let to_px = |p: (f64, f64)| (xa.px(p.0), ya.px(p.1));
    for s in &chart.series {
        let col = rgb(palette(s.color));
        for run in runs(&s.points, xl, yl) {
            let px: Vec<(f64, f64)> = run.iter().map(|&p| to_px(p)).collect();
            match s.style {
                Style::Line | Style::LinePoints => svg.polyline(&px, &col, 2.0, None, &clip),
                Style::Dashed => svg.polyline(&px, &col, 2.0, Some("6 4"), &clip),
                Style::Points => {}
            }
            if matches!(s.style, Style::Points | Style::LinePoints) {
                for p in px {
                    svg.circle(p, 3.0, &col, None);
                }
            }
        }
    }
    for (i, m) in chart.marks.iter().enumerate() {
        let col = rgb(palette(m.color));
        match m.kind {
            MarkKind::VLine => {
                if !(m.x.is_finite() && (!xl || m.x > 0.0)) {
                    continue;
                }
                let px = xa.px(m.x);
                svg.line((px, rect.y), (px, rect.y + rect.h), &col, 1.2, Some("4 3"));
                let row = band_rows.get(i).copied().unwrap_or(0) as f64;
                let y = rect.y - 6.0 - row * (EVENT_SIZE + 4.0);
                let lx = label_x(px, text_width(&m.label, EVENT_SIZE), area);
                svg.text(lx, y, &m.label, EVENT_SIZE, "middle", &col, false);
            }
            MarkKind::Point => {
                if is_valid((m.x, m.y), xl, yl) {
                    svg.circle(to_px((m.x, m.y)), 5.0, "none", Some((&col, 2.0)));
                }
            }
            MarkKind::Arrow { dx, dy } => {
                let end = (m.x + dx, m.y + dy);
                if is_valid((m.x, m.y), xl, yl) && is_valid(end, xl, yl) {
                    svg.arrow(to_px((m.x, m.y)), to_px(end), &col);
                }
            }
        }
    }
    draw_legend(svg, rect.x + rect.w + PAD, rect.y, &entries);
    Ok(())
}

/// Cell edges around strictly increasing centres.
fn edges(centres: &[f64], what: &str) -> Result<Vec<f64>, String> {
    if centres.is_empty() {
        return Err(format!("{what} is empty"));
    }
    if let Some(v) = centres.iter().find(|v| !v.is_finite()) {
        return Err(format!("{what} holds the non-finite value {v}"));
    }
    if let Some(i) = (1..centres.len()).find(|&i| centres[i] <= centres[i - 1]) {
        return Err(format!(
            "{what} is not strictly increasing at index {i} ({} after {})",
            centres[i],
            centres[i - 1]
        ));
    }
    let n = centres.len();
    if n == 1 {
        return Ok(vec![centres[0] - 0.5, centres[0] + 0.5]);
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(centres[0] - (centres[1] - centres[0]) / 2.0);
    for i in 1..n {
        e.push((centres[i - 1] + centres[i]) / 2.0);
    }
    e.push(centres[n - 1] + (centres[n - 1] - centres[n - 2]) / 2.0);
    Ok(e)
}

fn draw_heatmap(svg: &mut Svg, area: Rect, map: &HeatMap, _id: usize) -> Result<(), String> {
    let xe = edges(&map.x_values, "x_values")?;
    let ye = edges(&map.y_values, "y_values")?;
    if map.cells.len() != map.y_values.len() {
        return Err(format!(
            "cells has {} rows but y_values has {} values",
            map.cells.len(),
            map.y_values.len()
        ));
    }
    for (iy, row) in map.cells.iter().enumerate() {
        if row.len() != map.x_values.len() {
            return Err(format!(
                "cells row {iy} has {} cells but x_values has {} values",
                row.len(),
                map.x_values.len()
            ));
        }
        if let Some(&c) = row.iter().find(|&&c| c as usize >= map.categories.len()) {
            return Err(format!(
                "cells row {iy} uses category {c} but only {} categories are defined",
                map.categories.len()
            ));
        }
    }
    let entries: Vec<Entry<'_>> = map
        .categories
        .iter()
        .map(|(n, col)| Entry::Swatch(n.as_str(), *col))
        .collect();
    let legend_w = legend_width(&entries);
    let head = draw_heading(svg, area, &map.title, "");
    let (xr, yr) = ((xe[0], xe[xe.len() - 1]), (ye[0], ye[ye.len() - 1]));
    let mut rect = plot_rect(area, head, 0.0, 40.0, legend_w);
    let ya0 = Axis {
        lo: yr.0,
        hi: yr.1,
        log: false,
        p0: rect.y + rect.h,
        p1: rect.y,
    };
    let ytick_w = ya0
        .ticks(tick_target(rect.h))
        .iter()
        .map(|(_, l)| text_width(l, TICK_SIZE))
        .fold(0.0, f64::max);
    rect = plot_rect(area, head, 0.0, ytick_w, legend_w);
    let xa = Axis {
        lo: xr.0,
        hi: xr.1,
        log: false,
        p0: rect.x,
        p1: rect.x + rect.w,
    };
    let ya = Axis {
        lo: yr.0,
        hi: yr.1,
        log: false,
        p0: rect.y + rect.h,
        p1: rect.y,
    };
    for (iy, row) in map.cells.iter().enumerate() {
        for (ix, &cat) in row.iter().enumerate() {
            let (x0, x1) = (xa.px(xe[ix]), xa.px(xe[ix + 1]));
            let (y0, y1) = (ya.px(ye[iy + 1]), ya.px(ye[iy]));
            svg.rect(
                Rect {
                    x: x0,
                    y: y0,
                    w: x1 - x0,
                    h: y1 - y0,
                },
                &rgb(map.categories[cat as usize].1),
                None,
            );
        }
    }
    let xt = xa.ticks(tick_target(rect.w));
    let yt = ya.ticks(tick_target(rect.h));
    draw_axes(
        svg,
        rect,
        &xa,
        &ya,
        &xt,
        &yt,
        &map.x_label,
        &map.y_label,
        false,
    );
    draw_legend(svg, rect.x + rect.w + PAD, rect.y, &entries);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_split_at_nan_and_nonpositive_on_log() {
        let p = [
            (1.0, 1.0),
            (2.0, f64::NAN),
            (3.0, 3.0),
            (4.0, 4.0),
            (5.0, -1.0),
        ];
        assert_eq!(runs(&p, false, false).len(), 2);
        assert_eq!(
            runs(&p, false, true),
            vec![vec![(1.0, 1.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn constant_data_gets_distinct_ticks() {
        let (lo, hi) = axis_range(
            [
                std::f64::consts::FRAC_PI_2,
                std::f64::consts::FRAC_PI_2 + 3e-13,
            ]
            .into_iter(),
            false,
        );
        let a = Axis {
            lo,
            hi,
            log: false,
            p0: 0.0,
            p1: 100.0,
        };
        let t = a.ticks(5);
        let labels: std::collections::BTreeSet<&String> = t.iter().map(|(_, l)| l).collect();
        assert_eq!(labels.len(), t.len(), "{t:?}");
        assert!(t.len() >= 3);
    }

    #[test]
    fn ticks_are_nice_numbers() {
        let a = Axis {
            lo: -0.13,
            hi: 1.07,
            log: false,
            p0: 0.0,
            p1: 500.0,
        };
        let labels: Vec<String> = a.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let l = Axis {
            lo: 0.5,
            hi: 2e4,
            log: true,
            p0: 0.0,
            p1: 500.0,
        };
        // One notation per axis: 1e4 needs scientific notation, so every decade gets it.
        let labels: Vec<String> = l.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["1e0", "1e1", "1e2", "1e3", "1e4"]);
        let l = Axis {
            lo: 0.05,
            hi: 500.0,
            ..l
        };
        let labels: Vec<String> = l.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
    }

    #[test]
    fn coordinates_are_sub_pixel_and_text_is_measured() {
        assert_eq!(c(12.3456), "12.35");
        assert_eq!(c(3.0), "3");
        assert!(text_width("MMMM", 10.0) > text_width("iiii", 10.0));
        assert!((text_width("x", 20.0) / text_width("x", 10.0) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn tick_labels_are_compact() {
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(2.0), "2");
        assert_eq!(format_tick(1e-6), "1e-6");
        assert_eq!(format_tick(2.5e-8), "2.5e-8");
        assert_eq!(format_tick(-0.0), "0");
    }
}
