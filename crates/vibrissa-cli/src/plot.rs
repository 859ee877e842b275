//! A small declarative chart API on top of plotters' SVG backend, used by the CLI and by
//! `cargo xtask reproduce` for every figure.
//!
//! A [`Chart`] is a titled x-y plot of [`Series`] (lines, dashed lines, points), with
//! automatic ranges, optional log axes (non-positive values are skipped) and an optional
//! equal aspect ratio for drawing beam shapes. NaN points are skipped and split lines.
//! [`write_svg_panels`] puts several charts in one SVG; [`HeatMap`] draws categorical maps
//! (stability maps). Every SVG is rendered in memory and written atomically.

use std::path::Path;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

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

/// A titled x-y chart.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    /// The caption above the plot.
    pub title: String,
    /// The x axis label.
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
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The colour of index `i` (modulo the palette length).
pub fn palette(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Writes `chart` as an SVG of `size` pixels (width, height) to `path`, atomically.
pub fn write_svg(chart: &Chart, path: &Path, size: (u32, u32)) -> Result<(), CliError> {
    write_figure(&[Panel::Chart(chart)], 1, path, size)
}

/// Writes several charts as panels of one SVG, `cols` per row, row by row.
pub fn write_svg_panels(
    charts: &[Chart],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), CliError> {
    let panels: Vec<Panel<'_>> = charts.iter().map(Panel::Chart).collect();
    write_figure(&panels, cols, path, size)
}

/// Writes `map` as an SVG of `size` pixels to `path`, atomically.
pub fn write_heatmap_svg(map: &HeatMap, path: &Path, size: (u32, u32)) -> Result<(), CliError> {
    write_figure(&[Panel::HeatMap(map)], 1, path, size)
}

/// Writes a figure made of charts and maps, `cols` panels per row.
pub fn write_figure(
    panels: &[Panel<'_>],
    cols: usize,
    path: &Path,
    size: (u32, u32),
) -> Result<(), CliError> {
    let svg = render_figure(panels, cols, size).map_err(|reason| CliError::Plot {
        path: path.to_path_buf(),
        reason,
    })?;
    write_atomic(path, svg.as_bytes())
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
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            match panel {
                Panel::Chart(c) => draw_chart(area, c)?,
                Panel::HeatMap(m) => draw_heatmap(area, m)?,
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(buf)
}

const MARGIN: u32 = 10;
const X_LABEL_AREA: u32 = 40;
const Y_LABEL_AREA: u32 = 62;
const CAPTION_HEIGHT: u32 = 30;

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

/// The padded range of `values` on a linear or log axis.
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
        if lo == hi {
            return (lo / 2.0, hi * 2.0);
        }
        let f = (hi / lo).powf(0.04);
        (lo / f, hi * f)
    } else {
        if lo == hi {
            let pad = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
            return (lo - pad, hi + pad);
        }
        let pad = (hi - lo) * 0.04;
        (lo - pad, hi + pad)
    }
}

/// The x and y ranges of a chart drawn in an area of `dim` pixels.
fn chart_ranges(chart: &Chart, dim: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let valid = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&p| is_valid(p, chart.x_log, chart.y_log))
    };
    let mut xr = axis_range(valid().map(|p| p.0), chart.x_log);
    let mut yr = axis_range(valid().map(|p| p.1), chart.y_log);
    if chart.aspect_equal && !chart.x_log && !chart.y_log {
        let w = dim.0.saturating_sub(Y_LABEL_AREA + 2 * MARGIN).max(10) as f64;
        let h = dim
            .1
            .saturating_sub(X_LABEL_AREA + CAPTION_HEIGHT + 2 * MARGIN)
            .max(10) as f64;
        let u = ((xr.1 - xr.0) / w).max((yr.1 - yr.0) / h);
        let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
        xr = (cx - u * w / 2.0, cx + u * w / 2.0);
        yr = (cy - u * h / 2.0, cy + u * h / 2.0);
    }
    (xr, yr)
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

fn draw_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = chart_ranges(chart, area.dim_in_pixel());
    match (chart.x_log, chart.y_log) {
        (false, false) => draw_chart_in(area, chart, x0..x1, y0..y1),
        (true, false) => draw_chart_in(area, chart, (x0..x1).log_scale(), y0..y1),
        (false, true) => draw_chart_in(area, chart, x0..x1, (y0..y1).log_scale()),
        (true, true) => draw_chart_in(area, chart, (x0..x1).log_scale(), (y0..y1).log_scale()),
    }
}

