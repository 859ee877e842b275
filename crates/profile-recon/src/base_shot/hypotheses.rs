//! The phase hypotheses of one row and the choice among them: a [`Hypothesis`] per candidate
//! contact (phase A at the tip, each phase-B root), the [`RowEval`] that holds them all, and
//! the rules that pick one at a noise level and measure how ambiguous the row is.

use super::context::K_SIGMA;
use contact_sim::Phase;

/// One phase hypothesis of a row.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hypothesis {
    pub phase: Phase,
    pub s1: f64,
    pub x: f64,
    pub y: f64,
    pub f: f64,
    pub psi: f64,
    /// Reported residual (A: |m(1)|, B: |phi - psi|).
    pub residual: f64,
    /// Residual over its noise sensitivity at unit relative noise.
    pub z: f64,
    /// Standard deviation of the point at unit relative noise.
    pub sigma_unit: f64,
    /// Square-root part of the point's error (a double root: noise `dm` in the moment moves
    /// it by `sqrt(2 dm / |m''|)`), at unit relative noise; 0 for simple roots and phase A.
    pub sigma_sqrt: f64,
    /// Signed consistency residual `r` (A: `m(1)`; B: `Q sin phi - P cos phi` at `s1`; 0 for
    /// the double root of a release) and its derivatives with respect to `(Ax, Ay, MA, phi0)`.
    pub r: f64,
    /// `dr / d(Ax, Ay, MA, phi0)` (zero without the Jacobian).
    pub dr: [f64; 4],
    /// Length of the linear projection's move of the point (see
    /// [`evaluate`](super::evaluate)).
    pub shift: f64,
}

impl Hypothesis {
    /// Error estimate (one standard deviation) of the point at relative noise `level`.
    pub fn sigma(&self, level: f64) -> f64 {
        level * self.sigma_unit + level.sqrt() * self.sigma_sqrt
    }

    /// Among `hyps`, the hypothesis of `self`'s phase and kind (simple root or double root)
    /// closest to it in `s1`: the same hypothesis after the row or the flow moved a little.
    pub fn nearest_in<'a>(&self, hyps: &'a [Hypothesis]) -> Option<&'a Hypothesis> {
        hyps.iter()
            .filter(|c| c.phase == self.phase && (c.sigma_sqrt == 0.0) == (self.sigma_sqrt == 0.0))
            .min_by(|a, b| (a.s1 - self.s1).abs().total_cmp(&(b.s1 - self.s1).abs()))
    }
}

/// Everything the identification and the reconstruction need of one row under one flow.
#[derive(Clone, Debug)]
pub(crate) struct RowEval {
    /// Phase-A contact force `f` of [6.8, 6.9] at `s1 = 1` over its sensitivity (pre-contact
    /// rows: within the noise of 0).
    pub f_z: f64,
    /// `|m(1)|` (the free-whisker check when `f = 0`), NaN if the integration stopped early.
    pub m1: f64,
    /// Tip state `(x(1) - x0, y(1), phi(1))` (the free tip for a pre-contact row).
    pub tip: (f64, f64, f64),
    /// All hypotheses (A first if the integration reached `s = 1`).
    pub hyps: Vec<Hypothesis>,
    /// For the phase-A hypothesis: for arcs `delta` back from the tip
    /// ([`TIP_GRID`](super::TIP_GRID) of them, geometric from 1e-5 to 0.5), the relative noise
    /// level at which a phase-B contact at `1 - delta` fits the row as well
    /// ([`RowEval::tip_ambiguity`]); empty without one.
    pub tip_levels: Vec<(f64, f64)>,
    /// Integrations spent.
    pub evaluations: usize,
}

