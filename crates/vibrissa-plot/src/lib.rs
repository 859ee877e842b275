//! A small declarative chart API with its own SVG renderer, used by the CLI and by
//! `cargo xtask reproduce` for every figure; each SVG gets a PNG twin rendered with resvg.
//!
//! A [`Chart`] is a titled x-y plot of [`Series`] (lines, dashed lines, points) with
//! automatic ranges, optional log axes (non-positive values are skipped), an optional equal
//! aspect ratio for beam shapes, [`Mark`]s (labelled vertical event lines, highlighted
//! points, arrows) and a note line under the title. NaN points are skipped and split lines.
//! [`FigureStyle::write_svg_panels`] puts several charts in one figure; [`HeatMap`] draws
//! categorical maps (stability maps).
//!
//! What a reader of a paper needs: coordinates are written with 1/100 pixel resolution (no
//! jagged curves), text is measured with the embedded DejaVu Sans font, so legends and
//! labels are sized to their text and placed outside the plotting area (they never cover
//! data), event labels sit in a band above the plot, staggered when close. The PNG is
//! rendered at twice the SVG's size with the same embedded font (no system fonts).
//!
//! No process-wide mutable state: the printed size and the formats of a figure are a
//! [`FigureStyle`] value handed to each writer (its methods), so threads and tests draw at
//! different sizes side by side. The only statics are immutable caches of the embedded font
//! (its parsed face and the font database of [`render_png`], each built once in a
//! `OnceLock`, and the memo of glyph advances, each slot written once with the font's own
//! value): whatever the order of calls, they answer the same.

mod axis;
mod chart;
mod draw;
pub mod error;
mod layout;
mod legend;
mod output;
mod svg;

