//! The base motion (spec/model.md, "Base motions"): the pose `(x0, y0, gamma)` of the base
//! along a path parameter, and the follicle stiffness k where a path sets it.
//!
//! The unloaded base direction is `pi/2 + gamma`, so the follicle law reads
//! `phi0 = pi/2 + gamma + m(0)/k` (`= pi/2 + gamma - MA/k`, [3.21, 3.22] turned by gamma); the
//! reactions `Ax, Ay` stay in the lab frame.
//!
//! - [`BaseMotion::Translate`]: `y0 = 0`, `gamma = 0`, x0 falling (the thesis's sweep, ch. 5).
//! - [`BaseMotion::Rotate`]: whisking: the base fixed at `(x0, y0)`, gamma rising
//!   (counter-clockwise: the tip moves towards -x first) from `gamma0` until the whisker
//!   separates from the obstacle.
//! - [`BaseMotion::Path`]: any sequence of poses, linear between them, with k along it where
//!   given (linear in the compliance `1/k`: the follicle tensing or relaxing), followed in
//!   the path parameter `p` ([`crate::path`]).
//!
//! How the sweep follows a motion: the whisker is shot in the lab frame from its loaded end,
//! so the shot gives the base's offset `(dx, dy)` from the contact point and the base
//! condition's value `R0 = phi(0) - pi/2 - m(0)/k`. A translation holds `R0 = 0` and
//! `y(s1) - y(0) = yc`, and reads its coordinate `x0 = xc - dx`; a rotation holds the base
//! position, `xc - dx = x0`, `yc - dy = y0`, and reads its coordinate `gamma = R0`. Either way
//! two equations hold on the contact branch and the motion's coordinate is an explicit
//! function of the branch state `(v, f, t)`, so one continuation serves both (`Frame`).
//!
//! A path holds neither its position nor its turn, but on one of its segments (rows `i`,
//! `i + 1`, the pose `P_i + w D_i` and the compliance `c_i + w dc`, `w = p - i` in
//! `[0, 1]`) the three conditions of the base are linear in the one unknown `w`:
//!
//! ```text
//! Q(u) = (xb - X_i, yb - Y_i, phi0 - pi/2 - m0 c_i - G_i) = w (DX, DY, DG + m0 dc) = w D(u)
//! ```
//!
//! (`xb = xc - dx`, `yb = yc - dy`; the third row is the follicle law
//! `phi0 = pi/2 + gamma(p) + m0/k(p)` [3.21, 3.22] turned and tensed along the path). The
//! segment's pivot `j` (the largest of `|DX|, |DY|, |DG|`) reads `w = Q_j / D_j` as an
//! explicit function of the branch state, and the other two rows, `Q_a - w D_a = 0`, are the
//! branch's two equations: the fourth unknown `p` is eliminated, the branch state stays
//! `(v, f, t)`, and the falling coordinate is `-p = -(i + w)`. A translation written as a
//! path (pivot x) holds exactly the translation's equations, a rotation (pivot gamma) the
//! rotation's. A corner of the path (where `D` jumps) is where the segment, hence the frame,
//! changes: the continuation stops on it (`End::Corner`) and goes on in the next segment's
//! frame from the same state.

use crate::error::{ContactError, Result};
use serde::{Deserialize, Serialize};

/// The pose of the base: position `(x0, y0)` and turn `gamma` (rad, counter-clockwise; the
/// unloaded base direction is `pi/2 + gamma`).
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    /// Base x.
    pub x0: f64,
    /// Base y.
    pub y0: f64,
    /// Turn of the follicle (rad).
    pub gamma: f64,
}

/// A path of poses (and follicle stiffnesses), linear between its rows; the path parameter
/// `p` runs from 0 at the first row to `n - 1` at the last.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Poses {
    /// The poses, in the order of the motion.
    pub poses: Vec<Pose>,
    /// The follicle stiffness at each pose, where the path sets it.
    #[serde(default)]
    pub k: Option<Vec<f64>>,
}

