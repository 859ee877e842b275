//! The sweep bench's scene (thesis case 1: a uniform rigid whisker under q = 5 past g1, 200
//! points) once, frictionless or with Coulomb friction `mu` (the first argument, default 0):
//! the program callgrind counts for the cost of friction (docs/friction.md):
//! `cargo build --release -p contact-sim --example sweep_g1 && valgrind --tool=callgrind
//! target/release/examples/sweep_g1 [mu]`.
use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, ContactLaw, Profile, SweepSettings};

fn main() {
    let mu: f64 = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 0.0,
        Some(Ok(mu)) => mu,
        Some(Err(e)) => {
            eprintln!("sweep_g1: the argument must be the friction coefficient mu: {e}");
            std::process::exit(2);
        }
    };
    let s = SweepSettings {
        points: 200,
        contact_law: if mu > 0.0 {
            ContactLaw::Coulomb { mu }
        } else {
            ContactLaw::Frictionless
        },
        ..Default::default()
    };
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    let r = match sweep(&Whisker::uniform(), flow, &Profile::g1(), &s) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("sweep_g1: {e}");
            std::process::exit(1);
        }
    };
    let last = r.points.last().unwrap();
    println!(
        "{} rows, {}, {} friction events, last x0 {:.12} MA {:.12}",
        r.points.len(),
        r.phase_pattern(),
        r.friction_events.len(),
        last.x0,
        last.ma
    );
}
