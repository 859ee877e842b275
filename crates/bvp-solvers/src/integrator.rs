//! Integrators for first-order systems `u' = G(s, u)`.
//!
//! * [`Rk4`]: the classical fourth-order Runge-Kutta method with equal steps, returning the
//!   whole [`Trajectory`] (global error `O(h^4)`).
//! * [`Dop853`]: the explicit Runge-Kutta pair of Dormand and Prince of order 8 with the
//!   combined 5th/3rd-order error estimator, step-size control and 7th-order dense output of
//!   Hairer's `DOP853` (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., §II.10), plus
//!   event location (first zero of a scalar function of the solution) by Brent's method on the
//!   dense output.
//!
//! Both methods allocate their stage buffers once per call; no allocation happens per step
//! (except for the stored dense output when it is requested).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::roots::{brent, RootOptions};
use crate::{BvpError, Result};

/// A first-order system `u' = G(s, u)` of dimension [`OdeSystem::dim`].
///
/// ```
/// use bvp_solvers::integrator::{Dop853, OdeSystem};
///
/// /// The harmonic oscillator u'' = -u as a first-order system.
/// struct Oscillator;
/// impl OdeSystem for Oscillator {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
///         du[0] = u[1];
///         du[1] = -u[0];
///     }
/// }
///
/// let sol = Dop853::new(1e-12, 1e-12).integrate(&Oscillator, 0.0, 1.0, &[0.0, 1.0]).unwrap();
/// assert!((sol.u_end[0] - 1f64.sin()).abs() < 1e-11);
/// ```
pub trait OdeSystem {
    /// Dimension `n` of the state `u`.
    fn dim(&self) -> usize;
    /// Writes `G(s, u)` into `du` (both of length `n`).
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]);
}

impl<T: OdeSystem + ?Sized> OdeSystem for &T {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        (**self).rhs(s, u, du)
    }
}

fn check_span(s0: f64, s1: f64) -> Result<()> {
    if !s0.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "s0",
            value: s0,
            reason: "integration bounds must be finite",
        });
    }
    if !s1.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "s1",
            value: s1,
            reason: "integration bounds must be finite",
        });
    }
    Ok(())
}

fn check_initial(n: usize, u0: &[f64]) -> Result<()> {
    if u0.len() != n {
        return Err(BvpError::DimensionMismatch {
            name: "initial state u0",
            expected: n,
            found: u0.len(),
        });
    }
    if let Some(&v) = u0.iter().find(|v| !v.is_finite()) {
        return Err(BvpError::InvalidInput {
            name: "u0",
            value: v,
            reason: "initial state must be finite",
        });
    }
    Ok(())
}

#[inline]
fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

// ---------------------------------------------------------------------------------------------
// RK4
// ---------------------------------------------------------------------------------------------

/// The classical fourth-order Runge-Kutta method with `steps` equal steps `h = (s1 - s0)/steps`:
///
/// `k1 = G(s, u)`, `k2 = G(s + h/2, u + h k1/2)`, `k3 = G(s + h/2, u + h k2/2)`,
/// `k4 = G(s + h, u + h k3)`, `u <- u + h (k1 + 2 k2 + 2 k3 + k4)/6`.
///
/// The global error is `O(h^4)` for smooth `G`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rk4 {
    /// Number of equal steps (at least 1).
    pub steps: usize,
}

/// States at the nodes `s_0, ..., s_steps` of a fixed-step integration.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Nodes (`steps + 1` values, `s[0] = s0`, last `= s1`).
    pub s: Vec<f64>,
    /// Row-major states: `u[i*dim .. (i+1)*dim]` is the state at `s[i]`.
    pub u: Vec<f64>,
    /// State dimension.
    pub dim: usize,
}

impl Trajectory {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.s.len()
    }
    /// `true` if there are no nodes (never the case for a trajectory returned by [`Rk4`]).
    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }
    /// State at node `i` (panics if `i >= len()`, like slice indexing).
    pub fn state(&self, i: usize) -> &[f64] {
        &self.u[i * self.dim..(i + 1) * self.dim]
    }
    /// State at the last node (empty slice for an empty trajectory).
    pub fn last(&self) -> &[f64] {
        match self.s.len() {
            0 => &[],
            m => self.state(m - 1),
        }
    }
}

struct Rk4Work {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    tmp: Vec<f64>,
}

impl Rk4Work {
    fn new(n: usize) -> Self {
        Self {
            k1: vec![0.0; n],
            k2: vec![0.0; n],
            k3: vec![0.0; n],
            k4: vec![0.0; n],
            tmp: vec![0.0; n],
        }
    }

    /// One classical RK4 step in place.
    #[inline]
    #[allow(clippy::needless_range_loop)]
    fn step<S: OdeSystem + ?Sized>(&mut self, sys: &S, s: f64, h: f64, u: &mut [f64]) {
        let n = u.len();
        sys.rhs(s, u, &mut self.k1);
        for i in 0..n {
            self.tmp[i] = u[i] + 0.5 * h * self.k1[i];
        }
        sys.rhs(s + 0.5 * h, &self.tmp, &mut self.k2);
        for i in 0..n {
            self.tmp[i] = u[i] + 0.5 * h * self.k2[i];
        }
        sys.rhs(s + 0.5 * h, &self.tmp, &mut self.k3);
        for i in 0..n {
            self.tmp[i] = u[i] + h * self.k3[i];
        }
        sys.rhs(s + h, &self.tmp, &mut self.k4);
        let h6 = h / 6.0;
        for i in 0..n {
            u[i] += h6 * (self.k1[i] + 2.0 * (self.k2[i] + self.k3[i]) + self.k4[i]);
        }
    }
}

