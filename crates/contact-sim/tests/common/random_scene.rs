//! The seeded random scenes of the accuracy batteries (contact-sim's `--tol` sweeps and
//! profile-recon's `--tol` reconstructions draw the same ones): a small deterministic
//! generator and one draw of a scene over the command line's space.

use beam_model::{FluidLoad, Whisker};
use contact_sim::Profile;

/// A small deterministic generator (xorshift64*), uniform in [0, 1).
pub struct Seeded(pub u64);

impl Seeded {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// A scene of a sweep: the contour, the whisker, the flow and a name that gives them all.
pub struct RandomScene {
    pub profile: Profile,
    pub whisker: Whisker,
    pub flow: FluidLoad,
    pub name: String,
}

/// The `k`-th scene drawn from `rng`: the contours by name in turn (g1, g2, ge, a parabola,
/// a circle), theta 0.05..1, A -1..1, B -0.8..0.8, rigid or a spring 2..50, q 0..8, flows at
/// up to ±0.8 rad (46 degrees).
#[allow(dead_code)] // (each battery that includes this file uses a part of it)
pub fn random_scene(rng: &mut Seeded, k: usize) -> RandomScene {
    const PROFILES: [&str; 5] = ["g1", "g2", "ge", "parabola:2,0.4,0.5", "circle:0.2,1.4,0.6"];
    let profile = Profile::parse(PROFILES[k % PROFILES.len()]).unwrap();
    let theta = rng.range(0.05, 1.0);
    let (a, b) = (rng.range(-1.0, 1.0), rng.range(-0.8, 0.8));
    let q = rng.range(0.0, 8.0);
    let alpha = rng.range(-0.8, 0.8);
    let stiff = if rng.next() < 0.5 {
        f64::INFINITY
    } else {
        rng.range(2.0, 50.0)
    };
    let name = format!(
        "#{k} {} theta {theta:.3} A {a:.3} B {b:.3} k {stiff:.1} q {q:.2} alpha {alpha:.2}",
        profile.name()
    );
    RandomScene {
        profile,
        whisker: Whisker::new(theta, a, b, stiff),
        flow: FluidLoad { q, alpha },
        name,
    }
}
