//! The discrete system: the problem with its singular term, the collocation residual of
//! the 3-point Lobatto IIIA scheme (eq. (2) of the module doc), its ABD Jacobian, and the
//! relative residual estimate that controls the mesh.

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

use super::abd::AbdMatrix;
use super::hermite::hermite;
use super::problem::{fd_step, BvpProblem};
use super::types::BvpStats;

/// The singular term `S y / (x - a)`: `S`, `D = (I - S)^+` (the limit `f(a) = D f(a, y(a))`
/// at `x = a`) and `B = I - S^+ S` (the projector that enforces `S y(a) = 0`), row-major.
pub struct Singular {
    /// `S`.
    pub s: Vec<f64>,
    /// `D = (I - S)^+`.
    pub d: Vec<f64>,
    /// `B = I - S^+ S`.
    pub b: Vec<f64>,
}

/// The problem wrapped with its sizes, singular term and evaluation counters.
pub struct System<'a, P: ?Sized> {
    /// The user's problem.
    pub prob: &'a P,
    /// States.
    pub n: usize,
    /// Unknown parameters.
    pub k: usize,
    /// The left end (where the singular term is singular).
    pub a: f64,
    /// The singular term, if any.
    pub sing: Option<Singular>,
    /// Evaluation counters.
    pub stats: BvpStats,
    buf: Vec<f64>,
    buf2: Vec<f64>,
    /// Scratch of [`Self::jacobian`] kept across Jacobians (no allocation per Newton step):
    /// `df/dy`, `df/dp` at the nodes and at one midpoint, and the perturbed point.
    pub jac_work: JacWork,
    /// Whether the problem's `rhs_jacobian` answered (`None` before the first call).
    analytic: Option<bool>,
}

/// The buffers of [`System::jacobian`] and [`System::fun_jac`] (resized, never cleared).
#[derive(Debug, Default)]
pub struct JacWork {
    jn: Vec<f64>,
    qn: Vec<f64>,
    jm: Vec<f64>,
    qm: Vec<f64>,
    yy: Vec<f64>,
    pp: Vec<f64>,
}

fn matvec(a: &[f64], x: &[f64], out: &mut [f64]) {
    let n = x.len();
    for (r, o) in out.iter_mut().enumerate() {
        *o = a[r * n..(r + 1) * n]
            .iter()
            .zip(x)
            .map(|(u, v)| u * v)
            .sum();
    }
}

/// The outputs of [`System::collocation`], each flat with `n` values per point.
#[derive(Debug, Default)]
pub struct Colloc {
    /// `f` at the nodes (`m * n`).
    pub f: Vec<f64>,
    /// The Hermite midpoints `y_{i+1/2}` [eq. (1)], `(m-1) * n`.
    pub y_mid: Vec<f64>,
    /// `f` at the midpoints.
    pub f_mid: Vec<f64>,
    /// The collocation residuals [eq. (2)], `(m-1) * n`.
    pub res: Vec<f64>,
}

impl JacWork {
    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [&self.jn, &self.qn, &self.jm, &self.qm, &self.yy, &self.pp];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
    }
}

impl Colloc {
    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [&self.f, &self.y_mid, &self.f_mid, &self.res];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
    }
}

impl<'a, P: BvpProblem + ?Sized> System<'a, P> {
    /// The system of `prob` with `n` states, `k` parameters, left end `a`.
    pub fn new(prob: &'a P, n: usize, k: usize, a: f64, sing: Option<Singular>) -> Self {
        Self {
            prob,
            n,
            k,
            a,
            sing,
            stats: BvpStats::default(),
            buf: vec![0.0; n + k],
            buf2: vec![0.0; 2 * (n + k)],
            jac_work: JacWork::default(),
            analytic: None,
        }
    }

    /// `f(x, y, p)` with the singular term: `S y / (x - a) + f` for `x > a`, `D f` at `x = a`.
    pub fn fun(&mut self, x: f64, y: &[f64], p: &[f64], out: &mut [f64]) {
        self.stats.rhs_evaluations += 1;
        self.prob.rhs(x, y, p, out);
        if let Some(sg) = &self.sing {
            let n = self.n;
            if x == self.a {
                let mut t = vec![0.0; n];
                matvec(&sg.d, out, &mut t);
                out.copy_from_slice(&t);
            } else {
                let inv = 1.0 / (x - self.a);
                for r in 0..n {
                    let s: f64 = (0..n).map(|c| sg.s[r * n + c] * y[c]).sum();
                    out[r] += s * inv;
                }
            }
        }
    }

