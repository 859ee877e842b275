//! The seeded random scenes of the whisking and path batteries and the RK4 re-integration
//! that checks their rows, shared by contact-sim's batteries (`whisk`, `path`, the
//! translation `battery`) and profile-recon's `whisk_recon` (which reconstructs the very
//! scenes contact-sim's whisking battery sweeps): one generator, one draw, one checker.
#![allow(dead_code)]

use beam_model::equations::{Sensitivities, WhiskerOde};
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Rk4;
use contact_sim::phase::contact_loads;
use contact_sim::{BaseMotion, Phase, Profile, SweepPoint, SweepSettings};

/// SplitMix64, seeded.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// A scene of a battery.
#[derive(Debug)]
pub struct Scene {
    pub name: String,
    pub whisker: Whisker,
    pub flow: FluidLoad,
    pub profile: Profile,
    pub settings: SweepSettings,
}

/// The first draws of a random scene: the whisker (theta 0.3..1, pre-curvature of both
/// signs, rigid in 40 % or a spring k 5..60), the flow (none in 30 %, else q 0..3, at
/// -45..45 degrees), the base `(bx, by)` in [-0.3, 0.3]^2 and the start turn gamma0 in
/// (-0.6, 0.3); the drawn numbers kept for the scene's name.
pub struct Start {
    pub whisker: Whisker,
    pub flow: FluidLoad,
    pub theta: f64,
    pub a: f64,
    pub b: f64,
    pub k: f64,
    pub q: f64,
    pub bx: f64,
    pub by: f64,
    pub gamma0: f64,
}

impl Start {
    pub fn draw(rng: &mut Rng) -> Start {
        let theta = rng.range(0.3, 1.0);
        let a = rng.range(-1.0, 1.0);
        let b = rng.range(-0.6, 0.6);
        let k = if rng.next() < 0.4 {
            f64::INFINITY
        } else {
            rng.range(5.0, 60.0)
        };
        let whisker = Whisker::new(theta, a, b, k);
        let q = if rng.next() < 0.3 {
            0.0
        } else {
            rng.range(0.0, 3.0)
        };
        let flow = FluidLoad {
            q,
            alpha: rng.range(-45.0, 45.0).to_radians(),
        };
        let (bx, by) = (rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let gamma0 = rng.range(-0.6, 0.3);
        Start {
            whisker,
            flow,
            theta,
            a,
            b,
            k,
            q,
            bx,
            by,
            gamma0,
        }
    }

    /// The whisker's and flow's part of a scene's name.
    pub fn describe(&self) -> String {
        let Start {
            theta, a, b, k, q, ..
        } = self;
        format!(
            "theta={theta:.3} A={a:.3} B={b:.3} k={k:.3} q={q:.3} alpha={:.1}deg",
            self.flow.alpha.to_degrees()
        )
    }
}

/// The obstacle drawn (`kind` in [0, 1): a peg below 0.4, a disc below 0.8, else a
/// parabola) at distance `d` from the base `(bx, by)` in the direction `ang` (a disc's near
/// side there, a parabola's vertex over it); a disc's radius or a parabola's width the next
/// draw of `rng`.
pub fn obstacle(rng: &mut Rng, kind: f64, (bx, by): (f64, f64), d: f64, ang: f64) -> Profile {
    let (px, py) = (bx - d * ang.sin(), by + d * ang.cos());
    if kind < 0.4 {
        Profile::Peg { x: px, y: py }
    } else if kind < 0.8 {
        let r = rng.range(0.03, 0.3);
        Profile::Disc {
            x: px - r * ang.sin(),
            y: py + r * ang.cos(),
            r,
        }
    } else {
        Profile::Parabola {
            a: rng.range(0.5, 3.0),
            xv: px,
            yv: by + d.max(0.6) + 0.15,
        }
    }
}

/// A random whisking scene ([`Start::draw`]), an obstacle ([`obstacle`]) placed where the
/// turning whisker meets it (0.35..0.85 from the base, 0.25..0.9 rad ahead of the start), and
/// a rotation about the base from gamma0; one in four scenes translates past a peg or a
/// disc instead.
pub fn random_whisking_scene(rng: &mut Rng, i: usize) -> Scene {
    let st = Start::draw(rng);
    let (bx, by, gamma0) = (st.bx, st.by, st.gamma0);
    let d = rng.range(0.35, 0.85);
    let ang = gamma0 + rng.range(0.25, 0.9);
    let kind = rng.next();
    let translate = rng.next() < 0.25;
    let profile = obstacle(rng, kind, (bx, by), d, ang);
    let (motion, label) = if translate && profile.is_closed() {
        (BaseMotion::Translate, "translate")
    } else {
        (
            BaseMotion::Rotate {
                x0: bx,
                y0: by,
                gamma0,
            },
            "rotate",
        )
    };
    Scene {
        name: format!(
            "#{i} {label} from ({bx:.3}, {by:.3}, {gamma0:.3}) past {} {}",
            profile.name(),
            st.describe()
        ),
        whisker: st.whisker,
        flow: st.flow,
        profile,
        settings: SweepSettings {
            points: 20,
            motion,
            ..SweepSettings::default()
        },
    }
}

/// Keeps the larger deviation in `slot`, with where it was met.
pub fn worse(slot: &mut (f64, String), v: f64, at: impl Fn() -> String) {
    if v > slot.0 {
        *slot = (v, at());
    }
}

/// The whisker integrated from the base with the row's observables as initial values
/// `(phi0, m(0) = -MA, x0, y0)` by classical RK4 (a different integrator, in the other
/// direction than the sweep's shots) on `n` steps over the whole length, `round(n s1)` of them
/// to the loaded end `s1`, then the unloaded rest `(s1, 1]` (`kappa = kappa0`, `m = 0`: the
/// pre-curvature's exact turn over each step, midpoint positions): `(s, phi, m, x, y)`
/// samples to `s = 1`.
pub fn from_base(
    whisker: &Whisker,
    flow: FluidLoad,
    p: &SweepPoint,
    y0: f64,
    n: usize,
) -> Vec<[f64; 5]> {
    let loads = contact_loads(flow, p.psi, p.f, p.s1);
    let ode = WhiskerOde::new(*whisker, loads, p.phi1, Sensitivities::None);
    let k1 = ((n as f64) * p.s1).round().max(1.0) as usize;
    let traj = Rk4 { steps: k1 }
        .integrate(&ode, 0.0, p.s1, &[p.phi0, -p.ma, p.x0, y0])
        .unwrap();
    let mut out: Vec<[f64; 5]> = (0..traj.len())
        .map(|i| {
            let u = traj.state(i);
            [traj.s[i], u[0], u[1], u[2], u[3]]
        })
        .collect();
    let last = *out.last().unwrap();
    let rest = n - k1;
    let (mut phi, mut x, mut y) = (last[1], last[3], last[4]);
    let h = (1.0 - p.s1) / rest.max(1) as f64;
    for j in 0..rest {
        let s0 = p.s1 + j as f64 * h;
        let dphi = whisker.a * (s0 + 0.5 * h) * h + whisker.b * h;
        x += h * (phi + 0.5 * dphi).cos();
        y += h * (phi + 0.5 * dphi).sin();
        phi += dphi;
        out.push([s0 + h, phi, 0.0, x, y]);
    }
    out
}

/// The misfits at the loaded end `s1` of the row `p`'s re-integration `tr` ([`from_base`]),
/// relative to the load scale max(1, f, |MA|) (the recorded base values carry the shots'
/// relative tolerance, so a contact pinned near the base, f ~ 1e4, is checked relative to
/// f): the largest of the free-end moment `m(s1)` and the loaded end's distance from the
/// contact point `(xc, yc)` in x and y; and the phase condition, tangency `phi(s1) = psi`
/// in B, the tip at least as steep as the boundary `phi(s1) >= psi` in A.
pub fn loaded_end_misfit(tr: &[[f64; 5]], p: &SweepPoint) -> (f64, f64) {
    let k1 = tr.iter().position(|v| v[0] >= p.s1 - 1e-15).unwrap();
    let e = tr[k1];
    let scale = 1f64.max(p.f).max(p.ma.abs());
    let d = [e[2], e[3] - p.xc, e[4] - p.yc]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        / scale;
    let ph = match p.phase {
        Phase::B => (e[1] - p.psi).abs(),
        _ => (p.psi - e[1]).max(0.0),
    } / scale;
    (d, ph)
}

/// The worst deviations of the contact rows' checks ([`check_contact_row`]), each with where
/// it was met: the free-end moment and contact point of the RK4 integration from the base,
/// the contact point's clearance from the obstacle, the phase condition (tangency in B, the
/// tip steeper than the boundary in A), the deepest point of the rest of the whisker inside
/// the obstacle.
pub struct ContactSlots<'a> {
    pub resolve: &'a mut (f64, String),
    pub on_obstacle: &'a mut (f64, String),
    pub phase: &'a mut (f64, String),
    pub penetration: &'a mut (f64, String),
}

