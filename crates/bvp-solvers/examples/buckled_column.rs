//! The Euler elastica of a cantilever column under an axial end load `P` (length 1, bending
//! stiffness 1):
//!
//! `theta'' + P sin(theta) = 0`, `theta(0) = 0` (clamped), `theta'(1) = 0` (free, load along
//! the original axis),
//!
//! solved by shooting backwards from the tip with a prescribed tip angle `theta(1) = theta_tip`
//! and the load `P` as the unknown, so that `theta(0) = 0`. The post-buckling branch is the
//! pendulum quarter period: `P = K(sin(theta_tip/2))^2` with `K` the complete elliptic integral
//! of the first kind; as `theta_tip -> 0` it bifurcates from the straight column at the Euler
//! load `P_c = pi^2/4`.
//!
//! Run with `cargo run -p bvp-solvers --example buckled_column --release`.

use bvp_solvers::continuation::{BranchGuard, Continuation};
use bvp_solvers::integrator::{Dop853, OdeSystem};
use bvp_solvers::shooting::{Shooting, ShootingIntegrator, ShootingProblem};
use bvp_solvers::trust_region::TrustRegionOptions;
use bvp_solvers::BvpError;

struct Column {
    theta_tip: f64,
}

struct ColumnOde {
    p: f64,
}

impl OdeSystem for ColumnOde {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[1];
        du[1] = -self.p * u[0].sin();
    }
}

impl ShootingProblem for Column {
    type System = ColumnOde;
    fn n_params(&self) -> usize {
        1
    }
    fn system(&self, p: &[f64]) -> ColumnOde {
        ColumnOde { p: p[0] }
    }
    fn span(&self, _p: &[f64]) -> (f64, f64) {
        (1.0, 0.0)
    }
    fn initial_state(&self, _p: &[f64], u0: &mut [f64]) {
        u0[0] = self.theta_tip;
        u0[1] = 0.0;
    }
    fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
        r[0] = u_end[0];
    }
}

/// Complete elliptic integral of the first kind, `K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))`.
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    // quadratic convergence: 40 iterations are far more than enough for k < 1
    for _ in 0..40 {
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    std::f64::consts::PI / (2.0 * a)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let shooting = Shooting {
        integrator: ShootingIntegrator::Dop853(Dop853::new(1e-13, 1e-13)),
        options: TrustRegionOptions {
            tol: 1e-12,
            ..TrustRegionOptions::default()
        },
    };
    let load = |theta_tip: f64, guess: f64| -> Result<f64, BvpError> {
        Ok(shooting.solve(&Column { theta_tip }, &[guess])?.params[0])
    };
    let pc = std::f64::consts::PI.powi(2) / 4.0;

    println!("Cantilever elastica: load P versus tip angle (Euler load pi^2/4 = {pc:.12})");
    println!(
        "{:>10} {:>18} {:>18} {:>10}",
        "theta_tip", "P (shooting)", "K(sin(t/2))^2", "rel. diff"
    );
    let cont = Continuation {
        initial_step: 0.25,
        min_step: 1e-4,
        max_step: 0.5,
    };
    // the first row solved from the Euler load, each next one by continuation in the tip
    // angle from the previous row (secant predictor, jump guard)
    let (mut prev_t, mut p) = (0.05f64, load(0.05, pc)?);
    for t in [0.05f64, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0] {
        if t != prev_t {
            let (y, _) = cont.follow(
                prev_t,
                t,
                vec![p],
                &BranchGuard::default(),
                |tt, g: &[f64]| load(tt, g[0]).map(|p| vec![p]),
            )?;
            (prev_t, p) = (t, y[0]);
        }
        let exact = ellip_k((t / 2.0).sin()).powi(2);
        let rel = (p - exact) / exact;
        println!("{t:>10.3} {p:>18.12} {exact:>18.12} {rel:>10.1e}");
        assert!(rel.abs() < 1e-9, "theta_tip {t}: P {p} vs {exact}");
    }

    // Small-amplitude limit: P(t) = P_c (1 + t^2/8 + O(t^4)); eliminate the t^2 term from
    // two small amplitudes.
    let (t1, t2) = (0.02, 0.04);
    let (p1, p2) = (load(t1, pc)?, load(t2, pc)?);
    let pc_est = (t2 * t2 * p1 - t1 * t1 * p2) / (t2 * t2 - t1 * t1);
    println!(
        "\nbifurcation load from P({t1}) = {p1:.12}, P({t2}) = {p2:.12}:\n  P_c ~ {pc_est:.12}  (pi^2/4 = {pc:.12}, diff {:.1e})",
        pc_est - pc
    );
    Ok(())
}
