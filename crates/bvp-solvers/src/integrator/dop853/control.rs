//! Step-size control of DOP853 (Hairer's controller): the new step
//! `h / max(1/6, min(3, err^(1/8) / 0.9))`, no increase right after a rejection, and a
//! retreat by `0.333` when a trial stage left the domain of the right-hand side.

/// What the controller decides for a step with error norm `err`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Verdict {
    /// Keep the step; continue with `h_next`.
    Accept {
        /// The next step.
        h_next: f64,
    },
    /// Redo the step with `h_retry`.
    Reject {
        /// The smaller step.
        h_retry: f64,
    },
}

/// The controller's state.
#[derive(Clone, Copy, Debug)]
pub(super) struct StepControl {
    safe: f64,
    fac1: f64,
    beta: f64,
    expo1: f64,
    facc1: f64,
    facc2: f64,
    facold: f64,
    /// Whether the last attempt was rejected.
    pub(super) reject: bool,
    hmax: f64,
    posneg: f64,
}

impl StepControl {
    /// Hairer's defaults: safety 0.9, step ratio in [1/3, 6] (`fac1 = 0.333`, `fac2 = 6`),
    /// no PI part (`beta = 0`); `hmax` bounds the step, `posneg` is the direction.
    pub(super) fn new(hmax: f64, posneg: f64) -> Self {
        let (safe, fac1, fac2, beta): (f64, f64, f64, f64) = (0.9, 0.333, 6.0, 0.0);
        StepControl {
            safe,
            fac1,
            beta,
            expo1: 1.0 / 8.0 - beta * 0.2,
            facc1: 1.0 / fac1,
            facc2: 1.0 / fac2,
            facold: 1e-4,
            reject: false,
            hmax,
            posneg,
        }
    }

    /// A trial stage produced a non-finite value: retreat.
    pub(super) fn retreat(&mut self, h: f64) -> f64 {
        self.reject = true;
        h * self.fac1
    }

    /// Judges a step of size `h` with the (finite) error norm `err`.
    pub(super) fn judge(&mut self, err: f64, h: f64) -> Verdict {
        // err^(1/8) by three square roots, and no PI factor when beta = 0 (Hairer's default):
        // two `powf` calls were ~3 % of a short integration
        let fac11 = if self.beta == 0.0 {
            err.sqrt().sqrt().sqrt()
        } else {
            err.powf(self.expo1)
        };
        let fac = if self.beta == 0.0 {
            fac11
        } else {
            fac11 / self.facold.powf(self.beta)
        };
        let fac = self.facc2.max(self.facc1.min(fac / self.safe));
        let mut hnew = h / fac;
        if err <= 1.0 {
            self.facold = err.max(1e-4);
            if hnew.abs() > self.hmax {
                hnew = self.posneg * self.hmax;
            }
            if self.reject {
                hnew = self.posneg * hnew.abs().min(h.abs());
            }
            self.reject = false;
            Verdict::Accept { h_next: hnew }
        } else {
            self.reject = true;
            Verdict::Reject {
                h_retry: h / self.facc1.min(fac11 / self.safe),
            }
        }
    }
}
