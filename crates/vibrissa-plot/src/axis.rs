//! Axes: valid points and their runs, ranges (linear and log), ticks and their labels.

use crate::svg::*;

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
        let f = (hi / lo).powf(0.02);
        (lo / f, hi * f)
    } else {
        let mag = lo.abs().max(hi.abs());
        if hi - lo <= 1e-9 * mag || hi == lo {
            let mid = 0.5 * (lo + hi);
            let pad = if mag == 0.0 { 1.0 } else { mag * 0.1 };
            return (mid - pad, mid + pad);
        }
        let pad = (hi - lo) * 0.02;
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
            let step = ((b - a).max(0) as usize).div_ceil(target.max(1)).max(1) as i32;
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
            // Counted down from the top decade (the range ends on it, see `to_ticks`).
            let mut out: Vec<(f64, String)> = (a..=b)
                .rev()
                .step_by(step as usize)
                .map(|e| (10f64.powi(e), decade(e)))
                .collect();
            out.reverse();
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
        let (step, mag) = nice_step(self.hi - self.lo, target);
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

/// The tick step for about `target` ticks over `span`: 1, 2, 2.5 or 5 times a power of
/// ten; also that power.
pub(super) fn nice_step(span: f64, target: usize) -> (f64, f64) {
    let raw = span / target.max(2) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * mag);
    (step, mag)
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

/// Widens the data's range `tight` to the ticks around it, so that the first and last
/// ticks cover the data (linear axes to the next tick step, log axes to whole decades when
/// they span more than one); where the data end on a tick, the padded `range` keeps them
/// off the frame.
pub(super) fn to_ticks(range: (f64, f64), tight: (f64, f64), log: bool, pixels: f64) -> (f64, f64) {
    if tight.0.partial_cmp(&tight.1) != Some(std::cmp::Ordering::Less) {
        return range;
    }
    let (lo, hi) = to_ticks_of(tight, log, pixels);
    let near = |a: f64, b: f64| {
        if log {
            (a / b).ln().abs() < 1e-6
        } else {
            (a - b).abs() <= 1e-6 * (tight.1 - tight.0)
        }
    };
    (
        if near(lo, tight.0) { range.0 } else { lo },
        if near(hi, tight.1) { range.1 } else { hi },
    )
}

fn to_ticks_of(range: (f64, f64), log: bool, pixels: f64) -> (f64, f64) {
    if log {
        let (a, b) = (range.0.log10().floor(), range.1.log10().ceil());
        if b - a >= 2.0 {
            // Labelled decades every `step`, counted down from the top one, so that the
            // first and last ticks both bound the data.
            let step = ((b - a) / tick_target(pixels) as f64).ceil().max(1.0);
            let a = b - step * ((b - a) / step).ceil();
            return (10f64.powf(a), 10f64.powf(b));
        }
        return range;
    }
    // Widen to the tick step; a wider range may take a coarser step, so repeat until the
    // ends are ticks of the range's own step. Data within 1e-6 of a step of a tick count
    // as on it.
    let (mut lo, mut hi) = range;
    for _ in 0..4 {
        let (step, _) = nice_step(hi - lo, tick_target(pixels));
        if !(step > 0.0 && step.is_finite()) {
            break;
        }
        let (l, h) = (
            (range.0 / step + 1e-6).floor() * step,
            (range.1 / step - 1e-6).ceil() * step,
        );
        if (l - lo).abs() <= 1e-9 * step && (h - hi).abs() <= 1e-9 * step {
            break;
        }
        (lo, hi) = (l, h);
    }
    (lo, hi)
}

/// About how many ticks an axis of `pixels` points takes (one per ~32 pt).
pub(super) fn tick_target(pixels: f64) -> usize {
    ((pixels / 32.0).round() as usize).clamp(3, 8)
}