impl RowEval {
    /// The chosen hypothesis at relative noise `level`: among the hypotheses consistent
    /// within [`K_SIGMA`] standard deviations, the best determined one (smallest error
    /// estimate: near a phase switch, or as `f -> 0`, several fit and their points agree to
    /// within their error estimates); if consistent hypotheses disagree beyond their error
    /// estimates, the most likely one (smallest `z`), whose error estimate then covers the
    /// others ([`RowEval::ambiguity`]); without any consistent one, the smallest `z`.
    pub fn chosen(&self, level: f64) -> Option<&Hypothesis> {
        let consistent: Vec<&Hypothesis> = self
            .hyps
            .iter()
            .filter(|h| h.z <= K_SIGMA * level)
            .collect();
        let by_z = |a: &&Hypothesis, b: &&Hypothesis| a.z.total_cmp(&b.z);
        let Some(best) = consistent
            .iter()
            .copied()
            .min_by(|a, b| a.sigma(level).total_cmp(&b.sigma(level)))
        else {
            return self.hyps.iter().min_by(by_z);
        };
        let agree = consistent.iter().all(|c| {
            (c.x - best.x).hypot(c.y - best.y) <= K_SIGMA * (best.sigma(level) + c.sigma(level))
        });
        if agree {
            Some(best)
        } else {
            consistent.into_iter().min_by(by_z)
        }
    }

    /// The phase-A hypothesis at relative noise `level`: how far back from the tip a phase-B
    /// contact fits the same row, the largest arc `delta` at which both phase-B conditions,
    /// `m(1 - delta) = 0` and `g = f sin(phi - psi) = 0` there, hold within 3 standard
    /// deviations (those of `m(1)` and `g(1)`). Under noise a small tangential contact force
    /// short of the tip and a tip contact can give the same observables; the point is only
    /// known to within that arc (0 for an exact log, or when no such contact fits).
    pub fn tip_ambiguity(&self, level: f64) -> f64 {
        // look-alikes within 3 standard deviations (a 6-sigma one is not a likely truth)
        self.tip_levels
            .iter()
            .filter(|(_, need)| *need * K_SIGMA <= 3.0 * level)
            .map(|(d, _)| *d)
            .fold(0.0, f64::max)
    }

    /// The other hypotheses consistent at `level` than `b`.
    fn others<'a>(&'a self, b: &'a Hypothesis, level: f64) -> impl Iterator<Item = &'a Hypothesis> {
        self.hyps
            .iter()
            .filter(move |h| !std::ptr::eq(*h, b) && h.z <= K_SIGMA * level)
    }

    /// The largest distance from `b`'s point to the point of another hypothesis consistent at
    /// `level` (0 if none): a row that several phases fit is only known to within that.
    pub fn ambiguity(&self, b: &Hypothesis, level: f64) -> f64 {
        self.others(b, level)
            .map(|h| (h.x - b.x).hypot(h.y - b.y))
            .fold(0.0, f64::max)
    }

    /// How many other hypotheses than `b` are consistent at `level`.
    pub fn alternatives(&self, b: &Hypothesis, level: f64) -> usize {
        self.others(b, level).count()
    }

