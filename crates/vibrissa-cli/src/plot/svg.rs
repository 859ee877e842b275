//! The SVG writer of the charts: the embedded font and text measurement, sizes, and a
//! small SVG builder with 1/100 pixel coordinates.

use super::*;

/// The embedded font (DejaVu Sans, free licence, shipped by the `dejavu` crate).
pub(super) fn font_data() -> &'static [u8] {
    dejavu::sans::regular()
}

pub(super) fn face() -> Option<&'static ttf_parser::Face<'static>> {
    static FACE: OnceLock<Option<ttf_parser::Face<'static>>> = OnceLock::new();
    FACE.get_or_init(|| ttf_parser::Face::parse(font_data(), 0).ok())
        .as_ref()
}

/// The width in points of `text` set in the embedded font at `size` points; subscripts
/// written `_x` or `_{..}` (see [`segments`]) count at their smaller size.
pub fn text_width(text: &str, size: f64) -> f64 {
    segments(text)
        .iter()
        .map(|(t, sub)| plain_width(t, if *sub { size * SUB_SCALE } else { size }))
        .sum()
}

fn plain_width(text: &str, size: f64) -> f64 {
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

/// The size of a subscript relative to its text.
pub(super) const SUB_SCALE: f64 = 0.8;

/// Splits a label into runs of normal text and subscripts (`true`): `A_x`, `M_A`, `φ_0`,
/// `s_1` and `x_{max}` set their subscript lower and smaller. An underscore is markup only
/// before a braced group, or before one letter or digit that ends a word (so `file_name`
/// stays as written).
pub fn segments(text: &str) -> Vec<(String, bool)> {
    let chars: Vec<char> = text.chars().collect();
    let mut out: Vec<(String, bool)> = Vec::new();
    let mut cur = String::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '_' && i + 1 < chars.len() {
            if chars[i + 1] == '{' {
                if let Some(end) = chars[i + 2..].iter().position(|&x| x == '}') {
                    out.push((std::mem::take(&mut cur), false));
                    out.push((chars[i + 2..i + 2 + end].iter().collect(), true));
                    i += end + 3;
                    continue;
                }
            } else if chars[i + 1].is_alphanumeric()
                && chars.get(i + 2).is_none_or(|n| !n.is_alphanumeric())
                && i > 0
            {
                out.push((std::mem::take(&mut cur), false));
                out.push((chars[i + 1].to_string(), true));
                i += 2;
                continue;
            }
        }
        cur.push(c);
        i += 1;
    }
    out.push((cur, false));
    out.retain(|(t, _)| !t.is_empty());
    out
}