impl Rk4 {
    fn check(&self, s0: f64, s1: f64) -> Result<()> {
        if self.steps == 0 {
            return Err(BvpError::InvalidInput {
                name: "steps",
                value: 0.0,
                reason: "RK4 needs at least one step",
            });
        }
        check_span(s0, s1)
    }

    /// Classical RK4 with `steps` equal steps from `s0` to `s1` (`s1 < s0` allowed: backward).
    ///
    /// Node `i` is `s0 + i (s1 - s0)/steps` (the last node is exactly `s1`).
    ///
    /// # Errors
    /// `InvalidInput` for `steps == 0`, non-finite bounds or a non-finite `u0`;
    /// `DimensionMismatch` if `u0.len() != sys.dim()`; `NonFinite` if the state becomes NaN/inf.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
    ) -> Result<Trajectory> {
        self.check(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        let m = self.steps;
        let h = (s1 - s0) / m as f64;
        let mut s = Vec::with_capacity(m + 1);
        let mut u = Vec::with_capacity((m + 1) * n);
        s.push(s0);
        u.extend_from_slice(u0);
        let mut work = Rk4Work::new(n);
        let mut cur = u0.to_vec();
        for i in 0..m {
            let si = s0 + i as f64 * h;
            work.step(sys, si, h, &mut cur);
            if !all_finite(&cur) {
                return Err(BvpError::NonFinite {
                    what: "RK4 state",
                    s: si + h,
                });
            }
            s.push(if i + 1 == m {
                s1
            } else {
                s0 + (i + 1) as f64 * h
            });
            u.extend_from_slice(&cur);
        }
        Ok(Trajectory { s, u, dim: n })
    }

    /// Like [`Rk4::integrate`] but keeps only the final state, written into `u_end`
    /// (length `sys.dim()`); no trajectory is stored (for shooting).
    ///
    /// # Errors
    /// As [`Rk4::integrate`]; `DimensionMismatch` also for a wrong `u_end` length.
    pub fn integrate_final<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        u_end: &mut [f64],
    ) -> Result<()> {
        self.check(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        if u_end.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "u_end",
                expected: n,
                found: u_end.len(),
            });
        }
        let h = (s1 - s0) / self.steps as f64;
        let mut work = Rk4Work::new(n);
        u_end.copy_from_slice(u0);
        for i in 0..self.steps {
            work.step(sys, s0 + i as f64 * h, h, u_end);
        }
        if !all_finite(u_end) {
            return Err(BvpError::NonFinite {
                what: "RK4 state",
                s: s1,
            });
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// DOP853 coefficients (Hairer's dop853.f; Dormand & Prince 1980 / Hairer-Nørsett-Wanner)
// ---------------------------------------------------------------------------------------------

#[allow(clippy::excessive_precision, clippy::unreadable_literal)]
mod coef {
    pub const C2: f64 = 0.526001519587677318785587544488e-01;
    pub const C3: f64 = 0.789002279381515978178381316732e-01;
    pub const C4: f64 = 0.118350341907227396726757197510e+00;
    pub const C5: f64 = 0.281649658092772603273242802490e+00;
    pub const C6: f64 = 0.333333333333333333333333333333e+00;
    pub const C7: f64 = 0.25e+00;
    pub const C8: f64 = 0.307692307692307692307692307692e+00;
    pub const C9: f64 = 0.651282051282051282051282051282e+00;
    pub const C10: f64 = 0.6e+00;
    pub const C11: f64 = 0.857142857142857142857142857142e+00;
    pub const C14: f64 = 0.1e+00;
    pub const C15: f64 = 0.2e+00;
    pub const C16: f64 = 0.777777777777777777777777777778e+00;

    /// Node of stage `j` (0-based: stage `j+1` of Hairer), for stages 2..=12.
    pub const C: [f64; 12] = [0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, 1.0];

    pub const B1: f64 = 5.42937341165687622380535766363e-2;
    pub const B6: f64 = 4.45031289275240888144113950566e0;
    pub const B7: f64 = 1.89151789931450038304281599044e0;
    pub const B8: f64 = -5.8012039600105847814672114227e0;
    pub const B9: f64 = 3.1116436695781989440891606237e-1;
    pub const B10: f64 = -1.52160949662516078556178806805e-1;
    pub const B11: f64 = 2.01365400804030348374776537501e-1;
    pub const B12: f64 = 4.47106157277725905176885569043e-2;

    pub const BHH1: f64 = 0.244094488188976377952755905512e+00;
    pub const BHH2: f64 = 0.733846688281611857341361741547e+00;
    pub const BHH3: f64 = 0.220588235294117647058823529412e-01;

    pub const ER1: f64 = 0.1312004499419488073250102996e-01;
    pub const ER6: f64 = -0.1225156446376204440720569753e+01;
    pub const ER7: f64 = -0.4957589496572501915214079952e+00;
    pub const ER8: f64 = 0.1664377182454986536961530415e+01;
    pub const ER9: f64 = -0.3503288487499736816886487290e+00;
    pub const ER10: f64 = 0.3341791187130174790297318841e+00;
    pub const ER11: f64 = 0.8192320648511571246570742613e-01;
    pub const ER12: f64 = -0.2235530786388629525884427845e-01;

    pub const A21: f64 = 5.26001519587677318785587544488e-2;
    pub const A31: f64 = 1.97250569845378994544595329183e-2;
    pub const A32: f64 = 5.91751709536136983633785987549e-2;
    pub const A41: f64 = 2.95875854768068491816892993775e-2;
    pub const A43: f64 = 8.87627564304205475450678981324e-2;
    pub const A51: f64 = 2.41365134159266685502369798665e-1;
    pub const A53: f64 = -8.84549479328286085344864962717e-1;
    pub const A54: f64 = 9.24834003261792003115737966543e-1;
    pub const A61: f64 = 3.7037037037037037037037037037e-2;
    pub const A64: f64 = 1.70828608729473871279604482173e-1;
    pub const A65: f64 = 1.25467687566822425016691814123e-1;
    pub const A71: f64 = 3.7109375e-2;
    pub const A74: f64 = 1.70252211019544039314978060272e-1;
    pub const A75: f64 = 6.02165389804559606850219397283e-2;
    pub const A76: f64 = -1.7578125e-2;
    pub const A81: f64 = 3.70920001185047927108779319836e-2;
    pub const A84: f64 = 1.70383925712239993810214054705e-1;
    pub const A85: f64 = 1.07262030446373284651809199168e-1;
    pub const A86: f64 = -1.53194377486244017527936158236e-2;
    pub const A87: f64 = 8.27378916381402288758473766002e-3;
    pub const A91: f64 = 6.24110958716075717114429577812e-1;
    pub const A94: f64 = -3.36089262944694129406857109825e0;
    pub const A95: f64 = -8.68219346841726006818189891453e-1;
    pub const A96: f64 = 2.75920996994467083049415600797e1;
    pub const A97: f64 = 2.01540675504778934086186788979e1;
    pub const A98: f64 = -4.34898841810699588477366255144e1;
    pub const A101: f64 = 4.77662536438264365890433908527e-1;
    pub const A104: f64 = -2.48811461997166764192642586468e0;
    pub const A105: f64 = -5.90290826836842996371446475743e-1;
    pub const A106: f64 = 2.12300514481811942347288949897e1;
    pub const A107: f64 = 1.52792336328824235832596922938e1;
    pub const A108: f64 = -3.32882109689848629194453265587e1;
    pub const A109: f64 = -2.03312017085086261358222928593e-2;
    pub const A111: f64 = -9.3714243008598732571704021658e-1;
    pub const A114: f64 = 5.18637242884406370830023853209e0;
    pub const A115: f64 = 1.09143734899672957818500254654e0;
    pub const A116: f64 = -8.14978701074692612513997267357e0;
    pub const A117: f64 = -1.85200656599969598641566180701e1;
    pub const A118: f64 = 2.27394870993505042818970056734e1;
    pub const A119: f64 = 2.49360555267965238987089396762e0;
    pub const A1110: f64 = -3.0467644718982195003823669022e0;
    pub const A121: f64 = 2.27331014751653820792359768449e0;
    pub const A124: f64 = -1.05344954667372501984066689879e1;
    pub const A125: f64 = -2.00087205822486249909675718444e0;
    pub const A126: f64 = -1.79589318631187989172765950534e1;
    pub const A127: f64 = 2.79488845294199600508499808837e1;
    pub const A128: f64 = -2.85899827713502369474065508674e0;
    pub const A129: f64 = -8.87285693353062954433549289258e0;
    pub const A1210: f64 = 1.23605671757943030647266201528e1;
    pub const A1211: f64 = 6.43392746015763530355970484046e-1;

    pub const A141: f64 = 5.61675022830479523392909219681e-2;
    pub const A147: f64 = 2.53500210216624811088794765333e-1;
    pub const A148: f64 = -2.46239037470802489917441475441e-1;
    pub const A149: f64 = -1.24191423263816360469010140626e-1;
    pub const A1410: f64 = 1.5329179827876569731206322685e-1;
    pub const A1411: f64 = 8.20105229563468988491666602057e-3;
    pub const A1412: f64 = 7.56789766054569976138603589584e-3;
    pub const A1413: f64 = -8.298e-3;
    pub const A151: f64 = 3.18346481635021405060768473261e-2;
    pub const A156: f64 = 2.83009096723667755288322961402e-2;
    pub const A157: f64 = 5.35419883074385676223797384372e-2;
    pub const A158: f64 = -5.49237485713909884646569340306e-2;
    pub const A1511: f64 = -1.08347328697249322858509316994e-4;
    pub const A1512: f64 = 3.82571090835658412954920192323e-4;
    pub const A1513: f64 = -3.40465008687404560802977114492e-4;
    pub const A1514: f64 = 1.41312443674632500278074618366e-1;
    pub const A161: f64 = -4.28896301583791923408573538692e-1;
    pub const A166: f64 = -4.69762141536116384314449447206e0;
    pub const A167: f64 = 7.68342119606259904184240953878e0;
    pub const A168: f64 = 4.06898981839711007970213554331e0;
    pub const A169: f64 = 3.56727187455281109270669543021e-1;
    pub const A1613: f64 = -1.39902416515901462129418009734e-3;
    pub const A1614: f64 = 2.9475147891527723389556272149e0;
    pub const A1615: f64 = -9.15095847217987001081870187138e0;

    pub const D41: f64 = -0.84289382761090128651353491142e+01;
    pub const D46: f64 = 0.56671495351937776962531783590e+00;
    pub const D47: f64 = -0.30689499459498916912797304727e+01;
    pub const D48: f64 = 0.23846676565120698287728149680e+01;
    pub const D49: f64 = 0.21170345824450282767155149946e+01;
    pub const D410: f64 = -0.87139158377797299206789907490e+00;
    pub const D411: f64 = 0.22404374302607882758541771650e+01;
    pub const D412: f64 = 0.63157877876946881815570249290e+00;
    pub const D413: f64 = -0.88990336451333310820698117400e-01;
    pub const D414: f64 = 0.18148505520854727256656404962e+02;
    pub const D415: f64 = -0.91946323924783554000451984436e+01;
    pub const D416: f64 = -0.44360363875948939664310572000e+01;
    pub const D51: f64 = 0.10427508642579134603413151009e+02;
    pub const D56: f64 = 0.24228349177525818288430175319e+03;
    pub const D57: f64 = 0.16520045171727028198505394887e+03;
    pub const D58: f64 = -0.37454675472269020279518312152e+03;
    pub const D59: f64 = -0.22113666853125306036270938578e+02;
    pub const D510: f64 = 0.77334326684722638389603898808e+01;
    pub const D511: f64 = -0.30674084731089398182061213626e+02;
    pub const D512: f64 = -0.93321305264302278729567221706e+01;
    pub const D513: f64 = 0.15697238121770843886131091075e+02;
    pub const D514: f64 = -0.31139403219565177677282850411e+02;
    pub const D515: f64 = -0.93529243588444783865713862664e+01;
    pub const D516: f64 = 0.35816841486394083752465898540e+02;
    pub const D61: f64 = 0.19985053242002433820987653617e+02;
    pub const D66: f64 = -0.38703730874935176555105901742e+03;
    pub const D67: f64 = -0.18917813819516756882830838328e+03;
    pub const D68: f64 = 0.52780815920542364900561016686e+03;
    pub const D69: f64 = -0.11573902539959630126141871134e+02;
    pub const D610: f64 = 0.68812326946963000169666922661e+01;
    pub const D611: f64 = -0.10006050966910838403183860980e+01;
    pub const D612: f64 = 0.77771377980534432092869265740e+00;
    pub const D613: f64 = -0.27782057523535084065932004339e+01;
    pub const D614: f64 = -0.60196695231264120758267380846e+02;
    pub const D615: f64 = 0.84320405506677161018159903784e+02;
    pub const D616: f64 = 0.11992291136182789328035130030e+02;
    pub const D71: f64 = -0.25693933462703749003312586129e+02;
    pub const D76: f64 = -0.15418974869023643374053993627e+03;
    pub const D77: f64 = -0.23152937917604549567536039109e+03;
    pub const D78: f64 = 0.35763911791061412378285349910e+03;
    pub const D79: f64 = 0.93405324183624310003907691704e+02;
    pub const D710: f64 = -0.37458323136451633156875139351e+02;
    pub const D711: f64 = 0.10409964950896230045147246184e+03;
    pub const D712: f64 = 0.29840293426660503123344363579e+02;
    pub const D713: f64 = -0.43533456590011143754432175058e+02;
    pub const D714: f64 = 0.96324553959188282948394950600e+02;
    pub const D715: f64 = -0.39177261675615439165231486172e+02;
    pub const D716: f64 = -0.14972683625798562581422125276e+03;
}

use coef::*;

/// Number of stored stage derivatives `k1..k16` (0-based slots 0..=15).
const NSTAGE: usize = 16;

/// Writes `out = y + h * sum_j a_j k_j` for the listed (0-based stage, coefficient) pairs.
#[inline(always)]
fn combo<const M: usize>(y: &[f64], h: f64, k: &[f64], terms: [(usize, f64); M], out: &mut [f64]) {
    let n = y.len();
    for (i, o) in out.iter_mut().enumerate().take(n) {
        let mut acc = 0.0;
        for &(j, a) in terms.iter() {
            acc += a * k[j * n + i];
        }
        *o = y[i] + h * acc;
    }
}

/// `sum_j a_j k_j` (no `y`, no `h`) at component `i`.
#[inline(always)]
fn lin<const M: usize>(k: &[f64], n: usize, i: usize, terms: [(usize, f64); M]) -> f64 {
    let mut acc = 0.0;
    for &(j, a) in terms.iter() {
        acc += a * k[j * n + i];
    }
    acc
}

/// Dormand-Prince 8(5,3) (Hairer's `DOP853`) with step-size control, dense output of order 7,
/// and event location.
///
/// One step of size `h` uses 12 stages `k1..k12` (`k1 = G(s, u)` is reused from the previous
/// step, FSAL) and gives the 8th-order update `u_new = u + h sum b_i k_i`. The local error is
/// estimated as in Hairer's code from the 5th-order difference `e5 = h sum er_i k_i` and the
/// 3rd-order difference `e3 = sum b_i k_i - bhh1 k1 - bhh2 k9 - bhh3 k12`,
/// scaled by `sk_i = atol + rtol max(|u_i|, |u_new,i|)`:
///
/// `err = |h| E5 / sqrt(n (E5 + 0.01 E3))` with `E5 = sum (e5_i/sk_i)^2`, `E3 = sum (e3_i/sk_i)^2`.
///
/// The step is accepted if `err <= 1`; the new step is `h / max(1/6, min(3, err^(1/8)/0.9))`
/// (after a rejection no increase). When `h_init` is `None`, the initial step is Hairer's
/// `HINIT` guess. Dense output uses three extra stages `k14..k16` and Hairer's 7th-degree
/// interpolant.
#[derive(Clone, Debug)]
pub struct Dop853 {
    /// Relative tolerance (`>= 0`).
    pub rtol: f64,
    /// Absolute tolerance (`>= 0`, `rtol + atol > 0`).
    pub atol: f64,
    /// Initial step size magnitude; `None` = Hairer's automatic guess.
    pub h_init: Option<f64>,
    /// Maximum number of attempted steps (accepted + rejected).
    pub max_steps: usize,
    /// Store the dense output for [`OdeSolution::eval`].
    pub dense: bool,
}

/// Work counters of an adaptive integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntegrationStats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand-side evaluations.
    pub rhs_evals: usize,
}