impl Poses {
    /// A path through `poses` (at least 2, finite) with the stiffnesses `k` (as many, each
    /// positive, `inf` for a rigid base) where given.
    ///
    /// # Errors
    /// [`ContactError::InvalidParameter`] naming the row and the value.
    pub fn new(poses: Vec<Pose>, k: Option<Vec<f64>>) -> Result<Self> {
        let bad = |name, value: f64, reason| {
            Err(ContactError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if poses.len() < 2 {
            return bad("path", poses.len() as f64, "a path needs at least 2 poses");
        }
        for p in &poses {
            for (name, v) in [("x0", p.x0), ("y0", p.y0), ("gamma", p.gamma)] {
                if !v.is_finite() {
                    return bad(name, v, "every pose of a path must be finite");
                }
            }
        }
        if let Some(k) = &k {
            if k.len() != poses.len() {
                return bad("k", k.len() as f64, "a path's k needs one value per pose");
            }
            if let Some(v) = k.iter().find(|v| v.is_nan() || **v <= 0.0) {
                return bad("k", *v, "the follicle stiffness must be > 0 (inf: rigid)");
            }
        }
        Ok(Poses { poses, k })
    }

    /// The segment of `p` and the weight within it.
    fn segment(&self, p: f64) -> (usize, f64) {
        let n = self.poses.len();
        let i = (p.floor().max(0.0) as usize).min(n - 2);
        (i, p - i as f64)
    }

    /// The pose at path parameter `p` (linear between rows, extended linearly beyond).
    pub fn pose(&self, p: f64) -> Pose {
        let (i, w) = self.segment(p);
        let (a, b) = (self.poses[i], self.poses[i + 1]);
        Pose {
            x0: a.x0 + w * (b.x0 - a.x0),
            y0: a.y0 + w * (b.y0 - a.y0),
            gamma: a.gamma + w * (b.gamma - a.gamma),
        }
    }

    /// `d(pose)/dp` at `p` (the segment's slope; the right one at a row).
    pub fn rate(&self, p: f64) -> Pose {
        let (i, _) = self.segment(p);
        let (a, b) = (self.poses[i], self.poses[i + 1]);
        Pose {
            x0: b.x0 - a.x0,
            y0: b.y0 - a.y0,
            gamma: b.gamma - a.gamma,
        }
    }

    /// The follicle stiffness at `p`, where the path sets it (linear in the compliance
    /// `1/k` between rows, so a rigid row blends continuously).
    pub fn k(&self, p: f64) -> Option<f64> {
        let k = self.k.as_ref()?;
        let (i, w) = self.segment(p);
        let c = (1.0 - w) / k[i] + w / k[i + 1];
        Some(1.0 / c)
    }

    /// The last value of the path parameter (`n - 1`).
    pub fn end(&self) -> f64 {
        (self.poses.len() - 1) as f64
    }

    /// The frame of segment `i` (rows `i`, `i + 1`), the follicle's compliance `compliance`
    /// where the path sets no k.
    pub(crate) fn segment_frame(&self, i: usize, compliance: f64) -> Segment {
        let (a, b) = (self.poses[i], self.poses[i + 1]);
        let (c0, c1) = match &self.k {
            Some(k) => (1.0 / k[i], 1.0 / k[i + 1]),
            None => (compliance, compliance),
        };
        let rate = Pose {
            x0: b.x0 - a.x0,
            y0: b.y0 - a.y0,
            gamma: b.gamma - a.gamma,
        };
        let size = [rate.x0.abs(), rate.y0.abs(), rate.gamma.abs()];
        // the largest component reads w; a segment that only tenses the follicle reads it
        // from the follicle law (D_3 = m0 dc)
        let mut pivot = 2;
        for j in [1, 0] {
            if size[j] > size[pivot] {
                pivot = j;
            }
        }
        Segment {
            index: i,
            from: a,
            rate,
            c0,
            dc: c1 - c0,
            pivot,
        }
    }
}

/// One segment of a path as the branch reads it ([`Frame::Path`]; the module's notes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// The segment's first row `i` (the path parameter there).
    pub index: usize,
    /// The pose `P_i` at its first row.
    pub from: Pose,
    /// `D = P_{i+1} - P_i`.
    pub rate: Pose,
    /// The follicle's compliance `1/k` at its first row.
    pub c0: f64,
    /// Its change over the segment.
    pub dc: f64,
    /// The component (x, y, gamma) that reads `w`.
    pub pivot: usize,
}

impl Segment {
    /// The compliance at the falling coordinate `c` (`-p`).
    pub(crate) fn compliance(&self, c: f64) -> f64 {
        self.c0 + (-c - self.index as f64) * self.dc
    }