    /// `df/dy` (`n x n`) and `df/dp` (`n x k`) of the wrapped `f` at `(x, y, p)`, `f0` its
    /// value there: analytic if the problem has it (then wrapped like [`Self::fun`]), else
    /// forward differences with scipy's step.
    pub fn fun_jac(
        &mut self,
        x: f64,
        y: &[f64],
        p: &[f64],
        f0: &[f64],
        dfdy: &mut [f64],
        dfdp: &mut [f64],
    ) {
        let (n, k) = (self.n, self.k);
        // zeroed for an analytic Jacobian that writes its non-zero entries only
        if self.analytic != Some(false) {
            dfdy.fill(0.0);
            dfdp.fill(0.0);
        }
        let analytic = self.prob.rhs_jacobian(x, y, p, dfdy, dfdp);
        self.analytic = Some(analytic);
        if analytic {
            if let Some(sg) = &self.sing {
                if x == self.a {
                    let mut t = vec![0.0; n * n];
                    for r in 0..n {
                        for c in 0..n {
                            t[r * n + c] = (0..n).map(|q| sg.d[r * n + q] * dfdy[q * n + c]).sum();
                        }
                    }
                    dfdy.copy_from_slice(&t);
                    let mut t = vec![0.0; n * k];
                    for r in 0..n {
                        for c in 0..k {
                            t[r * k + c] = (0..n).map(|q| sg.d[r * n + q] * dfdp[q * k + c]).sum();
                        }
                    }
                    dfdp.copy_from_slice(&t);
                } else {
                    let inv = 1.0 / (x - self.a);
                    for (d, s) in dfdy.iter_mut().zip(&sg.s) {
                        *d += s * inv;
                    }
                }
            }
            return;
        }
        self.stats.jacobian_by_differences = true;
        let mut yy = std::mem::take(&mut self.jac_work.yy);
        yy.clear();
        yy.extend_from_slice(y);
        let mut fnew = std::mem::take(&mut self.buf);
        fnew.resize(n, 0.0);
        for c in 0..n {
            let hs = fd_step(y[c]);
            yy[c] = y[c] + hs;
            let hi = yy[c] - y[c];
            self.fun(x, &yy, p, &mut fnew);
            self.stats.rhs_evaluations_for_jacobian += 1;
            for r in 0..n {
                dfdy[r * n + c] = (fnew[r] - f0[r]) / hi;
            }
            yy[c] = y[c];
        }
        if k > 0 {
            let mut pp = std::mem::take(&mut self.jac_work.pp);
            pp.clear();
            pp.extend_from_slice(p);
            for c in 0..k {
                let hs = fd_step(p[c]);
                pp[c] = p[c] + hs;
                let hi = pp[c] - p[c];
                self.fun(x, y, &pp, &mut fnew);
                self.stats.rhs_evaluations_for_jacobian += 1;
                for r in 0..n {
                    dfdp[r * k + c] = (fnew[r] - f0[r]) / hi;
                }
                pp[c] = p[c];
            }
            self.jac_work.pp = pp;
        }
        self.jac_work.yy = yy;
        self.buf = fnew;
    }

    /// The boundary residuals.
    pub fn bc(&mut self, ya: &[f64], yb: &[f64], p: &[f64], out: &mut [f64]) {
        self.stats.bc_evaluations += 1;
        self.prob.bc(ya, yb, p, out);
    }

    /// The boundary Jacobians into `mat.ba`, `mat.bb`, `mat.bp`; `r0` the residual at
    /// `(ya, yb, p)`.
    pub fn bc_jac(&mut self, ya: &[f64], yb: &[f64], p: &[f64], r0: &[f64], mat: &mut AbdMatrix) {
        let (n, k) = (self.n, self.k);
        mat.ba.fill(0.0);
        mat.bb.fill(0.0);
        mat.bp.fill(0.0);
        if self
            .prob
            .bc_jacobian(ya, yb, p, &mut mat.ba, &mut mat.bb, &mut mat.bp)
        {
            return;
        }
        let nr = n + k;
        let mut rnew = std::mem::take(&mut self.buf2);
        rnew.resize(nr, 0.0);
        let mut v = ya.to_vec();
        for c in 0..n {
            v[c] = ya[c] + fd_step(ya[c]);
            let hi = v[c] - ya[c];
            self.bc(&v, yb, p, &mut rnew);
            for r in 0..nr {
                mat.ba[r * n + c] = (rnew[r] - r0[r]) / hi;
            }
            v[c] = ya[c];
        }
        let mut v = yb.to_vec();
        for c in 0..n {
            v[c] = yb[c] + fd_step(yb[c]);
            let hi = v[c] - yb[c];
            self.bc(ya, &v, p, &mut rnew);
            for r in 0..nr {
                mat.bb[r * n + c] = (rnew[r] - r0[r]) / hi;
            }
            v[c] = yb[c];
        }
        let mut v = p.to_vec();
        for c in 0..k {
            v[c] = p[c] + fd_step(p[c]);
            let hi = v[c] - p[c];
            self.bc(ya, yb, &v, &mut rnew);
            for r in 0..nr {
                mat.bp[r * k + c] = (rnew[r] - r0[r]) / hi;
            }
            v[c] = p[c];
        }
        self.buf2 = rnew;
    }