/// Result of a [`Dop853`] integration: the end state and (optionally) the dense output.
#[derive(Clone, Debug)]
pub struct OdeSolution {
    /// Where the integration ended (`s1`, or the event location).
    pub s_end: f64,
    /// State at `s_end`.
    pub u_end: Vec<f64>,
    /// Work counters.
    pub stats: IntegrationStats,
    dim: usize,
    s_start: f64,
    u_start: Vec<f64>,
    /// Step start points plus the end (len = steps + 1), empty if not dense.
    points: Vec<f64>,
    /// Step sizes (len = steps).
    hs: Vec<f64>,
    /// 8 * dim interpolation coefficients per step.
    cont: Vec<f64>,
    dense: bool,
}

/// Evaluates the DOP853 dense output of one step with coefficients `rc` (8 blocks of `n`).
#[inline]
fn dense_eval(rc: &[f64], n: usize, theta: f64, out: &mut [f64]) {
    let t1 = 1.0 - theta;
    for (i, o) in out.iter_mut().enumerate().take(n) {
        let r = |j: usize| rc[j * n + i];
        *o = r(0)
            + theta
                * (r(1)
                    + t1 * (r(2)
                        + theta
                            * (r(3) + t1 * (r(4) + theta * (r(5) + t1 * (r(6) + theta * r(7)))))));
    }
}

