//! Figures as SVG and PNG (issue 13): printed sizes, font sizes, subscripts, units on the
//! axes, events, phases told apart by line style, and the PNG twin of every SVG.

use std::fs;
use std::path::Path;

use crate::common;
use common::*;

/// Width and height of a PNG from its IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

/// The printed `width` and `height` of an SVG (millimetres) and its canvas width
/// (points, from the viewBox).
fn svg_size(svg: &str) -> (f64, f64, f64) {
    let attr = |name: &str| -> String {
        let start = svg.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        let end = start + svg[start..].find('"').unwrap();
        svg[start..end].to_string()
    };
    let mm = |name: &str| {
        attr(name)
            .strip_suffix("mm")
            .unwrap()
            .parse::<f64>()
            .unwrap()
    };
    let vb: Vec<f64> = attr("viewBox")
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    (mm("width"), mm("height"), vb[2])
}

/// Every font size of an SVG in printed points: (text, subscripts).
fn printed_font_sizes(svg: &str) -> (Vec<f64>, Vec<f64>) {
    let (w_mm, _, canvas) = svg_size(svg);
    let k = w_mm / 25.4 * 72.0 / canvas;
    let mut text = Vec::new();
    let mut sub = Vec::new();
    for (i, _) in svg.match_indices("font-size=\"") {
        let v: f64 = svg[i + 11..i + 11 + svg[i + 11..].find('"').unwrap()]
            .parse()
            .unwrap();
        let tag_start = svg[..i].rfind('<').unwrap();
        if svg[tag_start..].starts_with("<tspan") {
            sub.push(v * k);
        } else {
            text.push(v * k);
        }
    }
    (text, sub)
}

/// Sweeps g1 under q = 5 with 20 contact rows and the flags `extra` into `cwd/out`.
fn sweep_g1(cwd: &Path, extra: &[&str], out: &str) {
    let mut args = vec!["sweep", "--profile", "g1", "--q", "5"];
    args.extend(extra);
    args.extend(["--points", "20"]);
    args.extend(["--out", out]);
    stdout(&run(&args, cwd));
}

/// A rigid support: phi0 = pi/2 throughout, so no phi0 panel; subscripts, units and the
/// legend of `observables.svg`.
fn rigid_observables_have_symbols_and_no_phi0_panel(cwd: &Path) {
    sweep_g1(cwd, &[], "rigid");
    let raw = fs::read_to_string(cwd.join("rigid/observables.svg")).unwrap();
    // Subscripts are set as such: A_x, M_A, x_0.
    assert!(
        raw.contains(">A<tspan") && raw.contains(">M<tspan"),
        "no subscripts"
    );
    let svg = svg_text(&raw);
    assert!(
        !svg.contains("φ0 [rad]"),
        "a rigid support has no phi0 panel"
    );
    assert!(svg.contains("φ0 = π/2 throughout (rigid support, no panel)"));
    for needle in [
        "base x0 [–]",
        "Ax [–]",
        "Ay [–]",
        "MA [–]",
        "first contact (",
        "phase A: tip contact",
        "no contact (flow only)",
    ] {
        assert!(svg.contains(needle), "observables.svg lacks {needle}");
    }
}

/// An elastic support has the phi0 panel; `shapes.svg` names what it draws and places its
/// curves at sub-pixel positions.
fn spring_figures_have_phi0_and_labelled_shapes(cwd: &Path) {
    sweep_g1(cwd, &["--k", "20", "--figures", "all"], "spring");
    let svg = svg_text(&fs::read_to_string(cwd.join("spring/observables.svg")).unwrap());
    assert!(svg.contains("φ0 [rad]"));
    let shapes = fs::read_to_string(cwd.join("spring/shapes.svg")).unwrap();
    for needle in [
        "obstacle (solid above)",
        "flow direction",
        "sweep (base → −x)",
        "first contact",
        "contact points",
    ] {
        assert!(shapes.contains(needle), "shapes.svg lacks {needle}");
    }
    // Sub-pixel coordinates: the curves' paths use fractional pixel positions.
    let frac = shapes
        .split("d=\"M")
        .skip(1)
        .flat_map(|p| p.split('"').next().unwrap().split([' ', 'L', 'M']))
        .filter(|t| t.contains('.'))
        .count();
    assert!(frac > 100, "only {frac} fractional coordinates");
}

/// An SVG prints one column wide (85 mm) with text of 7 pt or more (subscripts 5.5 pt or
/// more), and has its PNG twin at 300 dpi of that print.
fn prints_one_column_with_its_png_twin(p: &Path) {
    let svg = fs::read_to_string(p).unwrap();
    let (w, h, _) = svg_size(&svg);
    assert!((w - 85.0).abs() < 1e-9, "{}: {w} mm wide", p.display());
    let (text, sub) = printed_font_sizes(&svg);
    let small = text
        .iter()
        .chain(&sub)
        .fold(f64::INFINITY, |a, &b| a.min(b));
    assert!(
        text.iter().all(|&v| v >= 6.99),
        "{}: text at {small} pt",
        p.display()
    );
    assert!(
        sub.iter().all(|&v| v >= 5.5),
        "{}: subscript at {small} pt",
        p.display()
    );
    let png = fs::read(p.with_extension("png")).unwrap();
    let px = |mm: f64| (mm / 25.4 * 300.0).round() as i64;
    let (pw, ph) = png_size(&png);
    assert!(
        (i64::from(pw) - px(w)).abs() <= 1 && (i64::from(ph) - px(h)).abs() <= 1,
        "{}: {pw}x{ph} px for {w}x{h} mm",
        p.display()
    );
}

#[test]
fn figures_come_as_svg_and_png_with_symbols_units_and_events() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    rigid_observables_have_symbols_and_no_phi0_panel(cwd);
    spring_figures_have_phi0_and_labelled_shapes(cwd);
    // Every SVG of the folder, with its PNG twin.
    let mut n = 0;
    for e in fs::read_dir(cwd.join("spring")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            prints_one_column_with_its_png_twin(&p);
            n += 1;
        }
    }
    assert_eq!(n, 3, "observables, contact, shapes");
    // Phases and events differ in line style, not only in colour.
    let raw = fs::read_to_string(cwd.join("spring/observables.svg")).unwrap();
    let dashes: std::collections::BTreeSet<&str> = raw
        .split("stroke-dasharray=\"")
        .skip(1)
        .map(|t| &t[..t.find('"').unwrap()])
        .collect();
    assert!(dashes.len() >= 4, "dash patterns: {dashes:?}");
    // --size page prints 175 mm wide, slides 254 mm.
    for (size, mm) in [("page", 175.0), ("slide", 254.0)] {
        sweep_g1(cwd, &["--size", size], size);
        let svg = fs::read_to_string(cwd.join(size).join("observables.svg")).unwrap();
        assert!((svg_size(&svg).0 - mm).abs() < 1e-9, "{size}");
    }
}
