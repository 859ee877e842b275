//! A small declarative chart API with its own SVG renderer, used by the CLI and by
//! `cargo xtask reproduce` for every figure; each SVG gets a PNG twin rendered with resvg.
//!
//! A [`Chart`] is a titled x-y plot of [`Series`] (lines, dashed lines, points) with
//! automatic ranges, optional log axes (non-positive values are skipped), an optional equal
//! aspect ratio for beam shapes, [`Mark`]s (labelled vertical event lines, highlighted
//! points, arrows) and a note line under the title. NaN points are skipped and split lines.
//! [`FigureStyle::write_svg_panels`] puts several charts in one figure; [`HeatMap`] draws
//! categorical maps (stability maps).
//!
//! What a reader of a paper needs: coordinates are written with 1/100 pixel resolution (no
//! jagged curves), text is measured with the embedded DejaVu Sans font, so legends and
//! labels are sized to their text and placed outside the plotting area (they never cover
//! data), event labels sit in a band above the plot, staggered when close. The PNG is
//! rendered at twice the SVG's size with the same embedded font (no system fonts).
//!
//! No process-wide mutable state: the printed size and the formats of a figure are a
//! [`FigureStyle`] value handed to each writer (its methods), so threads and tests draw at
//! different sizes side by side. The only statics are immutable caches of the embedded font
//! (its parsed face and the font database of [`render_png`], each built once in a
//! `OnceLock`, and the memo of glyph advances, each slot written once with the font's own
//! value): whatever the order of calls, they answer the same.

use std::fmt::Write as _;
use std::sync::OnceLock;

mod axis;
mod draw;
pub mod error;
mod layout;
mod legend;
mod output;
mod svg;

pub use axis::format_tick;
use axis::*;
use draw::*;
pub use error::PlotError;
pub use layout::*;
use legend::*;
pub use output::*;
use svg::*;
pub use svg::{segments, text_width};

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
    /// A solid line with markers (about a dozen, evenly spread, on a long series).
    LinePoints,
    /// An obstacle's contour: a line with the solid side (above it, `y > g(x)`) filled
    /// light grey up to the top of the plot.
    Obstacle,
}

/// A line's dash pattern; colour is never the only thing that tells two lines apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// Solid.
    Solid,
    /// Short dashes.
    Dashed,
    /// Dots.
    Dotted,
    /// Dash and dot.
    DashDot,
    /// Long dashes.
    LongDash,
}

impl Dash {
    /// The dash patterns in the order event lines take them.
    pub const EVENTS: [Dash; 4] = [Dash::Dashed, Dash::Dotted, Dash::DashDot, Dash::LongDash];

    /// The SVG `stroke-dasharray` in points (None for solid).
    pub fn pattern(self) -> Option<&'static str> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some("3.2 1.8"),
            Dash::Dotted => Some("0.9 1.2"),
            Dash::DashDot => Some("3.6 1.2 0.9 1.2"),
            Dash::LongDash => Some("6.5 2"),
        }
    }
}

/// A marker's shape; by default a series takes the shape of its colour index, so that
/// series with different colours also differ in shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A disc.
    Circle,
    /// A square.
    Square,
    /// A triangle pointing up.
    Triangle,
    /// A diamond.
    Diamond,
    /// A triangle pointing down.
    TriangleDown,
}

impl Marker {
    /// The shape that goes with colour index `color`.
    pub fn of_color(color: usize) -> Marker {
        [
            Marker::Circle,
            Marker::Square,
            Marker::Triangle,
            Marker::Diamond,
            Marker::TriangleDown,
        ][color % 5]
    }
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
    /// The line's dash pattern, overriding the style's (solid for lines, dashed for
    /// [`Style::Dashed`]).
    pub dash: Option<Dash>,
    /// The marker's shape, overriding [`Marker::of_color`].
    pub marker: Option<Marker>,
    /// Error bars: the half-length of each point's vertical bar (data units), empty for
    /// none.
    pub err: Vec<f64>,
    /// The line's width as a multiple of the standard width (None: 1), in the plot and
    /// in its legend sample: a third way, besides colour and dash, to tell lines apart
    /// (a frictional sweep's stuck rows are drawn heavier than its sliding ones).
    pub width: Option<f64>,
}

