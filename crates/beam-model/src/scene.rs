//! A scene: one whisker under one set of loads.

use crate::balance::Reactions;
use crate::error::Result;
use crate::loads::Loads;
use crate::whisker::Whisker;
use serde::{Deserialize, Serialize};

/// A whisker with its loads: everything the forward problem [3.25] needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Geometry and support.
    pub whisker: Whisker,
    /// Loads.
    pub loads: Loads,
}

impl Scene {
    /// A scene from its parts (not yet validated).
    pub fn new(whisker: Whisker, loads: Loads) -> Self {
        Scene { whisker, loads }
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        self.whisker.validate()?;
        self.loads.validate()
    }

    /// The same scene with the load angles beta and alpha reduced to `[-pi, pi]` (when outside) by
    /// `atan2(sin, cos)` (the reduction of `sin`/`cos` is exact, so a huge angle keeps its
    /// meaning; `beta + phi` would otherwise lose `phi` to rounding).
    pub fn normalised(&self) -> Scene {
        let reduce = |a: f64| {
            if a.abs() <= std::f64::consts::PI {
                return a;
            }
            let (s, c) = a.sin_cos();
            s.atan2(c)
        };
        let mut out = *self;
        out.loads.tip.beta = reduce(self.loads.tip.beta);
        out.loads.fluid.alpha = reduce(self.loads.fluid.alpha);
        out
    }

    /// Base reactions (support on whisker) for a known tip angle `phi1`:
    /// `Ax = -(f cos beta + q s1 cos alpha)`, `Ay = f sin beta + q s1 sin alpha` [5.1, 6.8, 6.9]
    /// ([`Reactions::balancing`]).
    pub fn base_reactions(&self, phi1: f64) -> (f64, f64) {
        let l = &self.loads;
        let (sb, cb) = l.tip.effective_beta(phi1).sin_cos();
        let r = Reactions::balancing((l.tip.f * cb, l.tip.f * sb), l.fluid, l.s1);
        (r.ax, r.ay)
    }
}