    /// How far a point of a free whisker moves at most per unit of `p` (`|(DX, DY)| +
    /// |DG|` for a rigid motion of a unit whisker; the tensing's share bounded by the free
    /// base moment under the flow `q`, at most `q/2`).
    pub(crate) fn speed(&self, q: f64) -> f64 {
        self.rate.x0.hypot(self.rate.y0) + self.rate.gamma.abs() + self.dc.abs() * 0.5 * q
    }
}

/// Why a path segment that changes only `k` (the pose fixed) is refused: its parameter would
/// be read from the follicle law `phi0 = pi/2 + gamma + m0 c(p)` [3.21, 3.22], singular where
/// the base moment `m0` vanishes (docs/whisking-recon.md, "Paths in the calibration").
pub const K_ONLY_SEGMENT: &str =
    "the path changes only k between this row (from 0) and the next, the pose fixed: \
     its parameter would be read from the follicle law, singular where MA = 0; \
     move the pose a little along the segment, or split the tensing over moving rows";

/// How the base moves during a sweep (spec/cli.md `--motion`).
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub enum BaseMotion {
    /// The base at `(x0, 0)` moves towards -x, unturned (the thesis's sweep).
    #[default]
    Translate,
    /// Whisking: the base stays at `(x0, y0)` and turns counter-clockwise from `gamma0`.
    Rotate {
        /// Base x.
        x0: f64,
        /// Base y.
        y0: f64,
        /// The turn where the rotation starts (rad).
        gamma0: f64,
    },
    /// Any sequence of poses (and follicle stiffnesses).
    Path(Poses),
}

impl BaseMotion {
    /// `translate`, `rotate` or `path`, as messages name it.
    pub fn label(&self) -> &'static str {
        match self {
            BaseMotion::Translate => "translate",
            BaseMotion::Rotate { .. } => "rotate",
            BaseMotion::Path(_) => "path",
        }
    }

    /// Refuses a motion the sweep cannot follow, naming the culprit.
    ///
    /// # Errors
    /// [`ContactError::InvalidParameter`] for a non-finite start pose;
    /// [`ContactError::NotImplemented`] for a path.
    pub fn validate(&self) -> Result<()> {
        match self {
            BaseMotion::Translate => Ok(()),
            BaseMotion::Rotate { x0, y0, gamma0 } => {
                for (name, v) in [("x0", *x0), ("y0", *y0), ("gamma0", *gamma0)] {
                    if !v.is_finite() {
                        return Err(ContactError::InvalidParameter {
                            name,
                            value: v,
                            reason: "the pose where a rotation starts must be finite",
                        });
                    }
                }
                Ok(())
            }
            BaseMotion::Path(path) => {
                for (i, w) in path.poses.windows(2).enumerate() {
                    let same_k = path.k.as_ref().is_none_or(|k| k[i] == k[i + 1]);
                    if w[0] == w[1] && same_k {
                        return Err(ContactError::InvalidParameter {
                            name: "path",
                            value: i as f64,
                            reason: "the path does not move between this row (from 0) and the next: equal poses and k",
                        });
                    }
                    // a segment that only tenses the follicle reads its parameter from the
                    // follicle law, w = (phi0 - pi/2 - m0 c_i - G_i) / (m0 dc): singular
                    // where the base moment m0 = 0 (the free whisker without flow, a touch)
                    if w[0] == w[1] {
                        return Err(ContactError::InvalidParameter {
                            name: "path",
                            value: i as f64,
                            reason: K_ONLY_SEGMENT,
                        });
                    }
                }
                Ok(())
            }
        }
    }