impl OdeSolution {
    /// Dense output at `s` inside the integrated span (`None` outside, or if the solution was
    /// computed with `dense == false`). The interpolant is Hairer's 7th-order continuous
    /// extension, evaluated on the step containing `s`.
    pub fn eval(&self, s: f64) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        if self.eval_into(s, &mut out) {
            Some(out)
        } else {
            None
        }
    }

    /// As [`OdeSolution::eval`], writing into `out` (length `dim`); returns `false` (and leaves
    /// `out` unspecified) if `s` is outside the span, not dense, or `out` has the wrong length.
    pub fn eval_into(&self, s: f64, out: &mut [f64]) -> bool {
        if !self.dense || out.len() != self.dim || !s.is_finite() {
            return false;
        }
        let dir = if self.s_end >= self.s_start {
            1.0
        } else {
            -1.0
        };
        let t = dir * (s - self.s_start);
        if t < 0.0 || t > dir * (self.s_end - self.s_start) {
            return false;
        }
        let nsteps = self.hs.len();
        if nsteps == 0 {
            out.copy_from_slice(&self.u_start);
            return true;
        }
        if s == self.s_end {
            out.copy_from_slice(&self.u_end);
            return true;
        }
        // last step whose start is <= s (in the integration direction)
        let idx = self.points[..nsteps]
            .partition_point(|&p| dir * (p - self.s_start) <= t)
            .saturating_sub(1)
            .min(nsteps - 1);
        let theta = (s - self.points[idx]) / self.hs[idx];
        let n = self.dim;
        dense_eval(&self.cont[idx * 8 * n..(idx + 1) * 8 * n], n, theta, out);
        true
    }

    /// Accepted step end points, including the start (and ending at `s_end`); empty if the
    /// integration was not dense.
    pub fn step_points(&self) -> &[f64] {
        &self.points
    }

    /// State dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }
}