impl Series {
    /// A series with colour 0.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series {
            name: name.into(),
            points,
            style,
            ..Series::default()
        }
    }

    /// Sets the colour index.
    pub fn color(mut self, color: usize) -> Self {
        self.color = color;
        self
    }

    /// Sets the dash pattern.
    pub fn dash(mut self, dash: Dash) -> Self {
        self.dash = Some(dash);
        self
    }

    /// Sets the marker shape.
    pub fn marker(mut self, marker: Marker) -> Self {
        self.marker = Some(marker);
        self
    }

    /// Sets the line width as a multiple of the standard width.
    pub fn width(mut self, factor: f64) -> Self {
        self.width = Some(factor);
        self
    }

    /// Sets vertical error bars (half-lengths, one per point).
    pub fn errors(mut self, err: Vec<f64>) -> Self {
        self.err = err;
        self
    }

    /// The dash pattern the line is drawn with.
    pub(crate) fn line_dash(&self) -> Dash {
        self.dash.unwrap_or(if self.style == Style::Dashed {
            Dash::Dashed
        } else {
            Dash::Solid
        })
    }

    /// The width the line is drawn with (points).
    pub(crate) fn line_width(&self) -> f64 {
        svg::LINE_W
            * self
                .width
                .filter(|w| w.is_finite() && *w > 0.0)
                .unwrap_or(1.0)
    }

    /// The marker shape the points are drawn with.
    pub(crate) fn marker_shape(&self) -> Marker {
        self.marker.unwrap_or(Marker::of_color(self.color))
    }
}

/// What a [`Mark`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarkKind {
    /// A vertical event line at `x` over the whole plot, dashed (each event line of a
    /// chart in its own pattern, [`Dash::EVENTS`]), explained in the legend.
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
    /// Its label in the legend (empty for none; marks with equal labels share an entry).
    pub label: String,
    /// Index into [`PALETTE`].
    pub color: usize,
    /// The shape of a [`MarkKind::Point`] (an open ring of [`Marker::of_color`] unless set)
    /// or the dash of a [`MarkKind::VLine`] (by order of appearance unless set).
    pub style: Option<MarkStyle>,
}

