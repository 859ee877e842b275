//! Sweeps against the physics: balance of forces and moments at every point, the phase
//! conditions, the separation kinds of thesis Figs. 5.11/5.14, and the phase patterns the
//! thesis describes for the chapter-5 cases.

use beam_model::{shape_from_tip_angle, FluidLoad, Scene, Whisker};
use contact_sim::phase::contact_loads;
use contact_sim::{
    cases, sweep, FirstContact, Phase, Profile, Separation, SweepResult, SweepSettings,
};

fn run(w: &Whisker, q: f64, p: &Profile, points: usize) -> SweepResult {
    let s = SweepSettings {
        points,
        ..SweepSettings::default()
    };
    sweep(w, FluidLoad { q, alpha: 0.0 }, p, &s).unwrap()
}

#[test]
fn every_point_balances_and_satisfies_its_phase_conditions() {
    let w = Whisker {
        theta: 0.75,
        a: 0.0,
        b: 0.0,
        support: beam_model::Support::Spring { k: 20.0 },
    };
    for (p, q) in [(Profile::g1(), 5.0), (Profile::g2(), 0.0)] {
        let r = run(&w, q, &p, 40);
        for pt in r.contact_points() {
            // contact point on the contour
            assert!((pt.yc - p.y(pt.xc)).abs() < 1e-12);
            // force balance [6.8, 6.9]
            assert!((pt.ax + pt.f * pt.psi.sin() + q * pt.s1).abs() < 1e-12);
            assert!((pt.ay - pt.f * pt.psi.cos()).abs() < 1e-12);
            assert!(pt.f >= -1e-9, "negative contact force {}", pt.f);
            // re-integrate the whisker from the recorded state: the loaded end is the contact
            // point, the base condition holds and the moment is the recorded MA
            let loads = contact_loads(FluidLoad { q, alpha: 0.0 }, pt.psi, pt.f, pt.s1);
            let scene = Scene::new(w, loads);
            let phi1 = pt.phi1;
            if pt.phase == Phase::B {
                assert_eq!(phi1, pt.psi);
            }
            let sol = shape_from_tip_angle(&scene, phi1, 1e-12, 50).unwrap();
            // base condition of the spring [3.21, 3.22]
            let m0 = -sol.base.ma;
            assert!((sol.base.phi0 - std::f64::consts::FRAC_PI_2 - m0 / 20.0).abs() < 1e-9);
            assert!(
                (pt.x0 + sol.loaded_end.x - pt.xc).abs() < 1e-8,
                "contact x {:?} {} vs {}",
                pt.phase,
                pt.x0 + sol.loaded_end.x,
                pt.xc
            );
            assert!((sol.loaded_end.y - pt.yc).abs() < 1e-8, "contact y");
            assert!((sol.base.ma - pt.ma).abs() < 1e-8, "MA");
            assert!((sol.base.phi0 - pt.phi0).abs() < 1e-8, "phi0");
            match pt.phase {
                Phase::A => {
                    assert_eq!(pt.s1, 1.0);
                    assert!(phi1 >= pt.psi - 1e-9, "phase A needs phi1 > psi");
                }
                Phase::B => assert!(pt.s1 < 1.0 + 1e-12),
                Phase::None => unreachable!(),
            }
        }
    }
}

#[test]
fn strong_flow_turns_the_snap_into_a_release() {
    // Thesis Figs. 5.11 / 5.14: without flow the whisker snaps off, under q = 5 (catenary)
    // the contact force decays to zero.
    let w = Whisker::uniform();
    let r0 = run(&w, 0.0, &Profile::g1(), 60);
    assert_eq!(r0.separation, Separation::Snap);
    let last = r0.points.last().unwrap();
    let prev = &r0.points[r0.points.len() - 2];
    assert!(last.f > prev.f, "the contact force rises before a snap");
    let r5 = run(&w, 5.0, &Profile::g1(), 60);
    assert_eq!(r5.separation, Separation::Release);
    assert!(r5.points.last().unwrap().f.abs() < 1e-6);
    // x0 decreases monotonically during contact (the base only moves left)
    for r in [&r0, &r5] {
        let x0: Vec<f64> = r.contact_points().map(|p| p.x0).collect();
        assert!(x0.windows(2).all(|w| w[1] <= w[0] + 1e-12));
    }
}

#[test]
fn pre_contact_rows_carry_the_flow_alone() {
    let r = run(&Whisker::uniform(), 5.0, &Profile::g2(), 20);
    let pre: Vec<_> = r.points.iter().filter(|p| p.phase == Phase::None).collect();
    assert_eq!(pre.len(), 10);
    for p in pre {
        assert!((p.ax + 5.0).abs() < 1e-14 && p.ay.abs() < 1e-14);
    }
}