    /// The collocation residuals [eq. (2)]: `f` at the nodes, the Hermite midpoints
    /// `y_{i+1/2} = (y_i + y_{i+1})/2 - h_i (f_{i+1} - f_i)/8` [eq. (1)], `f` there, and
    /// `r_i = y_{i+1} - y_i - h_i (f_i + 4 f_{i+1/2} + f_{i+1}) / 6` (Simpson's rule, the
    /// 3-point Lobatto IIIA method).
    pub fn collocation(&mut self, x: &[f64], y: &[f64], p: &[f64], out: &mut Colloc) {
        let n = self.n;
        let m = x.len();
        out.f.resize(m * n, 0.0);
        out.y_mid.resize((m - 1) * n, 0.0);
        out.f_mid.resize((m - 1) * n, 0.0);
        out.res.resize((m - 1) * n, 0.0);
        for i in 0..m {
            let (yi, fi) = (&y[i * n..(i + 1) * n], &mut out.f[i * n..(i + 1) * n]);
            self.fun(x[i], yi, p, fi);
        }
        for i in 0..m - 1 {
            let h = x[i + 1] - x[i];
            for c in 0..n {
                let (y0, y1) = (y[i * n + c], y[(i + 1) * n + c]);
                let (f0, f1) = (out.f[i * n + c], out.f[(i + 1) * n + c]);
                out.y_mid[i * n + c] = 0.5 * (y0 + y1) - 0.125 * h * (f1 - f0);
            }
            let xm = x[i] + 0.5 * h;
            let (ym, fm) = (
                &out.y_mid[i * n..(i + 1) * n],
                &mut out.f_mid[i * n..(i + 1) * n],
            );
            self.fun(xm, ym, p, fm);
            for c in 0..n {
                let (y0, y1) = (y[i * n + c], y[(i + 1) * n + c]);
                let (f0, f1) = (out.f[i * n + c], out.f[(i + 1) * n + c]);
                out.res[i * n + c] = y1 - y0 - h / 6.0 * (f0 + f1 + 4.0 * out.f_mid[i * n + c]);
            }
        }
    }

