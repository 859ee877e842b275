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

/// The width in pixels of `text` set in the embedded font at `size` pixels.
pub fn text_width(text: &str, size: f64) -> f64 {
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

pub(super) const FONT: &str = "DejaVu Sans, Verdana, sans-serif";
pub(super) const TITLE_SIZE: f64 = 15.0;
pub(super) const NOTE_SIZE: f64 = 11.0;
pub(super) const LABEL_SIZE: f64 = 13.0;
pub(super) const TICK_SIZE: f64 = 11.0;
pub(super) const LEGEND_SIZE: f64 = 12.0;
pub(super) const EVENT_SIZE: f64 = 11.0;
pub(super) const PAD: f64 = 8.0;

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
    pub(super) fn new(size: (u32, u32)) -> Self {
        let mut out = String::new();
        let _ = write!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
             viewBox=\"0 0 {w} {h}\" font-family=\"{FONT}\">\n\
             <rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n",
            w = size.0,
            h = size.1
        );
        Svg { out }
    }

    pub(super) fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }

    /// Text with its baseline at `y`; `anchor` is start, middle or end.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn text(
        &mut self,
        x: f64,
        y: f64,
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
        let _ = writeln!(
            self.out,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{fill}\"{rot}>{}</text>",
            c(x),
            c(y),
            size,
            esc(s)
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
            format!(" stroke=\"{s}\" stroke-width=\"1\"")
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
        let dash = dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
        let _ = writeln!(
            self.out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{width}\" \
             stroke-linejoin=\"round\" stroke-linecap=\"round\"{dash} clip-path=\"url(#{clip})\"/>"
        );
    }

    pub(super) fn circle(
        &mut self,
        p: (f64, f64),
        r: f64,
        fill: &str,
        stroke: Option<(&str, f64)>,
    ) {
        let stroke = stroke.map_or(String::new(), |(s, w)| {
            format!(" stroke=\"{s}\" stroke-width=\"{w}\"")
        });
        let _ = writeln!(
            self.out,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\"{stroke}/>",
            c(p.0),
            c(p.1),
            r
        );
    }

    pub(super) fn arrow(&mut self, a: (f64, f64), b: (f64, f64), color: &str) {
        self.line(a, b, color, 2.0, None);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy).max(1e-9);
        let (ux, uy) = (dx / len, dy / len);
        let (hl, hw) = (9.0, 4.5);
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

    pub(super) fn clip(&mut self, id: &str, r: Rect) {
        let _ = writeln!(
            self.out,
            "<clipPath id=\"{id}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
            c(r.x - 4.0),
            c(r.y - 4.0),
            c(r.w + 8.0),
            c(r.h + 8.0)
        );
    }
}