#[test]
fn chapter5_cases_show_the_phase_patterns_of_the_thesis() {
    let mut table = String::new();
    for c in cases::chapter5() {
        let r = run(&c.whisker, c.q, &c.profile, 40);
        let pattern = r.phase_pattern();
        // remarks of thesis 5.3.2-5.3.5
        if c.case == "4B" && c.label != "A=0 B=0" {
            assert_eq!(
                pattern, "A",
                "4B {}: positive pre-curvature never enters phase B",
                c.label
            );
        }
        if c.case == "5" && c.profile_name == "g1" {
            assert_eq!(
                r.first_contact,
                FirstContact::Tangential,
                "case 5 g1 {}",
                c.label
            );
        }
        if c.case == "2" && c.label == "theta=0.25" {
            assert_eq!(r.first_contact, FirstContact::Tangential);
        }
        if c.case == "3" && c.profile_name == "g2" && c.label == "k=5" {
            assert_eq!(pattern, "A", "a soft follicle keeps tip contact");
        }
        let pts: Vec<_> = r.contact_points().collect();
        let fmax = pts.iter().map(|p| p.f).fold(0.0, f64::max);
        table.push_str(&format!(
            "{:>3} {} {:<16} first={:<10} sep={:<8} pattern={:<4} x0=[{:.4}, {:.4}] fmax={:.4}\n",
            c.case,
            c.profile_name,
            c.label,
            format!("{:?}", r.first_contact),
            match r.separation {
                Separation::MultiContact { .. } => "Multi".to_string(),
                s => format!("{s:?}"),
            },
            pattern,
            pts.first().unwrap().x0,
            pts.last().unwrap().x0,
            fmax
        ));
    }
    insta::assert_snapshot!(table);
}

#[test]
fn bad_inputs_are_refused() {
    assert!(Profile::parse("parabola:-1,0,0").is_err());
    assert!(Profile::parse("wobble").is_err());
    assert!(Profile::parse("cosh:1,2,0").is_err());
    let e = sweep(
        &Whisker {
            theta: -0.5,
            ..Whisker::uniform()
        },
        FluidLoad { q: 5.0, alpha: 0.0 },
        &Profile::g1(),
        &SweepSettings::default(),
    );
    assert!(e.unwrap_err().to_string().contains("theta"));
    // a contour far above the whisker is never touched
    let high = Profile::Parabola {
        a: 1.0,
        xv: 0.0,
        yv: 3.0,
    };
    assert!(matches!(
        sweep(
            &Whisker::uniform(),
            FluidLoad::default(),
            &high,
            &SweepSettings::default()
        ),
        Err(contact_sim::ContactError::NoContact { .. })
    ));
    // a tabulated concave contour is refused
    let xs: Vec<f64> = (0..20).map(|i| i as f64 * 0.2 - 2.0).collect();
    let ys: Vec<f64> = xs.iter().map(|x| 0.9 - 0.1 * x * x).collect();
    let p = Profile::points(xs, ys).unwrap();
    let e = sweep(
        &Whisker::uniform(),
        FluidLoad::default(),
        &p,
        &SweepSettings::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, contact_sim::ContactError::NotConvex { .. }),
        "{e}"
    );
}

#[test]
fn profiles_have_the_documented_shapes() {
    // ge passes through the undeformed tip (0, 1)
    assert!((Profile::ge().y(0.0) - 1.0).abs() < 1e-14);
    assert!((Profile::g1().y(0.0) - 0.2).abs() < 1e-15);
    // spline through a parabola reproduces it closely inside
    let xs: Vec<f64> = (0..41).map(|i| -2.0 + 0.1 * i as f64).collect();
    let ys: Vec<f64> = xs.iter().map(|x| 0.5 + 0.5 * x * x).collect();
    let sp = Profile::points(xs, ys).unwrap();
    for x in [-1.0, -0.33, 0.0, 0.71, 1.5] {
        assert!((sp.y(x) - Profile::g2().y(x)).abs() < 1e-5);
        assert!((sp.psi(x) - Profile::g2().psi(x)).abs() < 1e-3);
    }
    // circle: psi and curvature 1/r
    let c = Profile::parse("circle:0,2,1.5").unwrap();
    assert!((c.curvature(0.3) - 1.0 / 1.5).abs() < 1e-12);
}

/// A sweep's numbers do not depend on how it shares the cores: alone (its second-contact
/// checks and half its rows on a second core where one exists) and three at once on
/// threads (each then in line), the rows are bit for bit the same; on a second-contact
/// scene too, where the checks ahead take the trace back.
#[test]
fn the_numbers_do_not_depend_on_the_cores() {
    let scenes = [
        (Whisker::uniform(), 5.0, 0.0, Profile::g1()),
        (
            Whisker {
                theta: 0.665,
                a: -0.691,
                b: 0.544,
                support: beam_model::Support::Rigid,
            },
            7.167,
            -3.5f64.to_radians(),
            Profile::g1(),
        ),
    ];
    for (k, (w, q, alpha, p)) in scenes.iter().enumerate() {
        let s = SweepSettings {
            points: 60,
            ..SweepSettings::default()
        };
        let flow = FluidLoad {
            q: *q,
            alpha: *alpha,
        };
        let alone = sweep(w, flow, p, &s).unwrap();
        if k == 1 {
            assert!(matches!(alone.separation, Separation::MultiContact { .. }));
        }
        let together: Vec<SweepResult> = std::thread::scope(|scope| {
            let hs: Vec<_> = (0..3)
                .map(|_| scope.spawn(|| sweep(w, flow, p, &s).unwrap()))
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for r in &together {
            assert_eq!(r.points.len(), alone.points.len());
            assert_eq!(r.separation, alone.separation);
            for (a, b) in r.points.iter().zip(&alone.points) {
                assert_eq!(a.x0.to_bits(), b.x0.to_bits());
                assert_eq!(a.ma.to_bits(), b.ma.to_bits());
                assert_eq!(a.ax.to_bits(), b.ax.to_bits());
                assert_eq!(a.phi0.to_bits(), b.phi0.to_bits());
            }
        }
    }
}