/// Checks the contact row `p` of a sweep of `s` independently of the sweep's solver: a
/// non-negative force, the force balance [6.7-6.9] in the lab frame to 1e-12, and from its
/// RK4 re-integration from the base ([`from_base`], 4000 steps): `m(s1) = 0` and the loaded
/// end at the contact point (relative to max(1, f, |MA|)), the contact point on the
/// obstacle, the phase condition, no other sampled point inside the obstacle (a peg:
/// nothing enters a point). The deviations go to `slots`, named by `at`.
pub fn check_contact_row(
    s: &Scene,
    p: &SweepPoint,
    slots: ContactSlots,
    at: impl Fn() -> String,
) -> Result<(), String> {
    if p.f < -1e-12 {
        return Err(format!("{}: negative contact force {}", at(), p.f));
    }
    let (sa, ca) = s.flow.alpha.sin_cos();
    let ax = -(p.f * p.psi.sin() + s.flow.q * p.s1 * ca);
    let ay = p.f * p.psi.cos() + s.flow.q * p.s1 * sa;
    if (ax - p.ax).abs() > 1e-12 * (1.0 + p.f) || (ay - p.ay).abs() > 1e-12 * (1.0 + p.f) {
        return Err(format!("{}: Ax, Ay do not balance the loads", at()));
    }
    let tr = from_base(&s.whisker, s.flow, p, p.y0, 4000);
    let (d, ph) = loaded_end_misfit(&tr, p);
    worse(slots.resolve, d, &at);
    worse(
        slots.on_obstacle,
        s.profile.clearance(p.xc, p.yc).abs(),
        &at,
    );
    worse(slots.phase, ph, &at);
    if !s.profile.is_peg() {
        for v in &tr {
            if (v[0] - p.s1).abs() < 2e-3 {
                continue;
            }
            worse(slots.penetration, -s.profile.clearance(v[3], v[4]), &at);
        }
    }
    Ok(())
}
