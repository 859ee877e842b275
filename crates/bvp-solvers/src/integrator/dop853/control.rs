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

#[cfg(test)]
mod tests {
    use super::*;

    fn accepted(v: Verdict) -> f64 {
        match v {
            Verdict::Accept { h_next } => h_next,
            other => panic!("{other:?}"),
        }
    }

    /// Hairer's rule `h_new = h / max(1/6, min(1/0.333, err^(1/8) / 0.9))`: with
    /// `err = 2^-8` (`err^(1/8) = 1/2`) the step grows by `0.9 / 0.5 = 1.8`; a tiny error
    /// grows it by the cap 6, bounded by `hmax`; backwards the same with the sign.
    #[test]
    fn an_accepted_step_grows_by_hairers_factor() {
        let mut c = StepControl::new(10.0, 1.0);
        let h = accepted(c.judge(1.0 / 256.0, 0.1));
        assert!((h - 0.1 / (0.5 / 0.9)).abs() < 1e-16, "{h}");
        assert_eq!(accepted(c.judge(1e-40, 0.1)), 0.1 * 6.0);
        assert_eq!(accepted(c.judge(1e-40, 5.0)), 10.0);
        let mut back = StepControl::new(10.0, -1.0);
        assert_eq!(accepted(back.judge(1e-40, -0.1)), -0.1 * 6.0);
        assert_eq!(accepted(back.judge(1e-40, -5.0)), -10.0);
        // err = 1 is still accepted: the step shrinks by 0.9
        assert!((accepted(c.judge(1.0, 0.1)) - 0.09).abs() < 1e-16);
    }

    /// A rejected step retries with `h / min(1/0.333, err^(1/8) / 0.9)`, and the step after
    /// a rejection does not grow; a retreat divides by 3 (`fac1 = 0.333`) and counts as one.
    #[test]
    fn a_rejection_shrinks_the_step_and_stops_the_next_growth() {
        let mut c = StepControl::new(10.0, 1.0);
        // err = 2^8: err^(1/8) = 2, h / (2 / 0.9) = 0.45 h
        match c.judge(256.0, 0.1) {
            Verdict::Reject { h_retry } => assert!((h_retry - 0.045).abs() < 1e-16, "{h_retry}"),
            other => panic!("{other:?}"),
        }
        assert!(c.reject);
        // a huge error: the retry is capped at h * 0.333
        match c.judge(1e30, 0.1) {
            Verdict::Reject { h_retry } => assert!((h_retry - 0.0333).abs() < 1e-16),
            other => panic!("{other:?}"),
        }
        // accepted right after: no growth beyond the step taken
        assert_eq!(accepted(c.judge(1e-40, 0.0333)), 0.0333);
        assert!(!c.reject);
        assert_eq!(accepted(c.judge(1e-40, 0.0333)), 0.0333 * 6.0);
        assert_eq!(c.retreat(0.3), 0.3 * 0.333);
        assert_eq!(accepted(c.judge(1e-40, 0.0999)), 0.0999);
    }
}
