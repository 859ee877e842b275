//! Legends: entries sized to their text, drawn outside the plotting area.

use super::*;

/// One legend entry.
pub(super) enum Entry<'a> {
    Series(&'a Series),
    Point(&'a Mark),
    Arrow(&'a Mark),
    Swatch(&'a str, (u8, u8, u8)),
}

impl Entry<'_> {
    pub(super) fn label(&self) -> &str {
        match self {
            Entry::Series(s) => &s.name,
            Entry::Point(m) | Entry::Arrow(m) => &m.label,
            Entry::Swatch(n, _) => n,
        }
    }
}

pub(super) const SAMPLE_W: f64 = 26.0;
pub(super) const ROW_H: f64 = 17.0;

pub(super) fn legend_width(entries: &[Entry<'_>]) -> f64 {
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
pub(super) fn draw_legend(svg: &mut Svg, x: f64, y: f64, entries: &[Entry<'_>]) {
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
pub(super) fn draw_legend_entry(svg: &mut Svg, x: f64, cy: f64, e: &Entry<'_>) {
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
pub(super) fn legend_entries(chart: &Chart) -> Vec<Entry<'_>> {
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