    /// The frame the branch is solved in (a path: its first segment's, [`Poses::segment_frame`]
    /// gives the others).
    pub(crate) fn frame(&self) -> Option<Frame> {
        match self {
            BaseMotion::Translate => Some(Frame::Translate),
            BaseMotion::Rotate { x0, y0, .. } => Some(Frame::Rotate { x0: *x0, y0: *y0 }),
            BaseMotion::Path(_) => None,
        }
    }

    /// The falling coordinate where the motion starts (`+inf` for a translation, which
    /// starts wherever the whisker is clear of the obstacle; `-gamma0` for a rotation; 0,
    /// `-p` at the first row, for a path).
    pub(crate) fn start(&self) -> f64 {
        match *self {
            BaseMotion::Rotate { gamma0, .. } => -gamma0,
            BaseMotion::Path(_) => 0.0,
            _ => f64::INFINITY,
        }
    }
}

/// How the contact branch reads the motion (see the module's notes): which two equations
/// hold on it and which explicit function of the state is the motion's coordinate. The
/// coordinate *falls* along the motion: `x0` for a translation, `-gamma` for a rotation; the
/// continuation, the events and the rows then work in it unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(crate) enum Frame {
    /// `R0 = 0`, `y(s1) - y(0) = yc`; coordinate `x0 = xc - dx`.
    #[default]
    Translate,
    /// `xc - dx = x0`, `yc - dy = y0`; coordinate `-gamma = -R0`.
    Rotate {
        /// Base x.
        x0: f64,
        /// Base y.
        y0: f64,
    },
    /// One segment of a path: `Q_a = w D_a` for the two rows but the pivot; coordinate
    /// `-p = -(i + Q_j / D_j)` (the module's notes).
    Path(Segment),
}

impl Frame {
    /// The pose at the falling coordinate `c`.
    pub(crate) fn pose(&self, c: f64) -> Pose {
        match *self {
            Frame::Translate => Pose {
                x0: c,
                y0: 0.0,
                gamma: 0.0,
            },
            Frame::Rotate { x0, y0 } => Pose { x0, y0, gamma: -c },
            Frame::Path(seg) => {
                let w = -c - seg.index as f64;
                Pose {
                    x0: seg.from.x0 + w * seg.rate.x0,
                    y0: seg.from.y0 + w * seg.rate.y0,
                    gamma: seg.from.gamma + w * seg.rate.gamma,
                }
            }
        }
    }