fn draw_chart_in<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart,
    x: X,
    y: Y,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut cc = ChartBuilder::on(area)
        .caption(&chart.title, ("sans-serif", 17))
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())?;
    cc.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .x_labels(7)
        .y_labels(7)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut any_named = false;
    for s in &chart.series {
        let col = palette(s.color);
        let line = ShapeStyle::from(&col).stroke_width(2);
        let marker = ShapeStyle::from(&col).filled();
        let has_line = matches!(s.style, Style::Line | Style::Dashed | Style::LinePoints);
        let has_marker = matches!(s.style, Style::Points | Style::LinePoints);
        for run in runs(&s.points, chart.x_log, chart.y_log) {
            match s.style {
                Style::Dashed => {
                    cc.draw_series(DashedLineSeries::new(run.clone(), 8, 5, line))
                        .map_err(|e| e.to_string())?;
                }
                Style::Line | Style::LinePoints => {
                    cc.draw_series(LineSeries::new(run.iter().copied(), line))
                        .map_err(|e| e.to_string())?;
                }
                Style::Points => {}
            }
            if has_marker {
                cc.draw_series(run.iter().map(|&p| Circle::new(p, 3, marker)))
                    .map_err(|e| e.to_string())?;
            }
        }
        if !s.name.is_empty() {
            any_named = true;
            let dashed = s.style == Style::Dashed;
            let seg = if has_line {
                line
            } else {
                ShapeStyle::from(&TRANSPARENT)
            };
            let dot = if has_marker {
                marker
            } else {
                ShapeStyle::from(&TRANSPARENT)
            };
            cc.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| e.to_string())?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    let (a, b) = if dashed { (8, 14) } else { (11, 11) };
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (a, 0)], seg)
                        + PathElement::new(vec![(b, 0), (22, 0)], seg)
                        + Circle::new((11, 0), 3, dot)
                });
        }
    }
    if any_named {
        cc.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
    }
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

fn draw_heatmap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    map: &HeatMap,
) -> Result<(), String> {
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
    let legend_w = 140.min(area.dim_in_pixel().0 / 3);
    let (plot_area, legend_area) = area.split_horizontally(area.dim_in_pixel().0 - legend_w);
    let mut cc = ChartBuilder::on(&plot_area)
        .caption(&map.title, ("sans-serif", 17))
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(xe[0]..xe[xe.len() - 1], ye[0]..ye[ye.len() - 1])
        .map_err(|e| e.to_string())?;
    cc.configure_mesh()
        .disable_mesh()
        .x_desc(map.x_label.as_str())
        .y_desc(map.y_label.as_str())
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    let rects = map.cells.iter().enumerate().flat_map(|(iy, row)| {
        let (xe, ye) = (&xe, &ye);
        row.iter().enumerate().map(move |(ix, &c)| {
            let (r, g, b) = map.categories[c as usize].1;
            Rectangle::new(
                [(xe[ix], ye[iy]), (xe[ix + 1], ye[iy + 1])],
                RGBColor(r, g, b).filled(),
            )
        })
    });
    cc.draw_series(rects).map_err(|e| e.to_string())?;
    for (i, (name, (r, g, b))) in map.categories.iter().enumerate() {
        let y = CAPTION_HEIGHT as i32 + 20 + 22 * i as i32;
        legend_area
            .draw(&Rectangle::new(
                [(6, y), (20, y + 14)],
                RGBColor(*r, *g, *b).filled(),
            ))
            .map_err(|e| e.to_string())?;
        legend_area
            .draw(&Rectangle::new([(6, y), (20, y + 14)], BLACK.mix(0.5)))
            .map_err(|e| e.to_string())?;
        legend_area
            .draw_text(
                name,
                &TextStyle::from(("sans-serif", 13).into_font()),
                (26, y + 1),
            )
            .map_err(|e| e.to_string())?;
    }
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
    fn ranges_pad_and_equalise() {
        let c = Chart::new("t", "x", "y").with(Series::new(
            "s",
            vec![(0.0, 0.0), (1.0, 0.1)],
            Style::Line,
        ));
        let ((x0, x1), (y0, y1)) = chart_ranges(&c, (600, 400));
        assert!(x0 < 0.0 && x1 > 1.0 && y0 < 0.0 && y1 > 0.1);
        let c = c.equal_aspect();
        let ((x0, x1), (y0, y1)) = chart_ranges(&c, (600, 400));
        let w = (600 - Y_LABEL_AREA - 2 * MARGIN) as f64;
        let h = (400 - X_LABEL_AREA - CAPTION_HEIGHT - 2 * MARGIN) as f64;
        assert!(((x1 - x0) / w - (y1 - y0) / h).abs() < 1e-12);
        assert_eq!(axis_range(std::iter::empty(), true), (1.0, 10.0));
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