/// A located zero of an event function.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Location of the zero crossing.
    pub s: f64,
    /// State there (from the dense output).
    pub u: Vec<f64>,
}

/// Work buffers of a DOP853 call (one allocation).
struct Work {
    k: Vec<f64>,
    y: Vec<f64>,
    ynew: Vec<f64>,
    tmp: Vec<f64>,
    rc: Vec<f64>,
}

impl Work {
    fn new(n: usize) -> Self {
        Self {
            k: vec![0.0; NSTAGE * n],
            y: vec![0.0; n],
            ynew: vec![0.0; n],
            tmp: vec![0.0; n],
            rc: vec![0.0; 8 * n],
        }
    }
}

impl Dop853 {
    /// Tolerances `rtol`, `atol`; automatic initial step, `max_steps = 100_000`, no dense output.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            h_init: None,
            max_steps: 100_000,
            dense: false,
        }
    }

    /// Sets whether the dense output is stored.
    pub fn with_dense(self, dense: bool) -> Self {
        Self { dense, ..self }
    }

    fn check(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(BvpError::InvalidInput {
                name,
                value,
                reason,
            })
        };
        if !(self.rtol >= 0.0 && self.rtol.is_finite()) {
            return bad("rtol", self.rtol, "must be finite and >= 0");
        }
        if !(self.atol >= 0.0 && self.atol.is_finite()) {
            return bad("atol", self.atol, "must be finite and >= 0");
        }
        if self.rtol + self.atol <= 0.0 {
            return bad(
                "rtol + atol",
                0.0,
                "at least one tolerance must be positive",
            );
        }
        if let Some(h) = self.h_init {
            if !(h.is_finite() && h != 0.0) {
                return bad("h_init", h, "must be finite and non-zero");
            }
        }
        if self.max_steps == 0 {
            return bad("max_steps", 0.0, "must be at least 1");
        }
        Ok(())
    }

    /// Integrates `u' = G(s, u)`, `u(s0) = u0` from `s0` to `s1` (either direction).
    ///
    /// # Errors
    /// `StepSizeUnderflow`, `TooManySteps`, `NonFinite` (the right-hand side returned NaN/inf at
    /// an accepted state), `InvalidInput` (bad tolerances/bounds, non-finite `u0`),
    /// `DimensionMismatch`.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
    ) -> Result<OdeSolution> {
        let (sol, _) = self.run(sys, s0, s1, u0, None::<fn(f64, &[f64]) -> f64>)?;
        Ok(sol)
    }

    /// Integrates until the first zero crossing of `event(s, u)` after `s0` (a sign change
    /// between the ends of an accepted step, or an exact zero at a step end), located to
    /// `|ds| <= 1e-14 * max(|s_a|, |s_b|, |h|)` by Brent's method on the dense output; or until
    /// `s1` if there is none. The returned solution ends at the event. A zero of `event` at
    /// `s0` itself is not an event.
    ///
    /// # Errors
    /// As [`Dop853::integrate`]; `NonFinite` if the event function returns NaN.
    pub fn integrate_until<S: OdeSystem + ?Sized, E: FnMut(f64, &[f64]) -> f64>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        event: E,
    ) -> Result<(OdeSolution, Option<Event>)> {
        self.run(sys, s0, s1, u0, Some(event))
    }

    /// Hairer's `HINIT`: initial step guess for order `iord = 8`.
    #[allow(clippy::too_many_arguments)]
    fn hinit<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        x: f64,
        y: &[f64],
        f0: &[f64],
        f1: &mut [f64],
        y1: &mut [f64],
        posneg: f64,
        hmax: f64,
    ) -> f64 {
        let n = y.len();
        let mut dnf = 0.0;
        let mut dny = 0.0;
        for i in 0..n {
            let sk = self.atol + self.rtol * y[i].abs();
            dnf += (f0[i] / sk).powi(2);
            dny += (y[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
            1e-6
        } else {
            (dny / dnf).sqrt() * 0.01
        };
        h = h.min(hmax) * posneg;
        for i in 0..n {
            y1[i] = y[i] + h * f0[i];
        }
        sys.rhs(x + h, y1, f1);
        let mut der2: f64 = 0.0;
        for i in 0..n {
            let sk = self.atol + self.rtol * y[i].abs();
            der2 += ((f1[i] - f0[i]) / sk).powi(2);
        }
        der2 = der2.sqrt() / h.abs();
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 || !der12.is_finite() {
            (1e-6f64).max(h.abs() * 1e-3)
        } else {
            (0.01 / der12).powf(1.0 / 8.0)
        };
        let h = (100.0 * h.abs()).min(h1).min(hmax);
        if h.is_finite() && h > 0.0 {
            h
        } else {
            hmax.min(1e-6)
        }
    }

    #[allow(clippy::too_many_lines)]
    fn run<S: OdeSystem + ?Sized, E: FnMut(f64, &[f64]) -> f64>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        mut event: Option<E>,
    ) -> Result<(OdeSolution, Option<Event>)> {
        self.check()?;
        check_span(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        let mut stats = IntegrationStats::default();
        let mut sol = OdeSolution {
            s_end: s0,
            u_end: u0.to_vec(),
            stats,
            dim: n,
            s_start: s0,
            u_start: if self.dense { u0.to_vec() } else { Vec::new() },
            points: Vec::new(),
            hs: Vec::new(),
            cont: Vec::new(),
            dense: self.dense,
        };
        if self.dense {
            sol.points.push(s0);
        }
        if s0 == s1 {
            return Ok((sol, None));
        }
        let need_cont = self.dense || event.is_some();
        let Work {
            mut k,
            mut y,
            mut ynew,
            mut tmp,
            mut rc,
        } = Work::new(n);
        y.copy_from_slice(u0);

        let uround = f64::EPSILON;
        let posneg = if s1 > s0 { 1.0 } else { -1.0 };
        let hmax = (s1 - s0).abs();
        let (safe, fac1, fac2, beta): (f64, f64, f64, f64) = (0.9, 0.333, 6.0, 0.0);
        let expo1 = 1.0 / 8.0 - beta * 0.2;
        let facc1 = 1.0 / fac1;
        let facc2 = 1.0 / fac2;
        let mut facold: f64 = 1e-4;

        let mut x = s0;
        sys.rhs(x, &y, &mut k[..n]);
        stats.rhs_evals += 1;
        if !all_finite(&k[..n]) {
            return Err(BvpError::NonFinite {
                what: "ODE right-hand side",
                s: x,
            });
        }
        let mut h = match self.h_init {
            Some(h0) => h0.abs().min(hmax) * posneg,
            None => {
                let (k0, rest) = k.split_at_mut(n);
                let hh = self.hinit(sys, x, &y, k0, &mut rest[..n], &mut tmp, posneg, hmax);
                stats.rhs_evals += 1;
                hh * posneg
            }
        };

        let mut g_old = 0.0;
        if let Some(ev) = event.as_mut() {
            g_old = ev(x, &y);
            if g_old.is_nan() {
                return Err(BvpError::NonFinite {
                    what: "event function",
                    s: x,
                });
            }
        }

        let mut reject = false;
        let mut last = false;
        let mut attempts = 0usize;
        let mut last_err_nonfinite = false;
        loop {
            if attempts >= self.max_steps {
                return Err(BvpError::TooManySteps {
                    max_steps: self.max_steps,
                    s: x,
                });
            }
            if 0.1 * h.abs() <= x.abs() * uround || h == 0.0 {
                if last_err_nonfinite {
                    return Err(BvpError::NonFinite {
                        what: "ODE right-hand side",
                        s: x,
                    });
                }
                return Err(BvpError::StepSizeUnderflow { s: x, h });
            }
            if (x + 1.01 * h - s1) * posneg > 0.0 {
                h = s1 - x;
                last = true;
            }
            attempts += 1;

            // ---- the 12 stages
            combo(&y, h, &k, [(0, A21)], &mut tmp);
            sys.rhs(x + C[1] * h, &tmp, &mut k[n..2 * n]);
            combo(&y, h, &k, [(0, A31), (1, A32)], &mut tmp);
            sys.rhs(x + C[2] * h, &tmp, &mut k[2 * n..3 * n]);
            combo(&y, h, &k, [(0, A41), (2, A43)], &mut tmp);
            sys.rhs(x + C[3] * h, &tmp, &mut k[3 * n..4 * n]);
            combo(&y, h, &k, [(0, A51), (2, A53), (3, A54)], &mut tmp);
            sys.rhs(x + C[4] * h, &tmp, &mut k[4 * n..5 * n]);
            combo(&y, h, &k, [(0, A61), (3, A64), (4, A65)], &mut tmp);
            sys.rhs(x + C[5] * h, &tmp, &mut k[5 * n..6 * n]);
            combo(
                &y,
                h,
                &k,
                [(0, A71), (3, A74), (4, A75), (5, A76)],
                &mut tmp,
            );
            sys.rhs(x + C[6] * h, &tmp, &mut k[6 * n..7 * n]);
            combo(
                &y,
                h,
                &k,
                [(0, A81), (3, A84), (4, A85), (5, A86), (6, A87)],
                &mut tmp,
            );
            sys.rhs(x + C[7] * h, &tmp, &mut k[7 * n..8 * n]);
            combo(
                &y,
                h,
                &k,
                [(0, A91), (3, A94), (4, A95), (5, A96), (6, A97), (7, A98)],
                &mut tmp,
            );
            sys.rhs(x + C[8] * h, &tmp, &mut k[8 * n..9 * n]);
            combo(
                &y,
                h,
                &k,
                [
                    (0, A101),
                    (3, A104),
                    (4, A105),
                    (5, A106),
                    (6, A107),
                    (7, A108),
                    (8, A109),
                ],
                &mut tmp,
            );
            sys.rhs(x + C[9] * h, &tmp, &mut k[9 * n..10 * n]);
            combo(
                &y,
                h,
                &k,
                [
                    (0, A111),
                    (3, A114),
                    (4, A115),
                    (5, A116),
                    (6, A117),
                    (7, A118),
                    (8, A119),
                    (9, A1110),
                ],
                &mut tmp,
            );
            sys.rhs(x + C[10] * h, &tmp, &mut k[10 * n..11 * n]);
            let xph = x + h;
            combo(
                &y,
                h,
                &k,
                [
                    (0, A121),
                    (3, A124),
                    (4, A125),
                    (5, A126),
                    (6, A127),
                    (7, A128),
                    (8, A129),
                    (9, A1210),
                    (10, A1211),
                ],
                &mut tmp,
            );
            sys.rhs(xph, &tmp, &mut k[11 * n..12 * n]);
            stats.rhs_evals += 11;

            // ---- 8th-order solution and error estimate
            let mut err = 0.0;
            let mut err2 = 0.0;
            for i in 0..n {
                let bsum = lin(
                    &k,
                    n,
                    i,
                    [
                        (0, B1),
                        (5, B6),
                        (6, B7),
                        (7, B8),
                        (8, B9),
                        (9, B10),
                        (10, B11),
                        (11, B12),
                    ],
                );
                ynew[i] = y[i] + h * bsum;
                let e3 = bsum - BHH1 * k[i] - BHH2 * k[8 * n + i] - BHH3 * k[11 * n + i];
                let e5 = lin(
                    &k,
                    n,
                    i,
                    [
                        (0, ER1),
                        (5, ER6),
                        (6, ER7),
                        (7, ER8),
                        (8, ER9),
                        (9, ER10),
                        (10, ER11),
                        (11, ER12),
                    ],
                );
                let sk = self.atol + self.rtol * y[i].abs().max(ynew[i].abs());
                err2 += (e3 / sk).powi(2);
                err += (e5 / sk).powi(2);
            }
            let mut deno = err + 0.01 * err2;
            if deno <= 0.0 {
                deno = 1.0;
            }
            let err = h.abs() * err * (1.0 / (n as f64 * deno)).sqrt();

            if !err.is_finite() {
                // A trial stage left the domain of G (or overflowed): retreat.
                last_err_nonfinite = true;
                reject = true;
                last = false;
                stats.rejected += 1;
                h *= fac1;
                continue;
            }
            last_err_nonfinite = false;

            let fac11 = err.powf(expo1);
            let fac = fac11 / facold.powf(beta);
            let fac = facc2.max(facc1.min(fac / safe));
            let mut hnew = h / fac;

            if err <= 1.0 {
                // ---- step accepted
                facold = err.max(1e-4);
                stats.steps += 1;
                // k13 = G(x + h, u_new): FSAL derivative
                sys.rhs(xph, &ynew, &mut k[12 * n..13 * n]);
                stats.rhs_evals += 1;
                if !all_finite(&k[12 * n..13 * n]) || !all_finite(&ynew) {
                    return Err(BvpError::NonFinite {
                        what: "ODE right-hand side",
                        s: xph,
                    });
                }
                if need_cont {
                    self.prepare_dense(sys, x, h, &y, &ynew, &mut k, &mut tmp, &mut rc);
                    stats.rhs_evals += 3;
                }

                // ---- event check
                if let Some(ev) = event.as_mut() {
                    let g_new = ev(xph, &ynew);
                    if g_new.is_nan() {
                        return Err(BvpError::NonFinite {
                            what: "event function",
                            s: xph,
                        });
                    }
                    let crossed = g_new == 0.0 || (g_old != 0.0 && (g_old < 0.0) != (g_new < 0.0));
                    if crossed {
                        let s_ev = if g_new == 0.0 {
                            xph
                        } else {
                            let scale = x.abs().max(xph.abs()).max(h.abs());
                            let opts = RootOptions {
                                xtol: 1e-14 * scale,
                                ftol: 0.0,
                                max_iter: 200,
                            };
                            let (a, b) = if posneg > 0.0 { (x, xph) } else { (xph, x) };
                            let rc_ref = &rc;
                            let buf = &mut tmp;
                            let root = brent(
                                |s: f64| -> Result<f64> {
                                    let theta = (s - x) / h;
                                    dense_eval(rc_ref, n, theta, buf);
                                    let g = ev(s, buf);
                                    if g.is_nan() {
                                        Err(BvpError::NonFinite {
                                            what: "event function",
                                            s,
                                        })
                                    } else {
                                        Ok(g)
                                    }
                                },
                                a,
                                b,
                                &opts,
                            )?;
                            root.x
                        };
                        let mut u_ev = vec![0.0; n];
                        if s_ev == xph {
                            u_ev.copy_from_slice(&ynew);
                        } else {
                            dense_eval(&rc, n, (s_ev - x) / h, &mut u_ev);
                        }
                        if self.dense {
                            sol.points.push(s_ev);
                            sol.hs.push(h);
                            sol.cont.extend_from_slice(&rc);
                        }
                        sol.s_end = s_ev;
                        sol.u_end.copy_from_slice(&u_ev);
                        sol.stats = stats;
                        return Ok((sol, Some(Event { s: s_ev, u: u_ev })));
                    }
                    g_old = g_new;
                }

                if self.dense {
                    sol.points.push(if last { s1 } else { xph });
                    sol.hs.push(h);
                    sol.cont.extend_from_slice(&rc);
                }
                // FSAL: k1 <- k13
                k.copy_within(12 * n..13 * n, 0);
                std::mem::swap(&mut y, &mut ynew);
                x = xph;
                if last {
                    break;
                }
                if hnew.abs() > hmax {
                    hnew = posneg * hmax;
                }
                if reject {
                    hnew = posneg * hnew.abs().min(h.abs());
                }
                reject = false;
            } else {
                // ---- step rejected
                hnew = h / facc1.min(fac11 / safe);
                reject = true;
                stats.rejected += 1;
                last = false;
            }
            h = hnew;
        }
        sol.s_end = s1;
        sol.u_end.copy_from_slice(&y);
        sol.stats = stats;
        Ok((sol, None))
    }

    /// Computes the 8 blocks of dense-output coefficients of the step `[x, x + h]` into `rc`
    /// (uses `k1..k13`, evaluates the extra stages `k14..k16`).
    #[allow(clippy::too_many_arguments)]
    fn prepare_dense<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        x: f64,
        h: f64,
        y: &[f64],
        ynew: &[f64],
        k: &mut [f64],
        tmp: &mut [f64],
        rc: &mut [f64],
    ) {
        let n = y.len();
        combo(
            y,
            h,
            k,
            [
                (0, A141),
                (6, A147),
                (7, A148),
                (8, A149),
                (9, A1410),
                (10, A1411),
                (11, A1412),
                (12, A1413),
            ],
            tmp,
        );
        sys.rhs(x + C14 * h, tmp, &mut k[13 * n..14 * n]);
        combo(
            y,
            h,
            k,
            [
                (0, A151),
                (5, A156),
                (6, A157),
                (7, A158),
                (10, A1511),
                (11, A1512),
                (12, A1513),
                (13, A1514),
            ],
            tmp,
        );
        sys.rhs(x + C15 * h, tmp, &mut k[14 * n..15 * n]);
        combo(
            y,
            h,
            k,
            [
                (0, A161),
                (5, A166),
                (6, A167),
                (7, A168),
                (8, A169),
                (12, A1613),
                (13, A1614),
                (14, A1615),
            ],
            tmp,
        );
        sys.rhs(x + C16 * h, tmp, &mut k[15 * n..16 * n]);
        for i in 0..n {
            let ydiff = ynew[i] - y[i];
            let bspl = h * k[i] - ydiff;
            rc[i] = y[i];
            rc[n + i] = ydiff;
            rc[2 * n + i] = bspl;
            rc[3 * n + i] = ydiff - h * k[12 * n + i] - bspl;
            rc[4 * n + i] = h * lin(
                k,
                n,
                i,
                [
                    (0, D41),
                    (5, D46),
                    (6, D47),
                    (7, D48),
                    (8, D49),
                    (9, D410),
                    (10, D411),
                    (11, D412),
                    (12, D413),
                    (13, D414),
                    (14, D415),
                    (15, D416),
                ],
            );
            rc[5 * n + i] = h * lin(
                k,
                n,
                i,
                [
                    (0, D51),
                    (5, D56),
                    (6, D57),
                    (7, D58),
                    (8, D59),
                    (9, D510),
                    (10, D511),
                    (11, D512),
                    (12, D513),
                    (13, D514),
                    (14, D515),
                    (15, D516),
                ],
            );
            rc[6 * n + i] = h * lin(
                k,
                n,
                i,
                [
                    (0, D61),
                    (5, D66),
                    (6, D67),
                    (7, D68),
                    (8, D69),
                    (9, D610),
                    (10, D611),
                    (11, D612),
                    (12, D613),
                    (13, D614),
                    (14, D615),
                    (15, D616),
                ],
            );
            rc[7 * n + i] = h * lin(
                k,
                n,
                i,
                [
                    (0, D71),
                    (5, D76),
                    (6, D77),
                    (7, D78),
                    (8, D79),
                    (9, D710),
                    (10, D711),
                    (11, D712),
                    (12, D713),
                    (13, D714),
                    (14, D715),
                    (15, D716),
                ],
            );
        }
    }
}