    /// The smallest `z` (infinite without hypotheses).
    pub fn best_z(&self) -> f64 {
        self.hyps.iter().map(|h| h.z).fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A hypothesis at `(x, 0)` with the given `z` and unit deviation.
    pub(crate) fn hyp(phase: Phase, s1: f64, x: f64, z: f64, sigma_unit: f64) -> Hypothesis {
        Hypothesis {
            phase,
            s1,
            x,
            y: 0.0,
            f: 1.0,
            psi: 0.0,
            residual: z * 1e-3,
            z,
            sigma_unit,
            sigma_sqrt: 0.0,
            r: 0.0,
            dr: [0.0; 4],
            shift: 0.0,
        }
    }

    pub(crate) fn eval_of(hyps: Vec<Hypothesis>) -> RowEval {
        RowEval {
            f_z: 1.0,
            m1: 0.0,
            tip: (0.0, 0.0, 0.0),
            hyps,
            tip_levels: Vec::new(),
            evaluations: 1,
        }
    }

    #[test]
    fn sigma_adds_the_linear_and_the_square_root_parts() {
        let h = Hypothesis {
            sigma_sqrt: 3.0,
            ..hyp(Phase::B, 0.5, 0.0, 0.0, 2.0)
        };
        // 1e-4 * 2 + sqrt(1e-4) * 3
        assert!((h.sigma(1e-4) - 0.0302).abs() < 1e-15);
    }

    /// Phase A at `x = 0.5` (`z = 1e-3`, unit deviation) and phase B at `(s1, x)` (`z = 4e-3`,
    /// deviation 0.5).
    pub(crate) fn a_and_b(s1: f64, x: f64) -> RowEval {
        eval_of(vec![
            hyp(Phase::A, 1.0, 0.5, 1e-3, 1.0),
            hyp(Phase::B, s1, x, 4e-3, 0.5),
        ])
    }

    #[test]
    fn agreeing_consistent_hypotheses_give_the_best_determined_one() {
        // both consistent at level 1e-3 (z <= 6e-3), points 1e-4 apart, well within
        // 6 (sigma_a + sigma_b) = 6 (1e-3 + 5e-4)
        let e = a_and_b(0.9, 0.5001);
        let c = e.chosen(1e-3).unwrap();
        assert_eq!(c.phase, Phase::B);
        assert_eq!(e.alternatives(c, 1e-3), 1);
        assert!((e.ambiguity(c, 1e-3) - 1e-4).abs() < 1e-12);
    }

    #[test]
    fn disagreeing_consistent_hypotheses_give_the_most_likely_one() {
        // 0.3 apart, far beyond the error estimates: the smaller z wins and the other
        // one's distance is the ambiguity
        let e = a_and_b(0.7, 0.8);
        let c = e.chosen(1e-3).unwrap();
        assert_eq!(c.phase, Phase::A);
        assert!((e.ambiguity(c, 1e-3) - 0.3).abs() < 1e-12);
        // at a lower level only A is consistent (z <= 6e-4 is false for both): smallest z
        let c = e.chosen(1e-4).unwrap();
        assert_eq!(c.phase, Phase::A);
        assert_eq!(e.alternatives(c, 1e-4), 0);
        assert_eq!(e.ambiguity(c, 1e-4), 0.0);
        assert_eq!(e.best_z(), 1e-3);
        assert!(eval_of(Vec::new()).chosen(1.0).is_none());
        assert_eq!(eval_of(Vec::new()).best_z(), f64::INFINITY);
    }

    #[test]
    fn tip_ambiguity_is_the_largest_arc_within_three_deviations() {
        let mut e = eval_of(vec![hyp(Phase::A, 1.0, 0.5, 0.0, 1.0)]);
        // needed levels: 6 * need <= 3 * level, i.e. need <= level / 2
        e.tip_levels = vec![
            (1e-5, 1e-9),
            (1e-3, 4e-7),
            (1e-1, 6e-7),
            (0.5, f64::INFINITY),
        ];
        assert_eq!(e.tip_ambiguity(1e-6), 1e-3);
        assert_eq!(e.tip_ambiguity(1e-8), 1e-5);
        assert_eq!(e.tip_ambiguity(1e-10), 0.0);
    }

    #[test]
    fn nearest_keeps_phase_and_kind() {
        let b = hyp(Phase::B, 0.5, 0.0, 0.0, 1.0);
        let double = Hypothesis {
            sigma_sqrt: 1.0,
            ..hyp(Phase::B, 0.51, 0.0, 0.0, 1.0)
        };
        let hyps = vec![
            hyp(Phase::A, 1.0, 0.0, 0.0, 1.0),
            double,
            hyp(Phase::B, 0.45, 0.0, 0.0, 1.0),
            hyp(Phase::B, 0.8, 0.0, 0.0, 1.0),
        ];
        assert_eq!(b.nearest_in(&hyps).unwrap().s1, 0.45);
        assert_eq!(double.nearest_in(&hyps).unwrap().s1, 0.51);
    }
}
