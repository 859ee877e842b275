//! The SVG writer of the charts: the embedded font and text measurement, sizes, and a
//! small SVG builder with 1/100 pixel coordinates.

use std::sync::atomic::{AtomicU64, Ordering};

use std::fmt::Write as _;
use std::sync::OnceLock;

use crate::chart::*;

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
    if !text.is_empty() && !text.contains('_') {
        // one run of plain text: what `segments` would return, without its allocations
        return plain_width(text, size);
    }
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
    let units: f64 = text.chars().map(|c| advance(face, c)).sum();
    units / upem * size
}

/// The advance of `c` in font units (0.6 em for a character the font lacks); the first
/// [`ADVANCES`] characters are looked up in the font once and then remembered (a figure
/// measures its labels word by word: the font's tables were a tenth of its cost).
fn advance(face: &ttf_parser::Face<'_>, c: char) -> f64 {
    let lookup = || {
        let upem = f64::from(face.units_per_em());
        face.glyph_index(c)
            .and_then(|g| face.glyph_hor_advance(g))
            .map_or(0.6 * upem, f64::from)
    };
    // 0 = not looked up yet (an advance of 0.0 is looked up each time); zero-initialised,
    // the table costs the binary nothing and the process only the pages it touches
    static CACHE: [AtomicU64; ADVANCES] = [const { AtomicU64::new(0) }; ADVANCES];
    let Some(slot) = CACHE.get(c as usize) else {
        return lookup();
    };
    match slot.load(Ordering::Relaxed) {
        0 => {
            let a = lookup();
            slot.store(a.to_bits(), Ordering::Relaxed);
            a
        }
        bits => f64::from_bits(bits),
    }
}

/// How many characters (from U+0000: Latin, Greek, the arrows and the minus sign of the
/// labels) [`advance`] remembers.
const ADVANCES: usize = 0x2300;

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
    push_path_data(&mut d, pts);
    d
}

/// Appends [`path_data`] of `pts` to `out`.
fn push_path_data(out: &mut String, pts: &[(f64, f64)]) {
    out.reserve(pts.len() * 16);
    for (i, p) in pts.iter().enumerate() {
        out.push_str(if i == 0 { "M" } else { " L" });
        push_c(out, p.0);
        out.push(' ');
        push_c(out, p.1);
    }
}

/// A coordinate with 1/100 pixel resolution.
pub(super) fn c(v: f64) -> String {
    let mut s = String::new();
    push_c(&mut s, v);
    s
}

/// Appends [`c`] of `v` to `out`: `v` rounded to two decimals as `format!("{v:.2}")` rounds
/// it (the exact binary value, ties to even), trailing zeros and point dropped, `-0` as `0`.
/// Done with integers (formatting a float with a precision was most of a figure's cost).
fn push_c(out: &mut String, v: f64) {
    let Some(hundredths) = hundredths(v.abs()) else {
        let s = format!("{v:.2}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        out.push_str(if s == "-0" { "0" } else { s });
        return;
    };
    if hundredths == 0 {
        out.push('0');
        return;
    }
    if v < 0.0 {
        out.push('-');
    }
    push_u64(out, hundredths / 100);
    let frac = hundredths % 100;
    if frac != 0 {
        out.push('.');
        out.push(char::from(b'0' + (frac / 10) as u8));
        if frac % 10 != 0 {
            out.push(char::from(b'0' + (frac % 10) as u8));
        }
    }
}

/// `a * 100` (`a` >= 0) rounded to an integer exactly as `{:.2}` rounds (half to even);
/// `None` for a non-finite or huge `a` (>= 1e15), left to the formatter.
fn hundredths(a: f64) -> Option<u64> {
    if !a.is_finite() || a >= 1e15 {
        return None;
    }
    if a == 0.0 {
        return Some(0);
    }
    let bits = a.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    // a = m * 2^e exactly
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp - 1075)
    };
    if e >= 0 {
        // an integer below 1e15: times 100 fits
        return Some((m << e) * 100);
    }
    let k = -e as u32;
    let num = u128::from(m) * 100;
    if k >= 100 {
        // a * 100 < 2^60 / 2^100: rounds to 0
        return Some(0);
    }
    let q = num >> k;
    let r = num & ((1u128 << k) - 1);
    let half = 1u128 << (k - 1);
    let up = r > half || (r == half && q & 1 == 1);
    Some((q + u128::from(up)) as u64)
}

/// Appends the decimal digits of `n`.
fn push_u64(out: &mut String, mut n: u64) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    for &b in &buf[i..] {
        out.push(char::from(b));
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
        let dash = dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
        self.out.push_str("<path d=\"");
        push_path_data(&mut self.out, pts);
        let _ = writeln!(
            self.out,
            "\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{width}\" \
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

#[cfg(test)]
mod tests {
    use super::*;

    /// [`c`] as it was written with the formatter.
    fn c_by_format(v: f64) -> String {
        let s = format!("{v:.2}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    }

    /// Coordinates rounded with integers read as the formatter rounds them: ties (to even),
    /// values just beside a tie, negative values, zeros, tiny, subnormal, huge and
    /// non-finite values, and a million pseudo-random coordinates of every magnitude.
    #[test]
    fn coordinates_round_as_the_formatter_rounds() {
        let mut values = vec![
            0.0,
            -0.0,
            0.004,
            0.005,
            -0.005,
            0.015,
            0.125,
            0.375,
            -0.625,
            2.675,
            1.0,
            100.0,
            -1500.0,
            999.995,
            5e-324,
            f64::MIN_POSITIVE,
            1e15,
            -3e20,
            f64::MAX,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for k in 0..4096 {
            // exact ties: odd multiples of 1/8 and 1/256 times 100
            let t = f64::from(k) / 8.0 + 1.0 / 256.0;
            values.extend([t, -t, t.next_up(), t.next_down(), f64::from(k) * 0.005]);
        }
        let mut x = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..1_000_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let mantissa = (x >> 11) as f64 / (1u64 << 53) as f64;
            let scale = 10f64.powi((x % 24) as i32 - 8);
            let sign = if x & (1 << 5) == 0 { 1.0 } else { -1.0 };
            values.push(sign * mantissa * scale);
        }
        for v in values {
            assert_eq!(c(v), c_by_format(v), "{v:e}");
        }
    }

    #[test]
    fn path_data_and_widths_are_unchanged() {
        assert_eq!(
            path_data(&[(0.0, -0.001), (12.345, 100.5), (-7.0, 3.10)]),
            "M0 0 L12.35 100.5 L-7 3.1"
        );
        // plain text is measured as one run, as `segments` splits it
        for t in [
            "k\u{a0}=\u{a0}20, rigid",
            "x",
            "φ_0",
            "M_A at x_{max}",
            "file_name",
            "_",
        ] {
            let by_runs: f64 = segments(t)
                .iter()
                .map(|(r, sub)| plain_width(r, if *sub { 7.0 * SUB_SCALE } else { 7.0 }))
                .sum();
            assert_eq!(text_width(t, 7.0).to_bits(), by_runs.to_bits(), "{t}");
        }
        // the remembered advances are the font's
        let face = face().unwrap();
        for ch in ['a', 'W', ' ', 'φ', '−', '→', '\u{2fff}', '\u{10000}'] {
            let upem = f64::from(face.units_per_em());
            let direct = face
                .glyph_index(ch)
                .and_then(|g| face.glyph_hor_advance(g))
                .map_or(0.6 * upem, f64::from);
            assert_eq!(advance(face, ch), direct, "{ch}");
            assert_eq!(advance(face, ch), direct, "{ch} (remembered)");
        }
    }
}
