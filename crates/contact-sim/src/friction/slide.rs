//! A frictional sweep that slides throughout, run on the frictionless machinery (issue 39's
//! cost).
//!
//! In slip `ft = s mu fn`, so the force is `F = fn (n + s mu t)`: the frictionless force
//! turned by `atan(s mu)` and stretched by `sqrt(1 + mu^2)` ([`Tilt`]). A sliding leg is
//! therefore the frictionless contact branch ([`crate::branch::Branch`] with that tilt), and
//! a sweep whose contact starts sliding (the first touch's mode, [`super::start`]) and never
//! stops is the frictionless sweep under the tilted force: its trace
//! (`continuation::trace_tightened`: phase switches, snap, release, second contact with the
//! depth checks ahead, end of contour), its rows (`rows::rows`, Broyden rows, the accuracy's
//! estimates and their tighter pass), only with the slip law added:
//!
//! - **the sliding never stops**: at every traced node after the touch the touching
//!   material point slides against `ft`, `-s u > 0` with `u` its velocity along `t` per
//!   unit of the path (phase A: `dt`, the contour parameter rising along `t`; phase B:
//!   `|c'(t)| dt - ds1`, rolling subtracted), along the branch's tangent oriented with the
//!   motion ([`slides_throughout`]). Where it fails (a slip -> stick switch or a sliding
//!   reversal on the path, or a phase switch after which sliding the same way breaks the
//!   law), the sweep falls back to the frictional sweep with its stick legs and switches
//!   ([`super::frictional_rows`]) from the start;
//! - the rows' `ft = s mu fn`, `slip = slip` and the slip distance (the contour's arc length
//!   summed from row to row, less the change of `s1`, [`slip_distances`]).

use super::contour::arc_length;
use crate::branch::Node;
use crate::contact_law::Tilt;
use crate::error::{ContactError, Result};
use crate::first_contact::FirstTouch;
use crate::phase::Phase;
use crate::profile::Profile;
use crate::sweep::{contact_sweep, SweepPoint, SweepProgress, SweepResult, SweepSettings};
use beam_model::{FluidLoad, Whisker};

/// The frictional sweep of a contact that starts sliding with `ft = s mu fn` (`s` from the
/// first touch's probes) on the frictionless machinery under the tilted force, if it slides
/// throughout ([`slides_throughout`]); `None` where it does not (or where that sweep fails
/// otherwise): the caller then runs the frictional sweep with its stick legs.
pub(super) fn sliding_sweep(
    (whisker, flow, profile): (&Whisker, FluidLoad, &Profile),
    settings: &SweepSettings,
    (phi1, touch): (f64, &FirstTouch),
    (s, mu): (f64, f64),
    progress: &mut dyn FnMut(SweepProgress),
) -> Option<SweepResult> {
    let tilt = Tilt { s_mu: s * mu };
    let check = |nodes: &[Node]| slides_throughout(profile, nodes, s, mu);
    let scene = (whisker, flow, profile);
    let mut r = contact_sweep(scene, settings, (phi1, *touch), (tilt, &check), progress).ok()?;
    slip_distances(profile, &mut r.points);
    Some(r)
}

/// The velocity `u` along `t` of the touching material point per unit of the branch's
/// tangent `tn` (in `(v, f, t)`) at `n`: `dt` in phase A (the tip; the contour parameter
/// rises along `t`, spec/model.md), `|c'(t)| dt - ds1` in phase B (the contact point's arc
/// length less the whisker's, rolling).
pub(super) fn sliding_rate(profile: &Profile, n: &Node, tn: &[f64; 3]) -> f64 {
    match n.phase {
        Phase::B => {
            let g = profile.at(n.u[2]);
            g.dx.hypot(g.dy) * tn[2] - tn[0]
        }
        _ => tn[2],
    }
}

/// Whether every traced node after the first touch slides against `ft = s mu fn`:
/// `-s u > 0` along the branch's tangent oriented with the motion (towards the next node of
/// the same phase, or from the one before). A node where it fails is a slip -> stick switch
/// (or a reversal) the frictionless machinery does not follow: the error names it.
pub(super) fn slides_throughout(profile: &Profile, nodes: &[Node], s: f64, mu: f64) -> Result<()> {
    for (i, n) in nodes.iter().enumerate().skip(1) {
        let along = |a: &Node, b: &Node| {
            (a.phase == b.phase && a.u != b.u).then(|| crate::branch::sub(&b.u, &a.u))
        };
        let dir = nodes
            .get(i + 1)
            .and_then(|b| along(n, b))
            .or_else(|| along(&nodes[i - 1], n));
        let Some(dir) = dir else { continue };
        let u = sliding_rate(profile, n, &n.tangent(&dir));
        // a NaN rate fails too
        if (-s * u).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(ContactError::FrictionIndeterminate {
                x0: n.x0(),
                xc: n.state.point.xc,
                mu,
                reason: format!(
                    "the sliding with ft = {s} mu fn stops in phase {} (rate {u:.3e})",
                    n.phase
                ),
            });
        }
    }
    Ok(())
}

