//! The sweep bench's scene (thesis case 1: a uniform rigid whisker under q = 5 past g1, 200
//! points), frictionless, once: the program callgrind counts for the cost of `mu = 0`
//! (docs/friction.md): `cargo build --release -p contact-sim --example sweep_g1 && valgrind
//! --tool=callgrind target/release/examples/sweep_g1`.
use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, Profile, SweepSettings};

fn main() {
    let s = SweepSettings {
        points: 200,
        ..Default::default()
    };
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    let r = sweep(&Whisker::uniform(), flow, &Profile::g1(), &s).unwrap();
    let last = r.points.last().unwrap();
    println!(
        "{} rows, {}, last x0 {:.12} MA {:.12}",
        r.points.len(),
        r.phase_pattern(),
        last.x0,
        last.ma
    );
}
