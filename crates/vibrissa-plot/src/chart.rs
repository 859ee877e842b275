//! The values a figure is made of: [`Chart`]s of [`Series`] and [`Mark`]s, [`HeatMap`]s,
//! their [`Panel`]s, the line styles and the palette. Plain data with builders; the modules
//! that draw them ([`crate::render_figure`], [`crate::FigureStyle`]) read them, and this
//! module depends on none of them.

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
    /// A closed obstacle (a disc): its outline as a line, the region inside filled light
    /// grey (the points go once round; the last joins the first).
    Region,
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

    /// The line's width as a multiple of the standard width (1 unless set to a positive
    /// finite factor).
    pub(crate) fn width_factor(&self) -> f64 {
        self.width
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

/// The heading of a multi-panel figure: a title, a note and one legend for all panels (the
/// entries of the first chart), above the panels.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Heading {
    /// The figure's title.
    pub title: String,
    /// A note line under it (scene, units).
    pub note: String,
}

// How the marks of a chart are drawn, in the plot and in its legend alike.

/// The dash of each event line of a chart: its own, or the next of [`Dash::EVENTS`] for
/// each new label.
pub(crate) fn event_dashes(chart: &Chart) -> Vec<Dash> {
    let mut seen: Vec<&str> = Vec::new();
    chart
        .marks
        .iter()
        .map(|m| match (m.kind, m.style) {
            (MarkKind::VLine, Some(MarkStyle::Dash(d))) => d,
            (MarkKind::VLine, _) => {
                let k = seen.iter().position(|l| *l == m.label).unwrap_or_else(|| {
                    seen.push(&m.label);
                    seen.len() - 1
                });
                Dash::EVENTS[k % Dash::EVENTS.len()]
            }
            _ => Dash::Solid,
        })
        .collect()
}

/// The marker of a highlighted point.
pub(crate) fn point_marker(m: &Mark) -> Marker {
    match m.style {
        Some(MarkStyle::Marker(k)) => k,
        _ => Marker::of_color(m.color),
    }
}

/// The fill of an obstacle's solid side.
pub(crate) const OBSTACLE_FILL: &str = "#d6d6d6";

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

/// The colour `c` as SVG writes it (`#rrggbb`).
pub(crate) fn rgb(c: (u8, u8, u8)) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}