/// How a [`Mark`] is drawn when not by default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarkStyle {
    /// The marker of a point.
    Marker(Marker),
    /// The dash of an event line.
    Dash(Dash),
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
            style: None,
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
            style: None,
        }
    }

    /// Sets the marker of a point or the dash of an event line.
    pub fn styled(mut self, style: MarkStyle) -> Self {
        self.style = Some(style);
        self
    }

    /// An arrow from `(x, y)` by `(dx, dy)`, explained in the legend.
    pub fn arrow(x: f64, y: f64, dx: f64, dy: f64, label: impl Into<String>, color: usize) -> Self {
        Mark {
            kind: MarkKind::Arrow { dx, dy },
            x,
            y,
            label: label.into(),
            color,
            style: None,
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
    /// The y axis includes 0 (a quantity that starts at 0, such as a contact force).
    pub y_zero: bool,
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

    /// Makes the y axis include 0.
    pub fn y_from_zero(mut self) -> Self {
        self.y_zero = true;
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

/// The series colours: the colour-blind-safe palette of Okabe and Ito (2008), with grey at
/// index 7 for context (unloaded shapes, no contact, true contours). Their grey levels
/// differ too, and series of different colours also differ in dash or marker.
pub const PALETTE: [(u8, u8, u8); 10] = [
    (0, 114, 178),
    (230, 159, 0),
    (0, 158, 115),
    (213, 94, 0),
    (204, 121, 167),
    (86, 180, 233),
    (0, 0, 0),
    (128, 128, 128),
    (160, 140, 0),
    (90, 90, 90),
];

/// The colour of index `i` (modulo the palette length).
pub fn palette(i: usize) -> (u8, u8, u8) {
    PALETTE[i % PALETTE.len()]
}

fn rgb(c: (u8, u8, u8)) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear axis over `lo..hi` drawn on 100 pixels.
    fn linear(lo: f64, hi: f64) -> Axis {
        Axis {
            lo,
            hi,
            log: false,
            p0: 0.0,
            p1: 100.0,
        }
    }

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
        let a = linear(lo, hi);
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

    #[test]
    fn ticks_cover_the_data() {
        // Linear: the range widens to ticks on both sides (the old padding left x_c's
        // -0.94..0.75 with the one tick 0).
        let (lo, hi) = to_ticks((-0.97, 0.78), (-0.94, 0.75), false, 100.0);
        let a = linear(lo, hi);
        let t = a.ticks(tick_target(100.0));
        assert!(t.len() >= 3, "{t:?}");
        assert!(
            t[0].0 <= -0.94 && t[t.len() - 1].0 >= 0.75,
            "{t:?} for ({lo}, {hi})"
        );
        // Data that end on a tick keep a little padding instead of another step.
        let (lo, _) = to_ticks((-0.2, 10.2), (0.0, 10.0), false, 100.0);
        assert!((-0.21..0.0).contains(&lo), "{lo}");
        // Log: whole decades, the top one labelled.
        let (lo, hi) = to_ticks((8e-15, 1.3e-10), (1e-14, 1.2e-10), true, 200.0);
        let l = Axis {
            lo,
            hi,
            log: true,
            p0: 0.0,
            p1: 200.0,
        };
        let t = l.ticks(tick_target(200.0));
        assert_eq!(t.last().map(|x| x.1.as_str()), Some("1e-9"), "{t:?}");
        assert!(t[0].0 <= 1e-14, "{t:?}");
    }

    #[test]
    fn the_legend_goes_where_it_hides_no_data() {
        let rect = Rect {
            x: 0.0,
            y: 0.0,
            w: 200.0,
            h: 100.0,
        };
        // Data fill the top right: the legend goes top left.
        let drawn: Vec<(f64, f64)> = (0..50).map(|i| (150.0 + i as f64, 5.0)).collect();
        assert_eq!(free_place(rect, (40.0, 20.0), &drawn), Some((3.0, 3.0)));
        // Data everywhere: no place inside (a key above the plot instead).
        let drawn: Vec<(f64, f64)> = (0..=40)
            .flat_map(|i| (0..=20).map(move |j| (i as f64 * 5.0, j as f64 * 5.0)))
            .collect();
        assert_eq!(free_place(rect, (40.0, 20.0), &drawn), None);
    }

    #[test]
    fn equal_aspect_means_equal_scales() {
        let chart = Chart::new("", "x", "y")
            .with(Series::new("", vec![(-3.0, 0.0), (2.0, 1.2)], Style::Line))
            .equal_aspect();
        let rect = Rect {
            x: 10.0,
            y: 10.0,
            w: 220.0,
            h: 70.0,
        };
        let (xr, yr) = DataRanges::of(&chart, &chart_points(&chart)).fit(&chart, rect);
        let (kx, ky) = ((xr.1 - xr.0) / rect.w, (yr.1 - yr.0) / rect.h);
        assert!((kx / ky - 1.0).abs() < 1e-12, "{kx} vs {ky}");
        assert!(xr.0 <= -3.0 && xr.1 >= 2.0 && yr.0 <= 0.0 && yr.1 >= 1.2);
    }

    #[test]
    fn subscripts_are_markup_only_where_meant() {
        assert_eq!(
            segments("A_x [N]"),
            vec![
                ("A".to_string(), false),
                ("x".to_string(), true),
                (" [N]".to_string(), false)
            ]
        );
        assert_eq!(segments("x_{max}")[1], ("max".to_string(), true));
        assert_eq!(
            segments("file_name"),
            vec![("file_name".to_string(), false)]
        );
        assert!(text_width("A_x", 10.0) < text_width("Ax", 10.0));
    }

    #[test]
    fn figures_print_at_the_chosen_width() {
        let chart = Chart::new("t", "x", "y").with(Series::new(
            "s",
            vec![(0.0, 0.0), (1.0, 1.0)],
            Style::Line,
        ));
        for (size, mm) in [
            (FigureSize::Column, "85mm"),
            (FigureSize::Page, "175mm"),
            (FigureSize::Slide, "254mm"),
        ] {
            let svg = render_figure(&[Panel::Chart(&chart)], 1, (800, 500), size).unwrap();
            assert!(svg.contains(&format!("width=\"{mm}\"")), "{}", &svg[..200]);
        }
    }

    /// Two threads write at two styles at once, each figure at its own size and in its
    /// own formats (with a process-wide setting one of them would take the other's).
    #[test]
    fn threads_write_figures_in_their_own_styles_at_once() {
        let dir = std::env::temp_dir().join(format!("vibrissa-plot-styles-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let chart = Chart::new("t", "x", "y").with(Series::new(
            "s",
            vec![(0.0, 0.0), (1.0, 2.0)],
            Style::Line,
        ));
        let styles = [
            FigureStyle::new(FigureSize::Page, FigureFormats::Svg),
            FigureStyle::new(FigureSize::Slide, FigureFormats::All),
            FigureStyle::default().sized(FigureSize::Column),
            FigureStyle::new(FigureSize::Page, FigureFormats::None),
        ];
        std::thread::scope(|s| {
            for (i, style) in styles.iter().enumerate() {
                let (chart, dir) = (&chart, &dir);
                s.spawn(move || {
                    for k in 0..5 {
                        let p = dir.join(format!("f{i}-{k}.svg"));
                        style.write_svg(chart, &p, (640, 480)).unwrap();
                    }
                });
            }
        });
        for (i, style) in styles.iter().enumerate() {
            for k in 0..5 {
                let p = dir.join(format!("f{i}-{k}.svg"));
                assert_eq!(p.exists(), style.formats.svg(), "{}", p.display());
                assert_eq!(
                    png_path(&p).exists(),
                    style.formats.png(),
                    "{}",
                    p.display()
                );
                if style.formats.svg() {
                    let svg = std::fs::read_to_string(&p).unwrap();
                    let mm = format!("width=\"{}mm\"", style.size.print_mm());
                    assert!(svg.contains(&mm), "{}: {}", p.display(), &svg[..200]);
                }
            }
        }
        // the slide's PNG at 150 dpi of 254 mm: 1500 pixels wide
        let png = std::fs::read(png_path(&dir.join("f1-0.svg"))).unwrap();
        let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
        assert!(width.abs_diff(1500) <= 1, "{width} pixels");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
