//! The whisking bench's scene: the uniform rigid whisker under q = 5 whisked (rotated about
//! its base at the origin from gamma = 0) against the peg (-0.2, 0.6), 200 points, once: the
//! program callgrind counts for the cost of a rotation against the translating `sweep_g1`
//! (docs/whisking.md): `cargo build --release -p contact-sim --example whisk_peg && valgrind
//! --tool=callgrind target/release/examples/whisk_peg`.
use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, BaseMotion, Profile, SweepSettings};

fn main() {
    let s = SweepSettings {
        points: 200,
        motion: BaseMotion::Rotate {
            x0: 0.0,
            y0: 0.0,
            gamma0: 0.0,
        },
        ..Default::default()
    };
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    let peg = Profile::parse("peg:-0.2,0.6").unwrap();
    let r = sweep(&Whisker::uniform(), flow, &peg, &s).unwrap();
    let last = r.points.last().unwrap();
    println!(
        "{} rows, {}, {}, first touch gamma {:.12}, last gamma {:.12} MA {:.12}",
        r.points.len(),
        r.phase_pattern(),
        r.separation,
        r.first_touch.gamma,
        last.gamma,
        last.ma
    );
}