    /// What the coordinate is called in messages.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            Frame::Translate => "x0",
            Frame::Rotate { .. } => "-gamma",
            Frame::Path(_) => "-p",
        }
    }

    /// The coordinate where the frame ends: a path's next row (`-(i + 1)`); none for a
    /// translation or a rotation.
    pub(crate) fn floor(&self) -> Option<f64> {
        match self {
            Frame::Path(seg) => Some(-(seg.index as f64 + 1.0)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x0: f64, y0: f64, gamma: f64) -> Pose {
        Pose { x0, y0, gamma }
    }

    /// A path's pose and rate are the linear interpolation written out; k blends in the
    /// compliance (a rigid row's neighbour halves the compliance halfway).
    #[test]
    fn a_path_interpolates_its_poses() {
        let poses = vec![
            Pose {
                x0: 0.0,
                y0: 0.0,
                gamma: 0.0,
            },
            Pose {
                x0: -1.0,
                y0: 0.5,
                gamma: 0.2,
            },
            Pose {
                x0: -1.0,
                y0: 0.5,
                gamma: 1.2,
            },
        ];
        let path = Poses::new(poses, Some(vec![10.0, f64::INFINITY, 20.0])).unwrap();
        let p = path.pose(0.25);
        assert_eq!((p.x0, p.y0, p.gamma), (-0.25, 0.125, 0.05));
        assert_eq!(path.rate(1.5).gamma, 1.0);
        assert_eq!(path.pose(2.0).gamma, 1.2);
        assert!((path.k(0.5).unwrap() - 20.0).abs() < 1e-12);
        assert_eq!(path.k(1.0).unwrap(), f64::INFINITY);
        let one = vec![Pose::default()];
        assert!(Poses::new(one, None).is_err());
        let two = vec![Pose::default(); 2];
        let e = Poses::new(two, Some(vec![1.0, -2.0])).unwrap_err();
        assert!(e.to_string().contains("k = -2"), "{e}");
    }

    /// The frames' coordinates: x0 for a translation, -gamma for a rotation, and back.
    /// A segment that only tenses the follicle is refused by name (its parameter would be
    /// read from the follicle law, singular where MA = 0); equal poses with equal k too.
    #[test]
    fn a_k_only_segment_is_refused_naming_its_row() {
        let poses = vec![
            pose(0.0, 0.0, 0.0),
            pose(0.0, 0.0, 0.3),
            pose(0.0, 0.0, 0.3),
        ];
        let tensing = Poses::new(poses.clone(), Some(vec![10.0, 10.0, 30.0])).unwrap();
        match BaseMotion::Path(tensing).validate() {
            Err(ContactError::InvalidParameter {
                name,
                value,
                reason,
            }) => {
                assert_eq!((name, value, reason), ("path", 1.0, K_ONLY_SEGMENT));
            }
            other => panic!("{other:?}"),
        }
        let moving = vec![
            pose(0.0, 0.0, 0.0),
            pose(0.0, 0.0, 0.3),
            pose(0.0, 0.0, 0.5),
        ];
        let ok = Poses::new(moving, Some(vec![10.0, 10.0, 30.0])).unwrap();
        assert!(BaseMotion::Path(ok).validate().is_ok());
        let still = Poses::new(poses, Some(vec![10.0, 10.0, 10.0])).unwrap();
        let e = BaseMotion::Path(still).validate().unwrap_err().to_string();
        assert!(e.contains("does not move"), "{e}");
    }

    #[test]
    fn frames_map_coordinates_to_poses() {
        let rot = Frame::Rotate { x0: 0.1, y0: -0.2 };
        let pose = rot.pose(-0.3);
        assert_eq!((pose.x0, pose.y0, pose.gamma), (0.1, -0.2, 0.3));
        assert_eq!(Frame::Translate.pose(0.4).x0, 0.4);
        let path = BaseMotion::Path(Poses::new(vec![Pose::default(); 2], None).unwrap());
        assert!(path
            .validate()
            .unwrap_err()
            .to_string()
            .contains("does not move"));
        // a segment's frame: the pose at -p, the pivot the largest component
        let turn = Pose {
            x0: 0.1,
            y0: 0.0,
            gamma: 0.5,
        };
        let path = Poses::new(vec![Pose::default(), turn], Some(vec![10.0, 5.0])).unwrap();
        let seg = path.segment_frame(0, 0.0);
        assert_eq!((seg.pivot, seg.dc), (2, 0.1));
        let pose = Frame::Path(seg).pose(-0.5);
        assert_eq!((pose.x0, pose.gamma), (0.05, 0.25));
        assert!((seg.compliance(-0.5) - 1.0 / path.k(0.5).unwrap()).abs() < 1e-15);
        assert_eq!(Frame::Path(seg).floor(), Some(-1.0));
    }
}
