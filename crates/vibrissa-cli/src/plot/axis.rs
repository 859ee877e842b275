//! Axes: valid points and their runs, ranges (linear and log), ticks and their labels.

use super::*;

pub(super) fn is_valid(p: (f64, f64), x_log: bool, y_log: bool) -> bool {
    p.0.is_finite() && p.1.is_finite() && (!x_log || p.0 > 0.0) && (!y_log || p.1 > 0.0)
}

/// Splits the points into runs of consecutive valid points.
pub(super) fn runs(points: &[(f64, f64)], x_log: bool, y_log: bool) -> Vec<Vec<(f64, f64)>> {
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

/// The padded range of `values` on a linear or log axis. A range narrower than 1e-9 of its
/// magnitude (a constant up to rounding) is widened so that its ticks stay distinct.
pub(super) fn axis_range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        if hi / lo < 1.0 + 1e-9 {
            return (lo / 2.0, hi * 2.0);
        }
        let f = (hi / lo).powf(0.04);
        (lo / f, hi * f)
    } else {
        let mag = lo.abs().max(hi.abs());
        if hi - lo <= 1e-9 * mag || hi == lo {
            let mid = 0.5 * (lo + hi);
            let pad = if mag == 0.0 { 1.0 } else { mag * 0.1 };
            return (mid - pad, mid + pad);
        }
        let pad = (hi - lo) * 0.04;
        (lo - pad, hi + pad)
    }
}

/// A linear or logarithmic mapping from data to pixels.
#[derive(Debug, Clone, Copy)]
pub(super) struct Axis {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) log: bool,
    pub(super) p0: f64,
    pub(super) p1: f64,
}

impl Axis {
    /// The horizontal axis of `rect` over `range`.
    pub(super) fn across(range: (f64, f64), log: bool, rect: Rect) -> Self {
        Axis {
            lo: range.0,
            hi: range.1,
            log,
            p0: rect.x,
            p1: rect.x + rect.w,
        }
    }

    /// The vertical axis of `rect` over `range` (upwards).
    pub(super) fn up(range: (f64, f64), log: bool, rect: Rect) -> Self {
        Axis {
            lo: range.0,
            hi: range.1,
            log,
            p0: rect.y + rect.h,
            p1: rect.y,
        }
    }

    pub(super) fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    pub(super) fn px(&self, v: f64) -> f64 {
        self.p0 + self.t(v) * (self.p1 - self.p0)
    }

    /// Tick values and labels, about `target` of them.
    pub(super) fn ticks(&self, target: usize) -> Vec<(f64, String)> {
        if self.log {
            let (a, b) = (
                self.lo.log10().ceil() as i32,
                self.hi.log10().floor() as i32,
            );
            let decades = (b - a + 1).max(0) as usize;
            let step = decades.div_ceil(target.max(1)).max(1) as i32;
            // One notation per axis: plain numbers if every decade is between 0.01 and
            // 1000, else 1eN throughout.
            let plain = a >= -2 && b <= 3;
            let decade = |e: i32| {
                if plain {
                    format_tick(10f64.powi(e))
                } else {
                    format!("1e{e}")
                }
            };
            let mut out: Vec<(f64, String)> = (a..=b)
                .step_by(step as usize)
                .map(|e| (10f64.powi(e), decade(e)))
                .collect();
            if decades < 2 {
                for e in (a - 1)..=b {
                    for m in [2.0, 5.0] {
                        let v = m * 10f64.powi(e);
                        if v >= self.lo && v <= self.hi {
                            out.push((v, format_tick(v)));
                        }
                    }
                }
                out.sort_by(|x, y| x.0.total_cmp(&y.0));
            }
            return out;
        }
        let span = self.hi - self.lo;
        let raw = span / target.max(2) as f64;
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 2.5, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw * (1.0 - 1e-9))
            .unwrap_or(10.0 * mag);
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        let digits = (-(step.log10().floor()) as i32
            + if (step / mag - 2.5).abs() < 1e-9 {
                1
            } else {
                0
            })
        .max(0) as usize;
        let big = self.lo.abs().max(self.hi.abs());
        (first..=last)
            .map(|k| {
                let v = k as f64 * step;
                let v = if v.abs() < step * 1e-9 { 0.0 } else { v };
                let label = if big >= 1e5 || (big < 1e-3 && big > 0.0) {
                    format_tick(v)
                } else {
                    format!("{v:.digits$}")
                };
                (v, label.replace('-', "−"))
            })
            .collect()
    }
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

/// The centre of an event label of width `w` over the line at `px`, kept inside `area`.
pub(super) fn label_x(px: f64, w: f64, area: Rect) -> f64 {
    let (lo, hi) = (area.x + PAD + w / 2.0, area.x + area.w - PAD - w / 2.0);
    if lo > hi {
        px
    } else {
        px.clamp(lo, hi)
    }
}

pub(super) fn tick_target(pixels: f64) -> usize {
    ((pixels / 70.0).round() as usize).clamp(4, 9)
}
