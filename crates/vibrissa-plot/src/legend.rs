//! Legends: entries sized to their text, drawn as a box inside the plot where it covers no
//! data, or as a key of centred rows above the plot (and above the panels of a figure).

use crate::chart::*;
use crate::svg::*;

/// One legend entry.
pub(super) enum Entry<'a> {
    Series(&'a Series),
    Point(&'a Mark),
    Arrow(&'a Mark),
    Event(&'a Mark, Dash),
    Swatch(&'a str, (u8, u8, u8)),
}

impl Entry<'_> {
    pub(super) fn label(&self) -> &str {
        match self {
            Entry::Series(s) => &s.name,
            Entry::Point(m) | Entry::Arrow(m) | Entry::Event(m, _) => &m.label,
            Entry::Swatch(n, _) => n,
        }
    }
}

/// The width of a line sample (points).
pub(super) const SAMPLE_W: f64 = 15.0;
/// The height of a legend row (points).
pub(super) const ROW_H: f64 = 9.0;

/// The width of a legend box.
pub(super) fn legend_width(entries: &[Entry<'_>]) -> f64 {
    if entries.is_empty() {
        return 0.0;
    }
    let text = entries
        .iter()
        .map(|e| text_width(e.label(), LEGEND_SIZE))
        .fold(0.0, f64::max);
    3.0 + SAMPLE_W + 3.0 + text + 3.0
}

/// Draws the legend box with its top-left corner at `(x, y)`.
pub(super) fn draw_legend(svg: &mut Svg, x: f64, y: f64, entries: &[Entry<'_>]) {
    if entries.is_empty() {
        return;
    }
    let w = legend_width(entries);
    let h = 3.0 + ROW_H * entries.len() as f64;
    svg.rect(Rect { x, y, w, h }, "#ffffff", Some("#b8b8b8"));
    for (i, e) in entries.iter().enumerate() {
        let cy = y + 1.5 + ROW_H * (i as f64 + 0.5);
        draw_legend_entry(svg, x + 3.0, cy, e);
    }
}

/// The width an entry takes in a key row.
fn key_entry_width(e: &Entry<'_>) -> f64 {
    SAMPLE_W + 3.0 + text_width(e.label(), LEGEND_SIZE) + 9.0
}

/// The entries of each key row when the key is `width` wide.
fn key_rows(entries: &[Entry<'_>], width: f64) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut used = 0.0;
    for (i, e) in entries.iter().enumerate() {
        let w = key_entry_width(e);
        if used + w > width && !rows.last().is_some_and(Vec::is_empty) {
            rows.push(vec![]);
            used = 0.0;
        }
        used += w;
        if let Some(r) = rows.last_mut() {
            r.push(i);
        }
    }
    rows.retain(|r| !r.is_empty());
    rows
}

/// The height of a key of `entries` set in rows `width` wide.
pub(super) fn key_height(entries: &[Entry<'_>], width: f64) -> f64 {
    if entries.is_empty() {
        return 0.0;
    }
    key_rows(entries, width).len() as f64 * ROW_H + 3.0
}

/// Draws a key: the entries in centred rows `width` wide from `(x, top)`.
pub(super) fn draw_key(svg: &mut Svg, x: f64, width: f64, top: f64, entries: &[Entry<'_>]) {
    for (k, r) in key_rows(entries, width).iter().enumerate() {
        let total: f64 = r.iter().map(|&i| key_entry_width(&entries[i])).sum::<f64>() - 6.0;
        let mut ex = x + (width - total) / 2.0;
        let cy = top + 1.5 + ROW_H * (k as f64 + 0.5);
        for &i in r {
            draw_legend_entry(svg, ex, cy, &entries[i]);
            ex += key_entry_width(&entries[i]);
        }
    }
}

/// Draws one legend entry: its sample from `x` and its text after it, centred on `cy`.
pub(super) fn draw_legend_entry(svg: &mut Svg, x: f64, cy: f64, e: &Entry<'_>) {
    let (sx0, sx1) = (x, x + SAMPLE_W);
    let mid = ((sx0 + sx1) / 2.0, cy);
    match e {
        Entry::Series(s) => {
            let col = rgb(palette(s.color));
            if matches!(s.style, Style::Obstacle | Style::Region) {
                svg.rect(
                    Rect {
                        x: sx0,
                        y: cy - 3.5,
                        w: SAMPLE_W,
                        h: 3.5,
                    },
                    OBSTACLE_FILL,
                    None,
                );
            }
            if s.style != Style::Points {
                svg.line(
                    (sx0, cy),
                    (sx1, cy),
                    &col,
                    crate::svg::LINE_W * s.width_factor(),
                    s.line_dash().pattern(),
                );
            }
            if !s.err.is_empty() {
                svg.line((mid.0, cy - 3.0), (mid.0, cy + 3.0), &col, 0.5, None);
            }
            if matches!(s.style, Style::Points | Style::LinePoints) {
                svg.marker(mid, s.marker_shape(), MARKER_R, &col, None);
            }
        }
        Entry::Point(m) => {
            let col = rgb(palette(m.color));
            svg.marker(mid, point_marker(m), 3.0, "none", Some((&col, 0.9)));
        }
        Entry::Arrow(m) => {
            let col = rgb(palette(m.color));
            svg.arrow((sx0, cy), (sx1, cy), &col);
        }
        Entry::Event(m, dash) => {
            let col = rgb(palette(m.color));
            svg.line((sx0, cy), (sx1, cy), &col, 0.8, dash.pattern());
        }
        Entry::Swatch(_, col) => {
            svg.rect(
                Rect {
                    x: sx0 + 3.0,
                    y: cy - 3.0,
                    w: 8.0,
                    h: 6.0,
                },
                &rgb(*col),
                Some("#808080"),
            );
        }
    }
    svg.text(
        (sx1 + 3.0, cy + LEGEND_SIZE * 0.35),
        e.label(),
        LEGEND_SIZE,
        "start",
        "#202020",
        false,
    );
}

/// The legend entries of a chart: named series, then labelled points, arrows and event
/// lines (one entry per label).
pub(super) fn legend_entries(chart: &Chart) -> Vec<Entry<'_>> {
    let mut entries: Vec<Entry<'_>> = chart
        .series
        .iter()
        .filter(|s| !s.name.is_empty())
        .map(Entry::Series)
        .collect();
    let dashes = event_dashes(chart);
    let mut events: Vec<&str> = Vec::new();
    for (m, dash) in chart.marks.iter().zip(dashes) {
        if m.label.is_empty() {
            continue;
        }
        match m.kind {
            MarkKind::Point => entries.push(Entry::Point(m)),
            MarkKind::Arrow { .. } => entries.push(Entry::Arrow(m)),
            MarkKind::VLine if !events.contains(&m.label.as_str()) => {
                events.push(&m.label);
                entries.push(Entry::Event(m, dash));
            }
            MarkKind::VLine => {}
        }
    }
    entries
}
