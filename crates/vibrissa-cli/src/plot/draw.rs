//! Drawing a chart or a heat map into an area of a figure: heading, plot rectangle, axes,
//! series, marks and event labels.

use super::*;

/// The heading of a panel (title and note); returns its height.
pub(super) fn draw_heading(svg: &mut Svg, area: Rect, title: &str, note: &str) -> f64 {
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
pub(super) fn plot_rect(area: Rect, head: f64, band: f64, ytick_w: f64, legend_w: f64) -> Rect {
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
pub(super) fn draw_axes(
    svg: &mut Svg,
    r: Rect,
    xa: &Axis,
    ya: &Axis,
    x_label: &str,
    y_label: &str,
    grid: bool,
) {
    let xt = xa.ticks(tick_target(r.w));
    let yt = ya.ticks(tick_target(r.h));
    for (v, label) in &xt {
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
    for (v, label) in &yt {
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

pub(super) fn draw_chart(
    svg: &mut Svg,
    area: Rect,
    chart: &Chart,
    id: usize,
) -> Result<(), String> {
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
        let ya = Axis::up(yr, yl, rect);
        ytick_w = ya
            .ticks(tick_target(rect.h))
            .iter()
            .map(|(_, l)| text_width(l, TICK_SIZE))
            .fold(0.0, f64::max);
        // Event labels: rows of the band above the plot, staggered where they would meet.
        let xa = Axis::across(xr, xl, rect);
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
    let xa = Axis::across(xr, xl, rect);
    let ya = Axis::up(yr, yl, rect);
    draw_axes(svg, rect, &xa, &ya, &chart.x_label, &chart.y_label, true);
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
    let legend_w = legend_width(&entries);
    let head = draw_heading(svg, area, &map.title, "");
    let (xr, yr) = ((xe[0], xe[xe.len() - 1]), (ye[0], ye[ye.len() - 1]));
    let mut rect = plot_rect(area, head, 0.0, 40.0, legend_w);
    let ya0 = Axis::up(yr, false, rect);
    let ytick_w = ya0
        .ticks(tick_target(rect.h))
        .iter()
        .map(|(_, l)| text_width(l, TICK_SIZE))
        .fold(0.0, f64::max);
    rect = plot_rect(area, head, 0.0, ytick_w, legend_w);
    let xa = Axis::across(xr, false, rect);
    let ya = Axis::up(yr, false, rect);
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
    draw_axes(svg, rect, &xa, &ya, &map.x_label, &map.y_label, false);
    draw_legend(svg, rect.x + rect.w + PAD, rect.y, &entries);
    Ok(())
}
