//! Drawing a chart or a heat map into an area of a figure: heading, plot rectangle, axes,
//! series, marks and the legend (inside the plot where it covers no data, else a key row
//! above it).

use crate::axis::*;
use crate::chart::*;
use crate::legend::*;
use crate::svg::*;

/// Greedy word wrap of `text` at `size` into lines at most `width` wide.
pub(super) fn wrap(text: &str, size: f64, width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    // `k = 20` stays on one line: no break around an equals sign (no-break spaces).
    let text = text.replace(" = ", "\u{a0}=\u{a0}");
    for word in text.split(' ') {
        let trial = if cur.is_empty() {
            word.to_string()
        } else {
            format!("{cur} {word}")
        };
        if !cur.is_empty() && text_width(&trial, size) > width {
            lines.push(std::mem::replace(&mut cur, word.to_string()));
        } else {
            cur = trial;
        }
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    // The no-break spaces only held words together: they print as spaces.
    lines.iter().map(|l| l.replace('\u{a0}', " ")).collect()
}

/// The height of a heading (title and note, wrapped to `w`).
pub(super) fn heading_height(w: f64, title: &str, note: &str) -> f64 {
    let mut h = PAD;
    if !title.is_empty() {
        h += wrap(title, TITLE_SIZE, w - 2.0 * PAD).len() as f64 * (TITLE_SIZE + 2.0) + 1.0;
    }
    if !note.is_empty() {
        h += wrap(note, NOTE_SIZE, w - 2.0 * PAD).len() as f64 * (NOTE_SIZE + 1.5) + 1.5;
    }
    h
}

/// The heading of a panel (title and note, wrapped); returns its height.
pub(super) fn draw_heading(svg: &mut Svg, area: Rect, title: &str, note: &str) -> f64 {
    let mut y = area.y + PAD;
    let cx = area.x + area.w / 2.0;
    if !title.is_empty() {
        for line in wrap(title, TITLE_SIZE, area.w - 2.0 * PAD) {
            y += TITLE_SIZE;
            svg.text((cx, y), &line, TITLE_SIZE, "middle", "#000000", false);
            y += 2.0;
        }
        y += 1.0;
    }
    if !note.is_empty() {
        for line in wrap(note, NOTE_SIZE, area.w - 2.0 * PAD) {
            y += NOTE_SIZE;
            svg.text((cx, y), &line, NOTE_SIZE, "middle", "#404040", false);
            y += 1.5;
        }
        y += 1.5;
    }
    y - area.y
}

/// Space below the plot for the x tick labels and the x label.
pub(super) const BOTTOM: f64 = TICK_SIZE + 3.5 + LABEL_SIZE + 3.0 + PAD;

/// The plot rectangle inside `area` below a heading of height `head` and a key of height
/// `key_h`, leaving room for the tick labels (`ytick_w` wide) and the axis labels.
pub(super) fn plot_rect(area: Rect, head: f64, key_h: f64, ytick_w: f64) -> Rect {
    let left = PAD + LABEL_SIZE + 3.0 + ytick_w + 3.0;
    let top = head + key_h + 3.0;
    Rect {
        x: area.x + left,
        y: area.y + top,
        w: (area.w - left - PAD - 5.0).max(20.0),
        h: (area.h - top - BOTTOM).max(20.0),
    }
}

pub(super) fn draw_axes(
    svg: &mut Svg,
    r: Rect,
    xa: &Axis,
    ya: &Axis,
    labels: (&str, &str),
    grid: bool,
) {
    let xt = xa.ticks(tick_target(r.w));
    let yt = ya.ticks(tick_target(r.h));
    for (v, label) in &xt {
        let px = xa.px(*v);
        if grid {
            svg.line((px, r.y), (px, r.y + r.h), "#e4e4e4", GRID_W, None);
        }
        svg.line(
            (px, r.y + r.h),
            (px, r.y + r.h + 2.5),
            "#303030",
            AXIS_W,
            None,
        );
        svg.text(
            (px, r.y + r.h + 3.5 + TICK_SIZE),
            label,
            TICK_SIZE,
            "middle",
            "#202020",
            false,
        );
    }
    let mut ytick_w: f64 = 0.0;
    for (v, label) in &yt {
        let py = ya.px(*v);
        if grid {
            svg.line((r.x, py), (r.x + r.w, py), "#e4e4e4", GRID_W, None);
        }
        svg.line((r.x - 2.5, py), (r.x, py), "#303030", AXIS_W, None);
        svg.text(
            (r.x - 3.5, py + TICK_SIZE * 0.36),
            label,
            TICK_SIZE,
            "end",
            "#202020",
            false,
        );
        ytick_w = ytick_w.max(text_width(label, TICK_SIZE));
    }
    svg.rect(r, "none", Some("#303030"));
    svg.text(
        (
            r.x + r.w / 2.0,
            r.y + r.h + 3.5 + TICK_SIZE + 3.0 + LABEL_SIZE,
        ),
        labels.0,
        LABEL_SIZE,
        "middle",
        "#000000",
        false,
    );
    let lx = r.x - 3.5 - ytick_w - 3.0 - 2.0;
    svg.text(
        (lx, r.y + r.h / 2.0),
        labels.1,
        LABEL_SIZE,
        "middle",
        "#000000",
        true,
    );
}

/// The data extent of a chart (series with their error bars, marks other than event
/// lines), as an iterator over valid points.
pub(super) fn chart_points(chart: &Chart) -> Vec<(f64, f64)> {
    let (xl, yl) = (chart.x_log, chart.y_log);
    let mut pts: Vec<(f64, f64)> = Vec::new();
    for s in &chart.series {
        for (i, &p) in s.points.iter().enumerate() {
            pts.push(p);
            if let Some(&e) = s.err.get(i) {
                if e.is_finite() {
                    pts.push((p.0, p.1 - e));
                    pts.push((p.0, p.1 + e));
                }
            }
        }
    }
    for m in chart.marks.iter().filter(|m| m.kind != MarkKind::VLine) {
        pts.push((m.x, m.y));
        if let MarkKind::Arrow { dx, dy } = m.kind {
            pts.push((m.x + dx, m.y + dy));
        }
    }
    pts.retain(|&p| is_valid(p, xl, yl));
    pts
}

/// The ranges of a chart's points (padded and tight, per axis): computed once per chart,
/// fitted to each trial plot rectangle of the layout ([`DataRanges::fit`]: padded, widened
/// to the ticks so that ticks cover the data, 0 included if asked, or equal scales).
pub(super) struct DataRanges {
    x: (f64, f64),
    y: (f64, f64),
    x_tight: (f64, f64),
    y_tight: (f64, f64),
}

impl DataRanges {
    pub(super) fn of(chart: &Chart, pts: &[(f64, f64)]) -> Self {
        let (xl, yl) = (chart.x_log, chart.y_log);
        let xs = pts.iter().map(|p| p.0);
        let zero = chart.y_zero && !yl;
        let ys = pts.iter().map(|p| p.1).chain(zero.then_some(0.0));
        DataRanges {
            x: axis_range(xs.clone(), xl),
            y: axis_range(ys.clone(), yl),
            x_tight: tight_range(xs, xl),
            y_tight: tight_range(ys, yl),
        }
    }

    /// The axis ranges in the plot rectangle `rect`: equal aspect, or widened to ticks.
    pub(super) fn fit(&self, chart: &Chart, rect: Rect) -> ((f64, f64), (f64, f64)) {
        let (xl, yl) = (chart.x_log, chart.y_log);
        let (xr, yr) = (self.x, self.y);
        if chart.aspect_equal && !xl && !yl {
            let u = ((xr.1 - xr.0) / rect.w).max((yr.1 - yr.0) / rect.h);
            let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
            return (
                (cx - u * rect.w / 2.0, cx + u * rect.w / 2.0),
                (cy - u * rect.h / 2.0, cy + u * rect.h / 2.0),
            );
        }
        (
            to_ticks(xr, self.x_tight, xl, rect.w),
            to_ticks(yr, self.y_tight, yl, rect.h),
        )
    }
}

/// The unpadded range of `values` (on a log axis, of the positive ones).
fn tight_range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

/// The legend box's size.
fn legend_box(entries: &[Entry<'_>]) -> (f64, f64) {
    (legend_width(entries), 3.0 + ROW_H * entries.len() as f64)
}

/// Where the legend box of size `(w, h)` covers no drawn point: the first free place of
/// top right, top left, bottom right, bottom left, top and bottom centre; None if every
/// place covers some.
pub(super) fn free_place(rect: Rect, size: (f64, f64), drawn: &[(f64, f64)]) -> Option<(f64, f64)> {
    let (w, h) = size;
    if w + 6.0 > rect.w || h + 6.0 > rect.h {
        return None;
    }
    let (l, r) = (rect.x + 3.0, rect.x + rect.w - 3.0 - w);
    let (t, b) = (rect.y + 3.0, rect.y + rect.h - 3.0 - h);
    let c = rect.x + (rect.w - w) / 2.0;
    [(r, t), (l, t), (r, b), (l, b), (c, t), (c, b)]
        .into_iter()
        .find(|&(x, y)| {
            !drawn.iter().any(|&(px, py)| {
                px >= x - 1.5 && px <= x + w + 1.5 && py >= y - 1.5 && py <= y + h + 1.5
            })
        })
}

/// Points along every drawn line, marker and bar (pixels, about 1.5 pt apart), for
/// placing the legend where it hides nothing.
fn drawn_points(chart: &Chart, xa: &Axis, ya: &Axis, rect: Rect) -> Vec<(f64, f64)> {
    let (xl, yl) = (chart.x_log, chart.y_log);
    let mut out = Vec::new();
    let segment = |a: (f64, f64), b: (f64, f64), out: &mut Vec<(f64, f64)>| {
        let n = ((b.0 - a.0).hypot(b.1 - a.1) / 1.5)
            .ceil()
            .clamp(1.0, 2000.0) as usize;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    };
    for s in &chart.series {
        for run in runs(&s.points, xl, yl) {
            let px: Vec<(f64, f64)> = run.iter().map(|&p| (xa.px(p.0), ya.px(p.1))).collect();
            if s.style == Style::Points {
                out.extend(px.iter().copied());
            } else {
                for w in px.windows(2) {
                    segment(w[0], w[1], &mut out);
                }
                out.extend(px.first().copied());
            }
        }
        for (p, e) in s.points.iter().zip(&s.err) {
            if is_valid(*p, xl, yl) && e.is_finite() {
                segment(
                    (xa.px(p.0), ya.px(p.1 - e)),
                    (xa.px(p.0), ya.px(p.1 + e)),
                    &mut out,
                );
            }
        }
    }
    for m in &chart.marks {
        match m.kind {
            MarkKind::VLine if m.x.is_finite() => {
                let px = xa.px(m.x);
                segment((px, rect.y), (px, rect.y + rect.h), &mut out);
            }
            MarkKind::Point => out.push((xa.px(m.x), ya.px(m.y))),
            MarkKind::Arrow { dx, dy } => segment(
                (xa.px(m.x), ya.px(m.y)),
                (xa.px(m.x + dx), ya.px(m.y + dy)),
                &mut out,
            ),
            MarkKind::VLine => {}
        }
    }
    out
}

pub(super) fn draw_chart(
    svg: &mut Svg,
    area: Rect,
    chart: &Chart,
    id: usize,
) -> Result<(), String> {
    let chart = &scaled_units(chart);
    let (xl, yl) = (chart.x_log, chart.y_log);
    let pts = chart_points(chart);
    let entries = if chart.hide_legend {
        Vec::new()
    } else {
        legend_entries(chart)
    };
    let head_h = heading_height(area.w, &chart.title, &chart.note);
    // Lay out, find the tick labels' width, lay out again; then place the legend inside
    // the plot, or in a key above it (and lay out once more).
    let mut key_h = 0.0;
    let mut ytick_w = 18.0;
    let ranges = DataRanges::of(chart, &pts);
    let layout = |key_h: f64, ytick_w: &mut f64| {
        let mut rect = plot_rect(area, head_h, key_h, *ytick_w);
        for _ in 0..2 {
            let (_, yr) = ranges.fit(chart, rect);
            let ya = Axis::up(yr, yl, rect);
            *ytick_w = ya
                .ticks(tick_target(rect.h))
                .iter()
                .map(|(_, l)| text_width(l, TICK_SIZE))
                .fold(0.0, f64::max);
            rect = plot_rect(area, head_h, key_h, *ytick_w);
        }
        let (xr, yr) = ranges.fit(chart, rect);
        (rect, Axis::across(xr, xl, rect), Axis::up(yr, yl, rect))
    };
    let (mut rect, mut xa, mut ya) = layout(key_h, &mut ytick_w);
    let mut inside = None;
    if !entries.is_empty() {
        let drawn = drawn_points(chart, &xa, &ya, rect);
        inside = free_place(rect, legend_box(&entries), &drawn);
        if inside.is_none() {
            key_h = key_height(&entries, area.w - 2.0 * PAD);
            (rect, xa, ya) = layout(key_h, &mut ytick_w);
        }
    }
    draw_heading(svg, area, &chart.title, &chart.note);
    if key_h > 0.0 {
        draw_key(
            svg,
            area.x + PAD,
            area.w - 2.0 * PAD,
            area.y + head_h,
            &entries,
        );
    }
    draw_axes(svg, rect, &xa, &ya, (&chart.x_label, &chart.y_label), true);
    let clip = format!("plot{id}");
    svg.clip(&clip, rect);
    draw_series(svg, chart, (&xa, &ya), rect, &clip);
    draw_marks(svg, chart, (&xa, &ya), rect);
    if let Some((x, y)) = inside {
        draw_legend(svg, x, y, &entries);
    }
    Ok(())
}

/// The label's unit with an SI prefix for small values: a unit in newtons (`[N]`,
/// `[N mm]`, `[N/m]`, ...) whose largest value is below 1 becomes mN, µN or nN, and the
/// factor the data are multiplied by. None if the unit stays.
pub(super) fn prefixed_unit(label: &str, max_abs: f64) -> Option<(f64, String)> {
    let open = label.rfind('[')?;
    let unit = label[open + 1..].strip_suffix(']')?;
    let rest = unit.strip_prefix('N')?;
    if !(rest.is_empty() || rest.starts_with(' ') || rest.starts_with('/') || rest.starts_with('·'))
    {
        return None;
    }
    if !(max_abs > 0.0 && max_abs < 1.0 && max_abs.is_finite()) {
        return None;
    }
    let (factor, prefix) = match max_abs {
        v if v >= 1e-3 => (1e3, "m"),
        v if v >= 1e-6 => (1e6, "µ"),
        _ => (1e9, "n"),
    };
    Some((factor, format!("{}[{prefix}N{rest}]", &label[..open])))
}

/// The chart with each axis in newtons rescaled by [`prefixed_unit`].
fn scaled_units(chart: &Chart) -> Chart {
    let mut c = chart.clone();
    let pts = chart_points(chart);
    let max_x = pts.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let max_y = pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    if let Some((k, label)) = prefixed_unit(&chart.y_label, max_y) {
        c.y_label = label;
        for s in &mut c.series {
            s.points.iter_mut().for_each(|p| p.1 *= k);
            s.err.iter_mut().for_each(|e| *e *= k);
        }
        for m in &mut c.marks {
            m.y *= k;
            if let MarkKind::Arrow { dy, .. } = &mut m.kind {
                *dy *= k;
            }
        }
    }
    if let Some((k, label)) = prefixed_unit(&chart.x_label, max_x) {
        c.x_label = label;
        for s in &mut c.series {
            s.points.iter_mut().for_each(|p| p.0 *= k);
        }
        for m in &mut c.marks {
            m.x *= k;
            if let MarkKind::Arrow { dx, .. } = &mut m.kind {
                *dx *= k;
            }
        }
    }
    c
}

/// Draws the series: obstacle fills first, then lines, error bars and markers.
fn draw_series(svg: &mut Svg, chart: &Chart, axes: (&Axis, &Axis), rect: Rect, clip: &str) {
    let (xa, ya) = axes;
    let (xl, yl) = (chart.x_log, chart.y_log);
    let to_px = |p: (f64, f64)| (xa.px(p.0), ya.px(p.1));
    for s in chart.series.iter().filter(|s| s.style == Style::Obstacle) {
        for run in runs(&s.points, xl, yl) {
            let mut px: Vec<(f64, f64)> = run.iter().map(|&p| to_px(p)).collect();
            if let (Some(&a), Some(&b)) = (px.first(), px.last()) {
                px.push((b.0, rect.y - 3.0));
                px.push((a.0, rect.y - 3.0));
            }
            svg.polygon(&px, OBSTACLE_FILL, &format!("{clip}f"));
        }
    }
    for s in chart.series.iter().filter(|s| s.style == Style::Region) {
        for run in runs(&s.points, xl, yl) {
            let px: Vec<(f64, f64)> = run.iter().map(|&p| to_px(p)).collect();
            svg.polygon(&px, OBSTACLE_FILL, &format!("{clip}f"));
        }
    }
    for s in &chart.series {
        let col = rgb(palette(s.color));
        let dense = s.points.len() > 60;
        for run in runs(&s.points, xl, yl) {
            let px: Vec<(f64, f64)> = run.iter().map(|&p| to_px(p)).collect();
            if s.style != Style::Points {
                svg.polyline(
                    &px,
                    &col,
                    crate::svg::LINE_W * s.width_factor(),
                    s.line_dash().pattern(),
                    clip,
                );
            }
        }
        for (p, e) in s.points.iter().zip(&s.err) {
            if is_valid(*p, xl, yl) && e.is_finite() && *e > 0.0 {
                let (x, y0, y1) = (xa.px(p.0), ya.px(p.1 - e), ya.px(p.1 + e));
                svg.line((x, y0), (x, y1), &col, 0.5, None);
                svg.line((x - 1.2, y0), (x + 1.2, y0), &col, 0.5, None);
                svg.line((x - 1.2, y1), (x + 1.2, y1), &col, 0.5, None);
            }
        }
        if matches!(s.style, Style::Points | Style::LinePoints) {
            let r = if dense { MARKER_R * 0.75 } else { MARKER_R };
            // On a line the markers only tell it apart: about a dozen, evenly spread.
            let every = match s.style {
                Style::LinePoints => s.points.len().div_ceil(MARKERS_ON_A_LINE).max(1),
                _ => 1,
            };
            for p in s
                .points
                .iter()
                .step_by(every)
                .filter(|&&p| is_valid(p, xl, yl))
            {
                let r = if s.style == Style::LinePoints {
                    MARKER_R
                } else {
                    r
                };
                svg.marker(to_px(*p), s.marker_shape(), r, &col, None);
            }
        }
    }
}

/// Draws the marks: event lines, highlighted points (open markers) and arrows.
fn draw_marks(svg: &mut Svg, chart: &Chart, axes: (&Axis, &Axis), rect: Rect) {
    let (xa, ya) = axes;
    let (xl, yl) = (chart.x_log, chart.y_log);
    let dashes = event_dashes(chart);
    for (m, dash) in chart.marks.iter().zip(dashes) {
        let col = rgb(palette(m.color));
        match m.kind {
            MarkKind::VLine => {
                if m.x.is_finite() && (!xl || m.x > 0.0) {
                    let px = xa.px(m.x);
                    svg.line(
                        (px, rect.y),
                        (px, rect.y + rect.h),
                        &col,
                        0.8,
                        dash.pattern(),
                    );
                }
            }
            MarkKind::Point => {
                if is_valid((m.x, m.y), xl, yl) {
                    let p = (xa.px(m.x), ya.px(m.y));
                    svg.marker(p, point_marker(m), 3.0, "none", Some((&col, 0.9)));
                }
            }
            MarkKind::Arrow { dx, dy } => {
                let end = (m.x + dx, m.y + dy);
                if is_valid((m.x, m.y), xl, yl) && is_valid(end, xl, yl) {
                    let a = (xa.px(m.x), ya.px(m.y));
                    svg.arrow(a, (xa.px(end.0), ya.px(end.1)), &col);
                }
            }
        }
    }
}

/// How many markers a [`Style::LinePoints`] series shows at most.
pub(super) const MARKERS_ON_A_LINE: usize = 12;

/// Cell edges around strictly increasing centres.
pub(super) fn edges(centres: &[f64], what: &str) -> Result<Vec<f64>, String> {
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

pub(super) fn draw_heatmap(
    svg: &mut Svg,
    area: Rect,
    map: &HeatMap,
    _id: usize,
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
    let entries: Vec<Entry<'_>> = map
        .categories
        .iter()
        .map(|(n, col)| Entry::Swatch(n.as_str(), *col))
        .collect();
    let head = draw_heading(svg, area, &map.title, "");
    let key_h = key_height(&entries, area.w - 2.0 * PAD);
    draw_key(
        svg,
        area.x + PAD,
        area.w - 2.0 * PAD,
        area.y + head,
        &entries,
    );
    let (xr, yr) = ((xe[0], xe[xe.len() - 1]), (ye[0], ye[ye.len() - 1]));
    let mut rect = plot_rect(area, head, key_h, 18.0);
    let ya0 = Axis::up(yr, false, rect);
    let ytick_w = ya0
        .ticks(tick_target(rect.h))
        .iter()
        .map(|(_, l)| text_width(l, TICK_SIZE))
        .fold(0.0, f64::max);
    rect = plot_rect(area, head, key_h, ytick_w);
    let xa = Axis::across(xr, false, rect);
    let ya = Axis::up(yr, false, rect);
    for (iy, row) in map.cells.iter().enumerate() {
        for (ix, &cat) in row.iter().enumerate() {
            let (x0, x1) = (xa.px(xe[ix]), xa.px(xe[ix + 1]));
            let (y0, y1) = (ya.px(ye[iy + 1]), ya.px(ye[iy]));
            // Each cell overlaps its upper right neighbours by a hair, so that no seam of
            // the background shows between equal cells.
            svg.rect(
                Rect {
                    x: x0,
                    y: y0 - 0.15,
                    w: x1 - x0 + 0.15,
                    h: y1 - y0 + 0.15,
                },
                &rgb(map.categories[cat as usize].1),
                None,
            );
        }
    }
    draw_axes(svg, rect, &xa, &ya, (&map.x_label, &map.y_label), false);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_newtons_get_a_prefix() {
        assert_eq!(
            prefixed_unit("A_x [N]", 2.1e-4),
            Some((1e6, "A_x [µN]".to_string()))
        );
        assert_eq!(
            prefixed_unit("M_A [N mm]", 0.0125),
            Some((1e3, "M_A [mN mm]".to_string()))
        );
        assert_eq!(
            prefixed_unit("q [N/m]", 3e-8),
            Some((1e9, "q [nN/m]".to_string()))
        );
        assert_eq!(prefixed_unit("A_x [N]", 2.0), None);
        assert_eq!(prefixed_unit("x [mm]", 1e-4), None);
        assert_eq!(prefixed_unit("A_x [–]", 1e-4), None);
    }

    #[test]
    fn words_wrap_to_the_width() {
        let lines = wrap(
            "one two three four five six",
            7.0,
            text_width("one two three", 7.0),
        );
        assert_eq!(lines, ["one two three", "four five six"]);
    }
}
