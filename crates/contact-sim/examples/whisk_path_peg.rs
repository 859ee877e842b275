//! The whisking bench's scene written as a 2-row path of poses, `(0, 0, 0)` to `(0, 0, 3)`:
//! the uniform rigid whisker under q = 5 turned about its base at the origin against the peg
//! (-0.2, 0.6), 200 points, once: the program callgrind counts for the cost of a path against
//! the rotation `whisk_peg` (docs/whisking.md, "Paths"): `cargo build --release -p
//! contact-sim --example whisk_path_peg && valgrind --tool=callgrind
//! target/release/examples/whisk_path_peg`.
use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, BaseMotion, Pose, Poses, Profile, SweepSettings};

fn main() {
    let turn = Pose {
        x0: 0.0,
        y0: 0.0,
        gamma: 3.0,
    };
    let path = Poses::new(vec![Pose::default(), turn], None).unwrap();
    let s = SweepSettings {
        points: 200,
        motion: BaseMotion::Path(path),
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