/// Each contact row's slip displacement since the first contact row (contour parameter
/// `t0`, contact arc length `s10`): `sigma(t) - sigma(t0) - (s1 - s10)`, the contour's arc
/// length summed from row to row ([`arc_length`]; the contour parameter of a row is `xc` on
/// a graph, `psi` on a circle, [`Profile::at`]).
pub(super) fn slip_distances(profile: &Profile, points: &mut [SweepPoint]) {
    let param = |p: &SweepPoint| match profile {
        Profile::Circle { .. } | Profile::Disc { .. } => p.psi,
        _ => p.xc,
    };
    let mut origin: Option<(f64, f64, f64)> = None;
    for p in points.iter_mut().filter(|p| p.phase != Phase::None) {
        let t = param(p);
        let (t_prev, sigma, s10) = origin.unwrap_or((t, 0.0, p.s1));
        let sigma = sigma + arc_length(profile, t_prev, t);
        p.slip_distance = sigma - (p.s1 - s10);
        origin = Some((t, sigma, s10));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::branch::tests::TestScene;
    use crate::branch::Branch;
    use crate::friction::branch::{FrictionBranch, Mode};
    use crate::friction::start::{first_node, sweeper};
    use crate::friction::{frictional_rows, FrictionSettings};
    use beam_model::shot::Integration;
    use std::cell::RefCell;

    /// The tilted branch is the frictional sliding leg: at the same state, with
    /// `ft = s mu f`, the frictionless branch under [`Tilt`] and the frictional equations
    /// in slip (which build the force from its components, `contact_law::frictional_loads`)
    /// give the same residuals, base position, base angle and moment, in both phases, both
    /// signs of the sliding.
    #[test]
    fn the_tilted_branch_is_the_sliding_leg() {
        let scene = TestScene::bent(1e-13);
        for s_mu in [0.7, -0.4] {
            let branch = Branch {
                tilt: Tilt { s_mu },
                ..scene.branch()
            };
            let fb = FrictionBranch {
                whisker: &scene.whisker,
                flow: scene.flow,
                profile: &scene.profile,
                integration: Integration::adaptive(1e-13),
                tol: 1e-11,
                mu: s_mu.abs(),
                frame: crate::motion::Frame::Translate,
            };
            let mode = Mode::Slip { s: s_mu.signum() };
            for (phase, u) in [(Phase::A, [1.2, 0.8, 0.3]), (Phase::B, [0.7, 0.8, 0.3])] {
                let (r, n) = branch.eval(phase, u).unwrap();
                let w = [u[0], u[1], s_mu * u[1], u[2]];
                let (rf, nf) = fb.eval(phase, mode, w, false).unwrap();
                let (st, tilt) = (n.state, n.state.tilt);
                let err = [
                    r[0] - rf[0],
                    r[1] - rf[1],
                    st.x0 - nf.x0,
                    st.phi0 - nf.phi0,
                    st.m0 - nf.m0,
                ];
                assert!(
                    err.iter().all(|e| e.abs() < 1e-10),
                    "{phase} {s_mu}: {err:?}"
                );
                assert_eq!(tilt, Tilt { s_mu });
                // the state's observables are those of F = f n + ft t
                let (ax, ay, ma) = crate::contact_law::frictional_observables(
                    scene.flow,
                    st.point.psi,
                    st.f,
                    s_mu * st.f,
                    st.s1,
                    st.m0,
                );
                let (oax, oay, oma, _) = st.observables(scene.flow);
                assert!((ax - oax).abs() < 1e-15 && (ay - oay).abs() < 1e-15 && ma == oma);
            }
        }
    }

    /// The tilted branch's Jacobian (rows `dR0, dR1, dx0` in `(v, f, t)`; the force's size
    /// `f sqrt(1 + mu^2)` scales `d/df`) matches central differences of its equations, both
    /// phases, both signs.
    #[test]
    fn the_tilted_jacobian_matches_central_differences() {
        let scene = TestScene::bent(1e-13);
        for s_mu in [0.7, -1.2] {
            let branch = Branch {
                tilt: Tilt { s_mu },
                ..scene.branch()
            };
            for (phase, u) in [(Phase::A, [1.2, 0.8, 0.3]), (Phase::B, [0.7, 0.8, 0.3])] {
                let (_, node) = branch.eval(phase, u).unwrap();
                let h = 1e-5;
                for k in 0..3 {
                    let at = |d: f64| {
                        let mut v = u;
                        v[k] += d;
                        let (r, n) = branch.eval(phase, v).unwrap();
                        [r[0], r[1], n.x0()]
                    };
                    let (p, m) = (at(h), at(-h));
                    for i in 0..3 {
                        let fd = (p[i] - m[i]) / (2.0 * h);
                        let err = (node.jac[i][k] - fd).abs();
                        assert!(
                            err < 1e-7 * (1.0 + fd.abs()),
                            "{phase} {s_mu}: d{i}/du{k} {err:e}"
                        );
                    }
                }
            }
        }
    }

    /// Thesis case 1 (uniform rigid whisker, q = 5, g1) at mu = 0.5 slides throughout: the
    /// sweep on the frictionless machinery and the frictional legs' own sweep (the path
    /// this module replaces, `frictional_rows`) give the same rows (base position,
    /// observables, forces, contact point, slip distance) to the tolerances of the two
    /// traces' event location; the sliding check accepts the traced nodes with the first
    /// touch's sign and refuses them with the other.
    #[test]
    fn a_sliding_sweep_is_the_frictional_legs_sweep() {
        let (whisker, flow, profile) = (
            beam_model::Whisker::uniform(),
            FluidLoad { q: 5.0, alpha: 0.0 },
            Profile::g1(),
        );
        sliding_against_legs((whisker, flow, profile), 0.5);
    }

    /// A straight tapered whisker on a spring (k 10) sliding on a circle (the scene of
    /// profile-recon's stream test): the same agreement, 30 rows, worst 2.8e-11.
    #[test]
    fn a_sliding_tip_on_a_circle_is_the_frictional_legs_sweep() {
        let (whisker, flow, profile) = (
            beam_model::Whisker::new(0.5, 0.0, 0.0, 10.0),
            FluidLoad { q: 1.0, alpha: 0.2 },
            Profile::parse("circle:0.3,1.5,0.6").unwrap(),
        );
        sliding_against_legs((whisker, flow, profile), 0.4);
    }

    /// The sliding sweep against the frictional legs' own at `mu` (module tests above).
    fn sliding_against_legs(
        (whisker, flow, profile): (beam_model::Whisker, FluidLoad, Profile),
        mu: f64,
    ) {
        let settings = SweepSettings {
            points: 30,
            contact_law: crate::contact_law::ContactLaw::Coulomb { mu },
            ..SweepSettings::default()
        };
        let set = FrictionSettings {
            check_penetration: true,
            ..FrictionSettings::of(&settings, mu, crate::motion::Frame::Translate)
        };
        let integration = Integration::adaptive(settings.integration_tol);
        let tol = settings.integration_tol;
        let phi1 = crate::first_contact::free_tip(&whisker, flow, tol, &integration).unwrap();
        let touch = crate::first_contact::first_touch(&whisker, flow, phi1, &profile, tol).unwrap();
        let scene = (&whisker, flow, &profile);
        let sw = sweeper(scene, &set);
        let first = first_node(&sw, &touch, &set).unwrap();
        let Mode::Slip { s } = first.mode else {
            panic!("{:?}", first.mode)
        };
        let fast = sliding_sweep(scene, &settings, (phi1, &touch), (s, mu), &mut |_| {}).unwrap();
        let legs = frictional_rows(&sw, first, &set, &mut |_| {}).unwrap();
        let rows: Vec<_> = fast.contact_points().collect();
        assert_eq!(rows.len(), legs.rows.len());
        assert!(rows.len() >= 30);
        let mut worst = 0.0f64;
        for (a, (b, _)) in rows.iter().zip(&legs.rows) {
            assert_eq!((a.phase, a.slip), (b.phase, b.slip));
            let d = [
                a.x0 - b.x0,
                a.ax - b.ax,
                a.ay - b.ay,
                a.ma - b.ma,
                a.phi0 - b.phi0,
                a.f - b.f,
                a.ft - b.ft,
                a.s1 - b.s1,
                a.xc - b.xc,
                a.slip_distance - b.slip_distance,
            ];
            worst = d.iter().fold(worst, |w, v| w.max(v.abs()));
        }
        eprintln!(
            "sliding sweep against the legs: {} rows, worst {worst:.2e}",
            rows.len()
        );
        assert!(worst < 1e-8, "{worst:e}");
        assert_eq!(fast.separation, legs.separation);
        // the sliding check on the traced nodes: this sign slides, the other does not
        let traced = RefCell::new(Vec::new());
        let keep = |nodes: &[Node]| {
            traced.replace(nodes.to_vec());
            Ok(())
        };
        let tilt = Tilt { s_mu: s * mu };
        contact_sweep(scene, &settings, (phi1, touch), (tilt, &keep), &mut |_| {}).unwrap();
        let nodes = traced.into_inner();
        assert!(nodes.len() > 10);
        assert!(slides_throughout(&profile, &nodes, s, mu).is_ok());
        let e = slides_throughout(&profile, &nodes, -s, mu).unwrap_err();
        assert!(
            matches!(e, ContactError::FrictionIndeterminate { .. }),
            "{e}"
        );
    }
}