pub use axis::format_tick;
pub use chart::*;
pub use error::PlotError;
pub use layout::*;
pub use output::*;
pub use svg::{segments, text_width};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::*;
    use crate::draw::*;
    use crate::svg::*;

    /// A linear axis over `lo..hi` drawn on 100 pixels.
    fn linear(lo: f64, hi: f64) -> Axis {
        Axis {
            lo,
            hi,
            log: false,
            p0: 0.0,
            p1: 100.0,
        }
    }

    #[test]
    fn runs_split_at_nan_and_nonpositive_on_log() {
        let p = [
            (1.0, 1.0),
            (2.0, f64::NAN),
            (3.0, 3.0),
            (4.0, 4.0),
            (5.0, -1.0),
        ];
        assert_eq!(runs(&p, false, false).len(), 2);
        assert_eq!(
            runs(&p, false, true),
            vec![vec![(1.0, 1.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn constant_data_gets_distinct_ticks() {
        let (lo, hi) = axis_range(
            [
                std::f64::consts::FRAC_PI_2,
                std::f64::consts::FRAC_PI_2 + 3e-13,
            ]
            .into_iter(),
            false,
        );
        let a = linear(lo, hi);
        let t = a.ticks(5);
        let labels: std::collections::BTreeSet<&String> = t.iter().map(|(_, l)| l).collect();
        assert_eq!(labels.len(), t.len(), "{t:?}");
        assert!(t.len() >= 3);
    }

    #[test]
    fn ticks_are_nice_numbers() {
        let a = Axis {
            lo: -0.13,
            hi: 1.07,
            log: false,
            p0: 0.0,
            p1: 500.0,
        };
        let labels: Vec<String> = a.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let l = Axis {
            lo: 0.5,
            hi: 2e4,
            log: true,
            p0: 0.0,
            p1: 500.0,
        };
        // One notation per axis: 1e4 needs scientific notation, so every decade gets it.
        let labels: Vec<String> = l.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["1e0", "1e1", "1e2", "1e3", "1e4"]);
        let l = Axis {
            lo: 0.05,
            hi: 500.0,
            ..l
        };
        let labels: Vec<String> = l.ticks(6).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
    }

    #[test]
    fn coordinates_are_sub_pixel_and_text_is_measured() {
        assert_eq!(c(12.3456), "12.35");
        assert_eq!(c(3.0), "3");
        assert!(text_width("MMMM", 10.0) > text_width("iiii", 10.0));
        assert!((text_width("x", 20.0) / text_width("x", 10.0) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn tick_labels_are_compact() {
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(2.0), "2");
        assert_eq!(format_tick(1e-6), "1e-6");
        assert_eq!(format_tick(2.5e-8), "2.5e-8");
        assert_eq!(format_tick(-0.0), "0");
    }

    #[test]
    fn ticks_cover_the_data() {
        // Linear: the range widens to ticks on both sides (the old padding left x_c's
        // -0.94..0.75 with the one tick 0).
        let (lo, hi) = to_ticks((-0.97, 0.78), (-0.94, 0.75), false, 100.0);
        let a = linear(lo, hi);
        let t = a.ticks(tick_target(100.0));
        assert!(t.len() >= 3, "{t:?}");
        assert!(
            t[0].0 <= -0.94 && t[t.len() - 1].0 >= 0.75,
            "{t:?} for ({lo}, {hi})"
        );
        // Data that end on a tick keep a little padding instead of another step.
        let (lo, _) = to_ticks((-0.2, 10.2), (0.0, 10.0), false, 100.0);
        assert!((-0.21..0.0).contains(&lo), "{lo}");
        // Log: whole decades, the top one labelled.
        let (lo, hi) = to_ticks((8e-15, 1.3e-10), (1e-14, 1.2e-10), true, 200.0);
        let l = Axis {
            lo,
            hi,
            log: true,
            p0: 0.0,
            p1: 200.0,
        };
        let t = l.ticks(tick_target(200.0));
        assert_eq!(t.last().map(|x| x.1.as_str()), Some("1e-9"), "{t:?}");
        assert!(t[0].0 <= 1e-14, "{t:?}");
    }

    #[test]
    fn the_legend_goes_where_it_hides_no_data() {
        let rect = Rect {
            x: 0.0,
            y: 0.0,
            w: 200.0,
            h: 100.0,
        };
        // Data fill the top right: the legend goes top left.
        let drawn: Vec<(f64, f64)> = (0..50).map(|i| (150.0 + i as f64, 5.0)).collect();
        assert_eq!(free_place(rect, (40.0, 20.0), &drawn), Some((3.0, 3.0)));
        // Data everywhere: no place inside (a key above the plot instead).
        let drawn: Vec<(f64, f64)> = (0..=40)
            .flat_map(|i| (0..=20).map(move |j| (i as f64 * 5.0, j as f64 * 5.0)))
            .collect();
        assert_eq!(free_place(rect, (40.0, 20.0), &drawn), None);
    }

    #[test]
    fn equal_aspect_means_equal_scales() {
        let chart = Chart::new("", "x", "y")
            .with(Series::new("", vec![(-3.0, 0.0), (2.0, 1.2)], Style::Line))
            .equal_aspect();
        let rect = Rect {
            x: 10.0,
            y: 10.0,
            w: 220.0,
            h: 70.0,
        };
        let (xr, yr) = DataRanges::of(&chart, &chart_points(&chart)).fit(&chart, rect);
        let (kx, ky) = ((xr.1 - xr.0) / rect.w, (yr.1 - yr.0) / rect.h);
        assert!((kx / ky - 1.0).abs() < 1e-12, "{kx} vs {ky}");
        assert!(xr.0 <= -3.0 && xr.1 >= 2.0 && yr.0 <= 0.0 && yr.1 >= 1.2);
    }

    #[test]
    fn subscripts_are_markup_only_where_meant() {
        assert_eq!(
            segments("A_x [N]"),
            vec![
                ("A".to_string(), false),
                ("x".to_string(), true),
                (" [N]".to_string(), false)
            ]
        );
        assert_eq!(segments("x_{max}")[1], ("max".to_string(), true));
        assert_eq!(
            segments("file_name"),
            vec![("file_name".to_string(), false)]
        );
        assert!(text_width("A_x", 10.0) < text_width("Ax", 10.0));
    }

    #[test]
    fn figures_print_at_the_chosen_width() {
        let chart = Chart::new("t", "x", "y").with(Series::new(
            "s",
            vec![(0.0, 0.0), (1.0, 1.0)],
            Style::Line,
        ));
        for (size, mm) in [
            (FigureSize::Column, "85mm"),
            (FigureSize::Page, "175mm"),
            (FigureSize::Slide, "254mm"),
        ] {
            let svg = render_figure(&[Panel::Chart(&chart)], 1, (800, 500), size).unwrap();
            assert!(svg.contains(&format!("width=\"{mm}\"")), "{}", &svg[..200]);
        }
    }

    /// Two threads write at two styles at once, each figure at its own size and in its
    /// own formats (with a process-wide setting one of them would take the other's).
    #[test]
    fn threads_write_figures_in_their_own_styles_at_once() {
        let dir = std::env::temp_dir().join(format!("vibrissa-plot-styles-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let chart = Chart::new("t", "x", "y").with(Series::new(
            "s",
            vec![(0.0, 0.0), (1.0, 2.0)],
            Style::Line,
        ));
        let styles = [
            FigureStyle::new(FigureSize::Page, FigureFormats::Svg),
            FigureStyle::new(FigureSize::Slide, FigureFormats::All),
            FigureStyle::default().sized(FigureSize::Column),
            FigureStyle::new(FigureSize::Page, FigureFormats::None),
        ];
        std::thread::scope(|s| {
            for (i, style) in styles.iter().enumerate() {
                let (chart, dir) = (&chart, &dir);
                s.spawn(move || {
                    for k in 0..5 {
                        let p = dir.join(format!("f{i}-{k}.svg"));
                        style.write_svg(chart, &p, (640, 480)).unwrap();
                    }
                });
            }
        });
        for (i, style) in styles.iter().enumerate() {
            for k in 0..5 {
                let p = dir.join(format!("f{i}-{k}.svg"));
                assert_eq!(p.exists(), style.formats.svg(), "{}", p.display());
                assert_eq!(
                    png_path(&p).exists(),
                    style.formats.png(),
                    "{}",
                    p.display()
                );
                if style.formats.svg() {
                    let svg = std::fs::read_to_string(&p).unwrap();
                    let mm = format!("width=\"{}mm\"", style.size.print_mm());
                    assert!(svg.contains(&mm), "{}: {}", p.display(), &svg[..200]);
                }
            }
        }
        // the slide's PNG at 150 dpi of 254 mm: 1500 pixels wide
        let png = std::fs::read(png_path(&dir.join("f1-0.svg"))).unwrap();
        let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
        assert!(width.abs_diff(1500) <= 1, "{width} pixels");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