    /// The ABD Jacobian of [eq. (2)] with respect to `(y_0, ..., y_{m-1}, p)`, with `J = df/dy`
    /// and `Q = df/dp` at the nodes (`0`, `1`) and the midpoint (`m`):
    /// `A = -I - h/6 (J_0 + 2 J_m) - h^2/12 J_m J_0`,
    /// `C = I - h/6 (J_1 + 2 J_m) + h^2/12 J_m J_1`,
    /// `P = -h/6 (Q_0 + Q_1 + 4 Q_m) + h^2/12 J_m (Q_1 - Q_0)`.
    pub fn jacobian(
        &mut self,
        x: &[f64],
        y: &[f64],
        p: &[f64],
        col: &Colloc,
        bc0: &[f64],
        mat: &mut AbdMatrix,
    ) {
        let (n, k) = (self.n, self.k);
        let m = x.len();
        mat.resize(n, k, m);
        self.stats.jacobian_evaluations += 1;
        let nn = n * n;
        let nk = n * k;
        let mut jn = std::mem::take(&mut self.jac_work.jn);
        let mut qn = std::mem::take(&mut self.jac_work.qn);
        let mut jm = std::mem::take(&mut self.jac_work.jm);
        let mut qm = std::mem::take(&mut self.jac_work.qm);
        // written by `fun_jac` before they are read: resized, not cleared
        jn.resize(m * nn, 0.0);
        qn.resize(m * nk, 0.0);
        jm.resize(nn, 0.0);
        qm.resize(nk, 0.0);
        for i in 0..m {
            let (jy, jp) = (&mut jn[i * nn..(i + 1) * nn], &mut qn[i * nk..(i + 1) * nk]);
            self.fun_jac(
                x[i],
                &y[i * n..(i + 1) * n],
                p,
                &col.f[i * n..(i + 1) * n],
                jy,
                jp,
            );
        }
        for i in 0..m - 1 {
            let h = x[i + 1] - x[i];
            let xm = x[i] + 0.5 * h;
            self.fun_jac(
                xm,
                &col.y_mid[i * n..(i + 1) * n],
                p,
                &col.f_mid[i * n..(i + 1) * n],
                &mut jm,
                &mut qm,
            );
            let j0 = &jn[i * nn..(i + 1) * nn];
            let j1 = &jn[(i + 1) * nn..(i + 2) * nn];
            let a = &mut mat.a[i * nn..(i + 1) * nn];
            let c = &mut mat.c[i * nn..(i + 1) * nn];
            let (h6, h12) = (h / 6.0, h * h / 12.0);
            // the products J_m J_0, J_m J_1 row by row (skipping zeros of the often sparse J_m)
            for r in 0..n {
                let arow = &mut a[r * n..(r + 1) * n];
                let crow = &mut c[r * n..(r + 1) * n];
                for q in 0..n {
                    let jmq = 2.0 * jm[r * n + q];
                    arow[q] = -h6 * (j0[r * n + q] + jmq);
                    crow[q] = -h6 * (j1[r * n + q] + jmq);
                }
                arow[r] -= 1.0;
                crow[r] += 1.0;
                for t in 0..n {
                    let v = jm[r * n + t];
                    if v == 0.0 {
                        continue;
                    }
                    let (w0, w1) = (&j0[t * n..(t + 1) * n], &j1[t * n..(t + 1) * n]);
                    for q in 0..n {
                        arow[q] -= h12 * v * w0[q];
                        crow[q] += h12 * v * w1[q];
                    }
                }
            }
            if k > 0 {
                let q0 = &qn[i * nk..(i + 1) * nk];
                let q1 = &qn[(i + 1) * nk..(i + 2) * nk];
                let pb = &mut mat.p[i * nk..(i + 1) * nk];
                for r in 0..n {
                    for q in 0..k {
                        let s: f64 = (0..n)
                            .map(|t| jm[r * n + t] * (q1[t * k + q] - q0[t * k + q]))
                            .sum();
                        pb[r * k + q] =
                            -h6 * (q0[r * k + q] + q1[r * k + q] + 4.0 * qm[r * k + q]) + h12 * s;
                    }
                }
            }
        }
        self.jac_work.jn = jn;
        self.jac_work.qn = qn;
        self.jac_work.jm = jm;
        self.jac_work.qm = qm;
        let ya = &y[..n];
        let yb = &y[(m - 1) * n..];
        self.bc_jac(ya, yb, p, bc0, mat);
    }

    /// The relative residual of each interval (scipy's `estimate_rms_residuals`): the RMS
    /// over the interval of `|y_H' - f(x, y_H)| / (1 + |f|)`, `y_H` the Hermite interpolant,
    /// by 5-point Lobatto quadrature (the ends vanish by collocation; the midpoint value is
    /// `1.5 r_i / h_i`): `sqrt((32/45 r_mid^2 + 49/90 (r_1^2 + r_2^2)) / 2)` at
    /// `x_mid +- h/2 sqrt(3/7)`.
    pub fn rms_residuals(&mut self, x: &[f64], y: &[f64], p: &[f64], col: &Colloc) -> Vec<f64> {
        let n = self.n;
        let m = x.len();
        let mut out = vec![0.0; m - 1];
        let mut yv = vec![0.0; n];
        let mut dv = vec![0.0; n];
        let mut fv = vec![0.0; n];
        let w = 0.5 * (3.0f64 / 7.0).sqrt();
        for i in 0..m - 1 {
            let h = x[i + 1] - x[i];
            let xm = x[i] + 0.5 * h;
            let mut rm = 0.0;
            for c in 0..n {
                let r = 1.5 * col.res[i * n + c] / h / (1.0 + col.f_mid[i * n + c].abs());
                rm += r * r;
            }
            let mut r12 = 0.0;
            for t in [xm + w * h, xm - w * h] {
                hermite(
                    x[i],
                    h,
                    &y[i * n..(i + 1) * n],
                    &y[(i + 1) * n..(i + 2) * n],
                    &col.f[i * n..(i + 1) * n],
                    &col.f[(i + 1) * n..(i + 2) * n],
                    t,
                    &mut yv,
                    &mut dv,
                );
                self.fun(t, &yv, p, &mut fv);
                for c in 0..n {
                    let r = (dv[c] - fv[c]) / (1.0 + fv[c].abs());
                    r12 += r * r;
                }
            }
            out[i] = (0.5 * (32.0 / 45.0 * rm + 49.0 / 90.0 * r12)).sqrt();
        }
        out
    }
}
