mod support;
use beam_model::scenarios;
use beam_model::study::*;
use std::time::Instant;

#[test]
#[ignore]
fn explore() {
    for (name, scene) in scenarios::reference_scenes() {
        let t = Instant::now();
        let p = work_precision(&scene, name).unwrap();
        println!("{name} {:?}", t.elapsed());
        print!("{}", to_csv(&p));
        println!("{:?}", observed_orders(&p, "fdm"));
        println!("{:?}", observed_orders(&p, "rk4"));
    }
    for r in ansys_comparison().unwrap() {
        println!("{r:?}");
    }
    for kind in LoadAxis::ALL {
        for k in DEFAULT_KS {
            let t = Instant::now();
            let maps = stability_maps(
                &default_map_methods(),
                kind,
                &kind.default_loads(),
                &default_thetas(),
                k,
            )
            .unwrap();
            println!("{} k={k} {:?}", kind.name(), t.elapsed());
            for m in &maps {
                println!(" {} {:?}", m.method, m.counts());
                for (i, row) in m.cells.iter().enumerate() {
                    let s: String = row
                        .iter()
                        .map(|o| match o {
                            Outcome::Converged {
                                continuation_steps: 0,
                            } => '.',
                            Outcome::Converged { .. } => 'c',
                            Outcome::Failed => 'F',
                            Outcome::Wrong => 'W',
                        })
                        .collect();
                    let r: String = m.reference[i]
                        .iter()
                        .map(|&b| if b { ' ' } else { 'R' })
                        .collect();
                    println!("  {:5.1} {s} {r}", m.loads[i]);
                }
            }
        }
    }
}
