//! The beam-model issue's work-precision charts: error (in the norm the accuracy is asked
//! in) against time per solve of fdm, rk4, accurate, fdm-richardson and the automatic
//! choice, on the reference scenes.

use std::time::Instant;

use beam_model::scenarios;
use vibrissa_io::atomic::OutputDir;
use vibrissa_plot::{Chart, Dash, Marker, Series, Style};
use xtask::study;

use crate::common::{self, note_err, sci, sig};
use crate::Report;

/// One work-precision chart per reference scene, with its CSV and key numbers.
pub(super) fn work_precision(out: &OutputDir, report: &mut Report) {
    for (name, scene) in scenarios::reference_scenes() {
        let t0 = Instant::now();
        let entry = report.entry(
            format!("Work-precision: {name}"),
            "Accuracy against speed of the methods (beam-model issue): the error in the \
             norm the accuracy is asked in (--tol: the largest difference of the tip, the \
             loaded end and the base observables Ax, Ay, MA, phi0; the CSV also gives the \
             tip error max(|x1 - x1_ref|, |y1 - y1_ref|)) against an accurate solve at tol \
             1e-14, against the median wall time of one solve (log-log); fdm n = 25..3200, \
             rk4 n = 10..1280, accurate tol = 1e-4..1e-13; auto (the automatic choice) \
             asked for 1e-4..1e-12.",
        );
        let points = match study::work_precision(&scene, name) {
            Ok(p) => p,
            Err(e) => {
                entry.fail(format!("work_precision({name}): {e}"));
                continue;
            }
        };
        let mut chart = Chart::new(
            format!("work-precision: {name}"),
            "time per solve [s]",
            "error: tip, loaded end, base [–]",
        )
        .log(true, true);
        for (c, m) in ["fdm", "rk4", "accurate", "fdm-richardson", "auto"]
            .iter()
            .enumerate()
        {
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.method == *m)
                .map(|p| (p.seconds, p.error.max(1e-16)))
                .collect();
            let series = Series::new(*m, pts, Style::LinePoints).color(c);
            // The automatic choice: black, dashed, its own marker.
            let series = if *m == "auto" {
                series
                    .color(6)
                    .dash(Dash::Dashed)
                    .marker(Marker::TriangleDown)
            } else {
                series
            };
            chart.series.push(series);
            let best = points
                .iter()
                .filter(|p| p.method == *m && p.error.is_finite())
                .min_by(|a, b| a.error.total_cmp(&b.error));
            if let Some(b) = best {
                entry.number(
                    format!("{m}: smallest error (setting, time)"),
                    format!(
                        "{} ({}, {} s)",
                        sci(b.error),
                        sig(b.setting, 3),
                        sci(b.seconds)
                    ),
                    None,
                );
            }
            let failed = points
                .iter()
                .filter(|p| p.method == *m && !p.error.is_finite())
                .count();
            if failed > 0 {
                entry.number(format!("{m}: failed settings"), failed.to_string(), None);
            }
            if *m == "auto" {
                entry.number(
                    "auto: time / cheapest method meeting the same accuracy (per tol)",
                    auto_vs_envelope(&points),
                    None,
                );
                continue;
            }
            if *m != "accurate" {
                let orders: Vec<String> = study::observed_orders(&points, m)
                    .iter()
                    .map(|(_, o)| format!("{o:.2}"))
                    .collect();
                entry.number(format!("{m}: observed orders"), orders.join(", "), None);
            }
        }
        let stem = format!("work_precision_{name}");
        let r = common::svg_column(out, entry, &format!("{stem}.svg"), &chart).and_then(|()| {
            common::text(out, entry, &format!("{stem}.csv"), &study::to_csv(&points))
        });
        note_err(entry, &stem, r);
        entry.number("time", format!("{:.2} s", t0.elapsed().as_secs_f64()), None);
    }
}

/// For each accuracy asked of `auto`: its time over the time of the fastest other setting
/// of any method whose error meets that accuracy (1 = on the lower envelope).
fn auto_vs_envelope(points: &[study::WorkPoint]) -> String {
    points
        .iter()
        .filter(|p| p.method == "auto")
        .map(|a| {
            let best = points
                .iter()
                .filter(|p| p.method != "auto" && p.error <= a.setting)
                .map(|p| p.seconds)
                .fold(f64::INFINITY, f64::min);
            format!("{}: {:.2}", sci(a.setting), a.seconds / best)
        })
        .collect::<Vec<_>>()
        .join(", ")
}
