//! How the curves of chapter 4 are drawn: the dash and marker of each curve family, and
//! fdm as a line, accurate as markers on it and rk4 as rings around them.

use vibrissa_plot::{Chart, Dash, Mark, MarkStyle, Marker, Series, Style};

/// The dash patterns of curve families, in order.
pub(super) const DASHES: [Dash; 5] = [
    Dash::Solid,
    Dash::Dashed,
    Dash::DashDot,
    Dash::Dotted,
    Dash::LongDash,
];

/// The marker of curve family `f`: after five families the markers shift by one against
/// the dashes, so that no two of the first ten families look alike.
pub(super) fn family_marker(f: usize) -> Marker {
    Marker::of_color(f + f / DASHES.len())
}

/// The legend text of a method: fdm and rk4 at the thesis's step.
fn method_label(mname: &str) -> String {
    match mname {
        "fdm" | "rk4" => format!("{mname}, h = 0.01"),
        m => m.to_string(),
    }
}

/// Adds one method's curve of a tip-coordinate panel. fdm (the thesis's method) is a line,
/// accurate filled markers on it, rk4 open rings around them, so that curves that coincide
/// stay visible. In a panel of one family (`single`) the methods have their own colours
/// and legend entries; otherwise the family `f` sets colour, dash and marker and
/// [`method_key`] explains the methods.
pub(super) fn draw_method(
    c: &mut Chart,
    mname: &str,
    pts: Vec<(f64, f64)>,
    single: bool,
    f: usize,
) {
    let name = if single {
        method_label(mname)
    } else {
        String::new()
    };
    match mname {
        "fdm" => {
            let (color, dash) = if single {
                (0, Dash::Solid)
            } else {
                (f, DASHES[f % DASHES.len()])
            };
            c.series.push(
                Series::new(name, break_jumps(pts), Style::Line)
                    .color(color)
                    .dash(dash),
            );
        }
        "rk4" => {
            let color = if single { 2 } else { f };
            for (k, &(x, y)) in pts.iter().enumerate() {
                let label = if k == 0 { name.clone() } else { String::new() };
                c.marks.push(
                    Mark::point(x, y, label, color).styled(MarkStyle::Marker(Marker::Circle)),
                );
            }
        }
        _ => {
            let (color, marker) = if single {
                (1, Marker::Circle)
            } else {
                (f, family_marker(f))
            };
            c.series.push(
                Series::new(name, pts, Style::Points)
                    .color(color)
                    .marker(marker),
            );
        }
    }
}

/// The points with a NaN put into each jump (to another branch, such as the straight
/// whisker under an axial force at beta = 90 deg), so that the line does not join the two
/// branches: a step above 0.1 and five times the steps on either side.
fn break_jumps(pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let step = |i: usize| -> Option<f64> {
        let (a, b) = (pts.get(i)?, pts.get(i + 1)?);
        let d = (b.1 - a.1).abs();
        d.is_finite().then_some(d)
    };
    let mut out = Vec::with_capacity(pts.len() + 2);
    for (i, &p) in pts.iter().enumerate() {
        out.push(p);
        if let Some(d) = step(i) {
            let near = [i.checked_sub(1).and_then(step), step(i + 1)]
                .into_iter()
                .flatten()
                .fold(0.0, f64::max);
            if d > 0.1 && d > 5.0 * near {
                out.push((f64::NAN, f64::NAN));
            }
        }
    }
    out
}

/// The legend entry (black, without data) saying how a method is drawn in a panel of
/// several families.
pub(super) fn method_key(c: &mut Chart, mname: &str) {
    let label = method_label(mname);
    match mname {
        "fdm" => c
            .series
            .push(Series::new(format!("{label} (lines)"), Vec::new(), Style::Line).color(6)),
        "rk4" => c.marks.push(
            Mark::point(f64::NAN, f64::NAN, format!("{label} (rings)"), 6)
                .styled(MarkStyle::Marker(Marker::Circle)),
        ),
        _ => c.series.push(
            Series::new(format!("{label} (markers)"), Vec::new(), Style::Points)
                .color(6)
                .marker(Marker::Circle),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_break_at_jumps_only() {
        let smooth: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 0.2 * i as f64)).collect();
        assert_eq!(break_jumps(smooth.clone()), smooth);
        let mut jump = smooth.clone();
        jump.push((10.0, -3.0));
        let out = break_jumps(jump);
        assert_eq!(out.len(), 12);
        assert!(out[10].0.is_nan());
    }
}
