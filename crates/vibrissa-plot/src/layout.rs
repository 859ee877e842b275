//! The canvas of a figure at its printed size (`--size`): panels, heading and shared key
//! laid out in points.

use crate::axis::*;
use crate::chart::*;
use crate::draw::*;
use crate::legend::*;
use crate::svg::*;

/// Renders charts under a [`Heading`] (what [`crate::FigureStyle::write_panels_with_heading`]
/// writes), printed at `print`.
pub fn render_figure_with(
    charts: &[Chart],
    cols: usize,
    size: (u32, u32),
    heading: &Heading,
    print: FigureSize,
) -> Result<String, String> {
    let Some(first) = charts.first() else {
        return Err("no panels to draw".to_string());
    };
    let entries = legend_entries(first);
    let key = |w: f64| key_height(&entries, w - 2.0 * PAD);
    let top = |w: f64| heading_height(w, &heading.title, &heading.note) + key(w);
    let mut hidden: Vec<Chart> = charts.to_vec();
    for c in &mut hidden {
        c.hide_legend = true;
    }
    let panels_hidden: Vec<Panel<'_>> = hidden.iter().map(Panel::Chart).collect();
    render_layout(&panels_hidden, cols, size, print, top, |svg, w| {
        let full = Rect {
            x: 0.0,
            y: 0.0,
            w,
            h: 0.0,
        };
        let h = draw_heading(svg, full, &heading.title, &heading.note);
        draw_key(svg, PAD, w - 2.0 * PAD, h, &entries);
    })
}

/// Renders a figure to an SVG string (what [`crate::FigureStyle::write_figure`] writes), printed
/// at `print`.
pub fn render_figure(
    panels: &[Panel<'_>],
    cols: usize,
    size: (u32, u32),
    print: FigureSize,
) -> Result<String, String> {
    render_layout(panels, cols, size, print, |_| 0.0, |_, _| {})
}

/// The canvas of a figure printed at `fs`: as wide (in points) as the
/// printed column, page or slide; panels in at most `cols` columns (fewer where a panel
/// would be narrower than 115 pt), each plot as high as the design `size` (its aspect) or,
/// for one equal-aspect chart, the data ask; `top` is the height of what goes above.
fn render_layout(
    panels: &[Panel<'_>],
    cols: usize,
    size: (u32, u32),
    fs: FigureSize,
    top: impl Fn(f64) -> f64,
    draw_top: impl FnOnce(&mut Svg, f64),
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
    let n = panels.len();
    let w = fs.canvas_width();
    let design_cols = cols.min(n);
    let design_rows = n.div_ceil(design_cols);
    let cols = design_cols.min(((w / 115.0).floor() as usize).max(1));
    let pw = w / cols as f64;
    let design_aspect =
        (f64::from(size.1) / design_rows as f64) / (f64::from(size.0) / design_cols as f64);
    let plot_w = pw - 40.0;
    // Each panel's height: its plot as the design's aspect asks or, for an equal-aspect
    // chart, as its data ask, plus its heading, axes and (for a lone chart) a key row.
    let panel_h = |p: &Panel<'_>| -> f64 {
        let (title, note, aspect, key) = match p {
            Panel::Chart(c) => {
                let mut aspect = design_aspect;
                if c.aspect_equal && !c.x_log && !c.y_log {
                    let pts = chart_points(c);
                    let (xr, yr) = (
                        axis_range(pts.iter().map(|p| p.0), false),
                        axis_range(pts.iter().map(|p| p.1), false),
                    );
                    aspect = ((yr.1 - yr.0) / (xr.1 - xr.0)).clamp(0.2, 1.1);
                }
                let key = if c.hide_legend {
                    0.0
                } else {
                    key_height(&legend_entries(c), pw - 2.0 * PAD)
                };
                (c.title.as_str(), c.note.as_str(), aspect, key)
            }
            Panel::HeatMap(m) => {
                let entries: Vec<Entry<'_>> = m
                    .categories
                    .iter()
                    .map(|(n, col)| Entry::Swatch(n.as_str(), *col))
                    .collect();
                let key = key_height(&entries, pw - 2.0 * PAD);
                (m.title.as_str(), "", design_aspect, key)
            }
        };
        heading_height(pw, title, note) + BOTTOM + 6.0 + key + (plot_w * aspect).max(55.0)
    };
    let row_h: Vec<f64> = panels
        .chunks(cols)
        .map(|row| row.iter().map(panel_h).fold(0.0, f64::max))
        .collect();
    let head = top(w);
    let h = head + row_h.iter().sum::<f64>();
    let mut svg = Svg::new(w, h, fs.print_mm());
    draw_top(&mut svg, w);
    let mut y = head;
    for (r, row) in panels.chunks(cols).enumerate() {
        for (k, panel) in row.iter().enumerate() {
            let i = r * cols + k;
            let area = Rect {
                x: k as f64 * pw,
                y,
                w: pw,
                h: row_h[r],
            };
            match panel {
                Panel::Chart(c) => draw_chart(&mut svg, area, c, i)?,
                Panel::HeatMap(m) => draw_heatmap(&mut svg, area, m, i)?,
            }
        }
        y += row_h[r];
    }
    Ok(svg.finish())
}

/// The printed size figures are made for: `--size column|page|slide`. The canvas is as
/// wide in points as the print, so the fonts print at their nominal sizes (7-8.5 pt; on a
/// slide twice that).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum FigureSize {
    /// One column of a journal page, 85 mm wide (the command line's and the library's
    /// default).
    #[default]
    Column,
    /// Both columns of a journal page, 175 mm wide.
    Page,
    /// A presentation slide, 254 mm (10 in) wide, fonts twice as large.
    Slide,
}

impl FigureSize {
    /// The canvas width in points.
    pub fn canvas_width(self) -> f64 {
        match self {
            FigureSize::Column => 85.0 / 25.4 * 72.0,
            FigureSize::Page => 175.0 / 25.4 * 72.0,
            FigureSize::Slide => 127.0 / 25.4 * 72.0,
        }
    }

    /// The printed width in millimetres.
    pub fn print_mm(self) -> f64 {
        match self {
            FigureSize::Column => 85.0,
            FigureSize::Page => 175.0,
            FigureSize::Slide => 254.0,
        }
    }

    /// The resolution of the PNG twin (dots per inch of the print).
    pub fn png_dpi(self) -> f64 {
        match self {
            FigureSize::Slide => 150.0,
            _ => 300.0,
        }
    }
}