pub(super) const FONT: &str = "DejaVu Sans, Verdana, sans-serif";
// Sizes are in points (1/72 in) of the printed figure: the canvas of a figure is as wide
// in points as the printed column, page or slide it is made for (see `FigureSize`).
pub(super) const TITLE_SIZE: f64 = 8.5;
pub(super) const NOTE_SIZE: f64 = 7.0;
pub(super) const LABEL_SIZE: f64 = 8.0;
pub(super) const TICK_SIZE: f64 = 7.0;
pub(super) const LEGEND_SIZE: f64 = 7.0;
pub(super) const PAD: f64 = 4.0;
/// Line widths (points): data, axes, grid.
pub(super) const LINE_W: f64 = 1.0;
pub(super) const AXIS_W: f64 = 0.6;
pub(super) const GRID_W: f64 = 0.35;
/// Marker radius (points).
pub(super) const MARKER_R: f64 = 1.7;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Rect {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

/// An SVG document under construction.
pub(super) struct Svg {
    pub(super) out: String,
}

pub(super) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The `d` attribute of a path through `pts` (`M x y L x y ...`).
pub(super) fn path_data(pts: &[(f64, f64)]) -> String {
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
    d
}

/// A coordinate with 1/100 pixel resolution.
pub(super) fn c(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

impl Svg {
    /// A canvas of `w` x `h` points printed `print_mm` millimetres wide.
    pub(super) fn new(w: f64, h: f64, print_mm: f64) -> Self {
        let mut out = String::new();
        let (wm, hm) = (print_mm, print_mm * h / w);
        let _ = write!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{wm}mm\" height=\"{hm}mm\" \
             viewBox=\"0 0 {w} {h}\" font-family=\"{FONT}\">\n\
             <rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n",
            wm = c(wm),
            hm = c(hm),
            w = c(w),
            h = c(h)
        );
        Svg { out }
    }

    pub(super) fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }

    /// Text with its baseline at `(x, y)`; `anchor` is start, middle or end.
    pub(super) fn text(
        &mut self,
        (x, y): (f64, f64),
        s: &str,
        size: f64,
        anchor: &str,
        fill: &str,
        rotate: bool,
    ) {
        let rot = if rotate {
            format!(" transform=\"rotate(-90 {} {})\"", c(x), c(y))
        } else {
            String::new()
        };
        let mut body = String::new();
        let mut lowered = false;
        for (t, sub) in segments(s) {
            if sub {
                let _ = write!(
                    body,
                    "<tspan font-size=\"{}\" dy=\"{}\">{}</tspan>",
                    c(size * SUB_SCALE),
                    c(size * 0.22),
                    esc(&t)
                );
                lowered = true;
            } else if lowered {
                let _ = write!(
                    body,
                    "<tspan dy=\"{}\">{}</tspan>",
                    c(-size * 0.22),
                    esc(&t)
                );
                lowered = false;
            } else {
                body.push_str(&esc(&t));
            }
        }
        let _ = writeln!(
            self.out,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{fill}\"{rot}>{body}</text>",
            c(x),
            c(y),
            c(size),
        );
    }

    pub(super) fn line(
        &mut self,
        a: (f64, f64),
        b: (f64, f64),
        stroke: &str,
        width: f64,
        dash: Option<&str>,
    ) {
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

    pub(super) fn rect(&mut self, r: Rect, fill: &str, stroke: Option<&str>) {
        let stroke = stroke.map_or(String::new(), |s| {
            format!(" stroke=\"{s}\" stroke-width=\"{AXIS_W}\"")
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

    pub(super) fn polyline(
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
        let d = path_data(pts);
        let dash = dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
        let _ = writeln!(
            self.out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{width}\" \
             stroke-linejoin=\"round\" stroke-linecap=\"round\"{dash} clip-path=\"url(#{clip})\"/>"
        );
    }

    pub(super) fn arrow(&mut self, a: (f64, f64), b: (f64, f64), color: &str) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy).max(1e-9);
        let (ux, uy) = (dx / len, dy / len);
        let (hl, hw) = (4.5_f64.min(0.6 * len), 1.8_f64.min(0.25 * len));
        // The shaft stops inside the head so that its end does not blunt the point.
        let stem = (b.0 - ux * hl * 0.7, b.1 - uy * hl * 0.7);
        self.line(a, stem, color, LINE_W * 0.9, None);
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

    /// A marker of `shape` centred on `p` with "radius" `r`: filled with `fill`, outlined
    /// with `stroke` (colour, width) if given.
    pub(super) fn marker(
        &mut self,
        p: (f64, f64),
        shape: Marker,
        r: f64,
        fill: &str,
        stroke: Option<(&str, f64)>,
    ) {
        let stroke = stroke.map_or(String::new(), |(s, w)| {
            format!(" stroke=\"{s}\" stroke-width=\"{}\"", c(w))
        });
        let (x, y) = p;
        let pts: Vec<(f64, f64)> = match shape {
            Marker::Circle => {
                let _ = writeln!(
                    self.out,
                    "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\"{stroke}/>",
                    c(x),
                    c(y),
                    c(r)
                );
                return;
            }
            Marker::Square => {
                let a = r * 0.9;
                vec![
                    (x - a, y - a),
                    (x + a, y - a),
                    (x + a, y + a),
                    (x - a, y + a),
                ]
            }
            Marker::Triangle => {
                let a = r * 1.25;
                vec![
                    (x, y - a),
                    (x + a * 0.87, y + a * 0.5),
                    (x - a * 0.87, y + a * 0.5),
                ]
            }
            Marker::Diamond => {
                let a = r * 1.25;
                vec![(x, y - a), (x + a, y), (x, y + a), (x - a, y)]
            }
            Marker::TriangleDown => {
                let a = r * 1.25;
                vec![
                    (x, y + a),
                    (x + a * 0.87, y - a * 0.5),
                    (x - a * 0.87, y - a * 0.5),
                ]
            }
        };
        let d = path_data(&pts);
        let _ = writeln!(self.out, "<path d=\"{d} Z\" fill=\"{fill}\"{stroke}/>");
    }

    /// A filled polygon (no outline), clipped to the plot.
    pub(super) fn polygon(&mut self, pts: &[(f64, f64)], fill: &str, clip: &str) {
        if pts.len() < 3 {
            return;
        }
        let d = path_data(pts);
        let _ = writeln!(
            self.out,
            "<path d=\"{d} Z\" fill=\"{fill}\" stroke=\"none\" clip-path=\"url(#{clip})\"/>"
        );
    }

    /// Two clip paths: `id` (the plot with 1.5 pt to spare, so that lines on the frame
    /// keep their width) and `id` + `f` (the plot exactly, for fills).
    pub(super) fn clip(&mut self, id: &str, r: Rect) {
        for (suffix, m) in [("", 1.5), ("f", 0.0)] {
            let _ = writeln!(
                self.out,
                "<clipPath id=\"{id}{suffix}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
                c(r.x - m),
                c(r.y - m),
                c(r.w + 2.0 * m),
                c(r.h + 2.0 * m)
            );
        }
    }
}
