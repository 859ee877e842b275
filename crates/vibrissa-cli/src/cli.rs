//! The command-line grammar (clap derive), per `spec/cli.md`.
//!
//! Numbers are taken as text here and parsed in [`crate::resolve`], so that every bad value
//! is reported in the binary's one-line format naming the flag, and values such as `inf`,
//! `nan` or negative numbers reach the model's own range checks.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

const MAIN_EXAMPLES: &str = "\
Examples:
  vibrissa solve --f 1 --json                 Mattiasson's cantilever, f = 1
  vibrissa solve scenes/s04-fluid-elastic-support.ron --k 5 --out out/s04
  vibrissa sweep --profile g1 --q 5 --theta 0.75 --k 20 --points 100 --out out/sweep
  vibrissa sweep scenes/c1-uniform-rigid-g1.ron --out out/c1
  vibrissa demo --out vibrissa-demo

Exit codes: 0 success, 1 solver failure, 2 usage or input error, 3 no contact (the whisker
never touches the obstacle), 4 output not delivered (standard output closed by its reader,
as `| head` does, or full; an --out folder written before stays whole).

Output folders (--out DIR): written whole or not at all (staged beside DIR, then swapped in);
DIR lists what vibrissa wrote in DIR/.vibrissa-output, and a DIR holding anything else is
refused (exit 2, naming one such file), never emptied; a symbolic link DIR is followed (the
folder it points to is replaced, the link stays a link); a second run into DIR while one
writes it is refused (exit 2).";

const SOLVE_EXAMPLES: &str = "\
Examples:
  vibrissa solve --f 1 --json
  vibrissa solve --theta 0.5 --k 10 --q 10 --method fdm --n 200
  vibrissa solve --f 5 --beta-deg 30 --q 5 --a 2 --b -1 --out out/combined
  vibrissa solve scenes/s11-combined-uniform-rigid.ron --beta-deg 45 --json";

const SWEEP_EXAMPLES: &str = "\
Examples:
  vibrissa sweep --profile g1 --q 5 --points 200 --out out/g1
  vibrissa sweep --profile parabola:2,0.4,0.5 --q 1 --out out/parabola
  vibrissa sweep --profile points:contour.csv --theta 0.75 --k 20 --q 5 --out out/tab
  vibrissa sweep scenes/c5-tapered-precurved-elastic-g1.ron --points 50 --out out/c5
  vibrissa sweep --motion rotate --gamma-deg -10 --profile peg:-0.2,0.6 --out out/whisk

Profiles: g1, g2, ge, parabola:a,xv,yv, cosh:a,c,xv,d, circle:xc,yc,r, points:FILE.csv;
obstacles touched from any side: peg:x,y (a point, such as a thin pole), disc:x,y,r.
A points file is a CSV table whose header names the x and y columns, units allowed
(x,y or x_mm;y_mm or x [mm]<TAB>y [mm]); comma, tab or semicolon separated; it need only
cover the part of the contour the whisker touches. In a physical scene (units:
Physical(...)) profile numbers and points without units are in mm; g1, g2, ge are in
whisker lengths. Outputs are in the scene's units (mm, N, N mm for a physical scene);
each CSV has a NAME.units.csv beside it.

Rows: --points N gives N contact rows + event rows + 10 rows before contact; rows are
numbered from 1 (row r is line r + 1 of observables.csv) in the text, the JSON and the CSV.

Frame: the base at (x0, 0) points along +y and moves towards -x; the obstacle is the region
above its contour, y > g(x); a flow at alpha = 0 pushes along +x. Phases: A, the tip rests on
the obstacle; B, the whisker touches it tangentially with a point before its tip (the part
beyond is unloaded). A contact ends by a snap (the whisker jumps off where the contact
branch turns back) or a release (the flow lifts it off: the contact force falls to 0).
Whisking (--motion rotate): the base stays at (--x0, --y0) and turns counter-clockwise
(gamma rising; the unloaded base direction is 90° + gamma, so phi0 = 90° + gamma - MA/k); a
peg is released when the tip slides past it.";

const RECONSTRUCT_EXAMPLES: &str = "\
Examples:
  vibrissa reconstruct out/g1 --out out/g1-recon          a sweep folder, no further flags
  vibrissa reconstruct out/g1/observables.csv --out out/recon
  vibrissa reconstruct obs.csv scenes/c1-uniform-rigid-g1.ron --q 5 --profile g1 --json --out out/recon
  vibrissa reconstruct noisy.csv --theta 0.75 --k 20 --tolerance none --out out/noisy
  sensor | vibrissa reconstruct --stream scenes/c1-uniform-rigid-g1.ron --q 5 --alpha-deg 0

The log needs the columns x0,Ax,Ay,MA,phi0 (any order; other columns are ignored; comma,
tab or semicolon separated). Whisker values come from the scene file (DIR/scene.ron for a
sweep folder) and the flags; loads in the scene are ignored (q is identified from the rows
before contact unless --q is given). A log's units come from NAME.units.csv beside it, else
the scene's units (mm, N, N mm for a physical scene); the outputs are in the scene's units.";

const DEMO_EXAMPLES: &str = "\
Examples:
  vibrissa demo
  vibrissa demo --out /tmp/demo";

/// Whisker-inspired tactile sensing: elastica, contact sweeps and contour reconstruction.
#[derive(Debug, Parser)]
#[command(name = "vibrissa", version, about, after_help = MAIN_EXAMPLES)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
    /// Figures to write with the outputs: none (fastest), svg (vector, small), png (300
    /// dpi at the printed size; 150 dpi for slides) or all.
    #[arg(
        long,
        global = true,
        value_enum,
        value_name = "WHICH",
        default_value = "svg"
    )]
    pub figures: vibrissa_plot::FigureFormats,
    /// The printed size the figures are made for: column (85 mm, one column of a journal
    /// page), page (175 mm, both columns) or slide (254 mm, fonts twice as large). Fonts
    /// print at 7-8.5 pt at that size.
    #[arg(
        long,
        global = true,
        value_enum,
        value_name = "SIZE",
        default_value = "column"
    )]
    pub size: vibrissa_plot::FigureSize,
}

impl Cli {
    /// How the command's figures are written: `--size` and `--figures`, handed to the
    /// command ([`crate::commands::run`]), not set for the process.
    pub fn figure_style(&self) -> vibrissa_plot::FigureStyle {
        vibrissa_plot::FigureStyle::new(self.size, self.figures)
    }
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve one whisker configuration (elastica, tip, base observables).
    #[command(after_help = SOLVE_EXAMPLES)]
    Solve(SolveArgs),
    /// Sweep the whisker past an obstacle under the fluid load; write the observables log.
    #[command(after_help = SWEEP_EXAMPLES)]
    Sweep(SweepArgs),
    /// Reconstruct a contour from an observables log.
    #[command(after_help = RECONSTRUCT_EXAMPLES)]
    Reconstruct(ReconstructArgs),
    /// Run the whole chain on a built-in scene and write its figures and CSVs.
    #[command(after_help = DEMO_EXAMPLES)]
    Demo(DemoArgs),
    /// Fit the whisker's own parameters to logs of sweeps past known contours.
    #[command(after_help = CALIBRATE_EXAMPLES)]
    Calibrate(CalibrateArgs),
}

/// Tip-force kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LoadArg {
    /// Direction-preserving: the force keeps its direction in space as the whisker bends.
    Dp,
    /// Angle-preserving: the force turns with the tip, keeping its angle to the whisker.
    Ap,
}

/// Whisker flags shared by every command.
#[derive(Debug, Clone, Default, Args)]
pub struct WhiskerFlags {
    /// Taper: diameter ratio tip/base, 0.01 <= T <= 1 (1 = a cylinder; thinner tips are beyond
    /// the solver's resolution) [default: 1]
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub theta: Option<String>,
    /// Slope A of the unloaded whisker's curvature along its length, kappa0(s) = A s + B
    /// (s = 0 at the base, 1 at the tip; a straight whisker has A = B = 0), |A| <= 100
    /// [default: 0]
    #[arg(long, value_name = "A", allow_hyphen_values = true)]
    pub a: Option<String>,
    /// Base value B of the unloaded curvature kappa0(s) = A s + B, |B| <= 100 [default: 0]
    #[arg(long, value_name = "B", allow_hyphen_values = true)]
    pub b: Option<String>,
    /// Stiffness of the torsional spring at the base (the follicle), k >= 0.01: the base
    /// turns by MA / k; `inf` for a rigid support [default: inf]
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub k: Option<String>,
}

/// Tip-force flags (solve only).
#[derive(Debug, Clone, Default, Args)]
pub struct TipFlags {
    /// Tip force magnitude 0 <= f <= 1000 [default: 0]
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub f: Option<String>,
    /// Tip force angle in degrees (0 pushes towards +x), reduced exactly modulo 360 [default: 0]
    #[arg(long = "beta-deg", value_name = "D", allow_hyphen_values = true)]
    pub beta_deg: Option<String>,
    /// Tip force kind: dp keeps its direction in space, ap turns with the tip [default: dp]
    #[arg(long, value_enum, value_name = "KIND")]
    pub load: Option<LoadArg>,
}

/// Fluid-load flags.
#[derive(Debug, Clone, Default, Args)]
pub struct FluidFlags {
    /// Fluid load per unit length 0 <= q <= 1000 [default: 0]
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub q: Option<String>,
    /// Fluid load angle in degrees (0 pushes towards +x), reduced exactly modulo 360 [default: 0]
    #[arg(long = "alpha-deg", value_name = "D", allow_hyphen_values = true)]
    pub alpha_deg: Option<String>,
}

/// Method flags.
#[derive(Debug, Clone, Default, Args)]
pub struct MethodFlags {
    /// Solution method: auto (the cheapest model and method that meets --tol: linear
    /// small-deflection theory where its a-priori bound proves it meets --tol, a spectral
    /// Picard iteration of the integral form for weak and moderate loads, else accurate at
    /// the tolerance that suffices), accurate (adaptive DOP853 shooting, error estimated by a second shot;
    /// falls back to fdm-richardson on refined grids where shooting is ill-conditioned, as
    /// `stats.method_used` says; refused when the estimate exceeds 1e-8), rk4 (fixed-step
    /// shooting), fdm (finite differences, the thesis's method), fdm-richardson (FDM on n,
    /// 2n, 4n with two Richardson levels, order 6), multiple-shooting (DOP853 on segments,
    /// from the FDM's branch) or collocation (Lobatto IIIA with mesh refinement and its own
    /// load continuation; --tol its accuracy, default 1e-8; accurate's last fallback for
    /// slender whiskers under tip forces); the fixed-grid methods are refused when
    /// their error estimate (the same solve on a grid twice as fine, compared) exceeds 5e-2
    /// [default: accurate]
    #[arg(long, value_name = "M")]
    pub method: Option<String>,
    /// Grid intervals per unit length for rk4/fdm (<= 100000; fdm-richardson <= 25000);
    /// output intervals for accurate [default: 100]
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub n: Option<String>,
    /// The accuracy asked for (absolute error of the tip, loaded end and base observables,
    /// dimensionless, in [1e-12, 1e-2]): solves with --method auto, the cheapest model and
    /// method whose error estimate meets it (linear theory for weak enough loads);
    /// `stats.model_used` and `stats.method_used` say which (sweep and reconstruct: always
    /// the elastica) [default: 1e-8]
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tol: Option<String>,
}

/// All model flags of `solve` and `sweep`.
#[derive(Debug, Clone, Default, Args)]
pub struct ModelFlags {
    /// Whisker flags.
    #[command(flatten)]
    pub whisker: WhiskerFlags,
    /// Tip force flags.
    #[command(flatten)]
    pub tip: TipFlags,
    /// Fluid load flags.
    #[command(flatten)]
    pub fluid: FluidFlags,
    /// Method flags.
    #[command(flatten)]
    pub method: MethodFlags,
}

/// `vibrissa solve`.
#[derive(Debug, Clone, Args)]
pub struct SolveArgs {
    /// A RON scene file (see scenes/README.md); flags override what it sets.
    #[arg(value_name = "SCENE.ron")]
    pub scene: Option<PathBuf>,
    /// Model flags.
    #[command(flatten)]
    pub model: ModelFlags,
    /// Print one JSON object on stdout instead of a human summary.
    #[arg(long)]
    pub json: bool,
    /// Write elastica.csv (s,x,y,phi,kappa,m, with elastica.units.csv), scene.ron and the
    /// figure elastica.svg/.png into DIR (mm, N mm for a physical scene). A symbolic link
    /// is followed; a DIR holding files vibrissa did not write is refused.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `vibrissa sweep`.
#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// A RON scene file (see scenes/README.md); flags override what it sets.
    #[arg(value_name = "SCENE.ron")]
    pub scene: Option<PathBuf>,
    /// The whisker (theta, a, b, k).
    #[command(flatten)]
    pub whisker: WhiskerFlags,
    /// The flow (q, alpha-deg); the contact force is the sweep's own, and its phases are
    /// always solved by adaptive shooting (no --f, --method or --n).
    #[command(flatten)]
    pub fluid: FluidFlags,
    /// The obstacle contour (required here or in the scene file).
    #[arg(long, value_name = "P")]
    pub profile: Option<String>,
    /// Contact rows, 2..=100000, evenly spaced in the base position x0 (in the turn gamma of
    /// a rotation) from the first contact to the separation (both included). One row is added at each phase switch; 10 rows
    /// before contact (flow only) come first. The summary counts them all [default: 200]
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub points: Option<String>,
    /// The accuracy asked for of every row (absolute error of its observables and contact
    /// point, dimensionless, in [1e-12, 1e-2]): the contact rows solved at tolerances derived
    /// from it (looser ones are cheaper), each with an a-posteriori error estimate; the
    /// summary reports the worst, and a row whose estimate exceeds T fails the sweep naming
    /// it (exit 1); the model is always the elastica (`model_used` in the JSON summary).
    /// Also the scene's `sweep.tol` [default: none, the rows at ~1e-10 without estimates]
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tol: Option<String>,
    /// The Coulomb friction coefficient at the contact, dimensionless, in [0, 10]: the
    /// contact force may have a tangential part `ft` with |ft| <= MU f (stick: the touching
    /// point of the whisker stays put on the obstacle; slip: |ft| = MU f against the
    /// sliding). The log's `ft` and `slip` columns and the summary's stick/slip switches
    /// show it. Also the scene's `mu` [default: 0, frictionless]
    #[arg(long, value_name = "MU", allow_hyphen_values = true)]
    pub mu: Option<String>,
    /// How the base moves: `translate` (the base at (x0, 0) moves towards -x, unturned: the
    /// thesis's sweep), `rotate` (whisking: the base stays at (--x0, --y0) and turns
    /// counter-clockwise from --gamma-deg until the whisker separates; rows evenly spaced in
    /// the turn gamma), or `path:FILE.csv` (a table of poses with the header
    /// `x0,y0,gamma_deg` and optionally `k`, the follicle stiffness along the path; linear
    /// between rows; units allowed in the names: `x0_mm`, `gamma [rad]`, `k [N mm/rad]`).
    /// Lengths in the scene's unit (mm in a physical scene), k in its stiffness unit (N m/rad
    /// physical). The log's `y0` and `gamma` (rad) columns carry each row's pose. Friction
    /// (--mu > 0) is for the translation past graphs only. Also the scene's `motion`
    /// [default: translate]
    #[arg(long, value_name = "M")]
    pub motion: Option<String>,
    /// The base x where a rotation starts (scene's length unit; --motion rotate) [default: 0]
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub x0: Option<String>,
    /// The base y where a rotation starts (scene's length unit; --motion rotate) [default: 0]
    #[arg(long, value_name = "Y", allow_hyphen_values = true)]
    pub y0: Option<String>,
    /// The turn of the follicle where a rotation starts, degrees counter-clockwise (the
    /// unloaded base direction is 90° + G; --motion rotate) [default: 0]
    #[arg(long, value_name = "G", allow_hyphen_values = true)]
    pub gamma_deg: Option<String>,
    /// Also write shapes.csv: the whisker's shape at every row (row, s, x, y, phi; 100
    /// intervals of arc length up to the contact point, then the load-free segment beyond a
    /// tangential contact, to the tip), in the scene's units.
    #[arg(long)]
    pub shapes: bool,
    /// Print one JSON object on stdout (first_contact, separation, phases, rows, the row
    /// counts and the events) instead of the summary line.
    #[arg(long)]
    pub json: bool,
    /// Output directory: observables.csv (+ observables.units.csv), scene.ron (every
    /// parameter, to reconstruct the folder with `vibrissa reconstruct DIR`), and the
    /// figures observables, contact, shapes (as `--figures` says: SVG by default). A
    /// symbolic link is followed; a DIR holding files vibrissa did not write is refused.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// `vibrissa reconstruct`.
#[derive(Debug, Clone, Args)]
pub struct ReconstructArgs {
    /// The observables log (columns x0,Ax,Ay,MA,phi0 at least), or a sweep folder DIR: then
    /// DIR/observables.csv is reconstructed with the whisker of DIR/scene.ron. Not with
    /// --stream.
    #[arg(value_name = "OBSERVABLES.csv|DIR", required_unless_present = "stream")]
    pub observables: Option<PathBuf>,
    /// A RON scene file with the whisker; flags override what it sets.
    #[arg(value_name = "SCENE.ron")]
    pub scene: Option<PathBuf>,
    /// Whisker flags.
    #[command(flatten)]
    pub whisker: WhiskerFlags,
    /// The fluid load q; identified from the log when not given.
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub q: Option<String>,
    /// The flow angle in degrees, in (-90, 90); identified from the log when not given
    /// (0 when only --q is given and no row is pre-contact).
    #[arg(long = "alpha-deg", value_name = "D", allow_hyphen_values = true)]
    pub alpha_deg: Option<String>,
    /// Relative noise level of the log (standard deviation over each column's largest
    /// magnitude); estimated from the log when not given.
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub noise: Option<String>,
    /// Read the log from standard input row by row (header line first) and write each
    /// contact point to standard output as soon as it is known (CSV, the header of
    /// reconstruction.csv); the positional argument is then the scene.
    #[arg(long)]
    pub stream: bool,
    /// The true contour, to compute the reconstruction error (eq. 6.11): adds an `error`
    /// column and error.svg.
    #[arg(long, value_name = "P")]
    pub profile: Option<String>,
    /// Reconstruction method: accurate (initial-value route from the base, ~1e-12) or
    /// thesis (the thesis's five equations around FDM solves) [default: accurate]
    #[arg(long, value_name = "M")]
    pub method: Option<String>,
    /// Largest consistency residual accepted per contact row; a row beyond it is an error
    /// naming its line. `none` never fails (for noisy logs: residuals are then only
    /// reported) [default: 1e-6]
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tolerance: Option<String>,
    /// The accuracy asked for of every contact point (absolute error of x, y,
    /// dimensionless, in [1e-12, 1e-2]; method accurate): the integration the points need,
    /// each with an a-posteriori error estimate; the summary reports the worst, and a point
    /// whose estimate exceeds T is an error naming its line (exit 1); the model is always
    /// the elastica (`model_used` in the JSON summary). Not with --stream [default: none,
    /// the points at the integrator tolerance 1e-12 without estimates]
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tol: Option<String>,
    /// Coulomb friction at the contact (spec/model.md): `identify` reconstructs the
    /// frictional log and identifies mu from the sliding rows (JSON `mu` with its standard
    /// error); a number MU in [0, 10] fixes it (0: the frictionless points, checked: a log
    /// that shows friction gets a warning and wider error estimates). Adds the column `ft`.
    /// With --stream: each contact row's frictional point with `ft` as soon as it is known
    /// (a tip contact's tangent from the points so far), mu on standard error at the end.
    /// Method accurate, not with --tol [default: none: mu identified with its standard
    /// error beside today's frictionless points, which stay unchanged unless the log proves
    /// friction (some |ft| beyond 6 standard deviations): then the frictional points and
    /// `ft` are written]
    #[arg(long, value_name = "MU|identify", allow_hyphen_values = true)]
    pub mu: Option<String>,
    /// Print one JSON object on stdout instead of a human summary.
    #[arg(long)]
    pub json: bool,
    /// Output directory: reconstruction.csv, reconstruction.svg (and error.svg with
    /// --profile); not with --stream. A symbolic link is followed; a DIR holding files
    /// vibrissa did not write is refused.
    #[arg(long, value_name = "DIR", required_unless_present = "stream")]
    pub out: Option<PathBuf>,
}

/// `vibrissa demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {
    /// Output directory (a symbolic link is followed; a DIR holding files vibrissa did not
    /// write is refused).
    #[arg(long, value_name = "DIR", default_value = "vibrissa-demo")]
    pub out: PathBuf,
    /// Contact rows of the demo sweep (event rows are added, as for `sweep --points`).
    #[arg(long, value_name = "N", default_value_t = 120)]
    pub points: usize,
}

const CALIBRATE_EXAMPLES: &str = "\
Examples:
  vibrissa calibrate out/post --json                       a sweep folder: contour and start from its scene.ron
  vibrissa calibrate run1/observables.csv --profile circle:0,1.4,0.5 --theta 0.7 --k 20 --out cal
  vibrissa calibrate post.csv=circle:0,1.4,0.5 bar.csv=parabola:2,0,0.5 --scene beta.ron --fit theta,a,b,k,ei --out cal
  vibrissa reconstruct unknown.csv cal/scene.ron --out rec  the calibrated whisker on an unknown object
  vibrissa calibrate --advise circle:0,1.4,0.5 --advise g2 --theta 0.7 --k 20 --q 2   which object to sweep past

Each LOG is an observables CSV (x0,Ax,Ay,MA,phi0 at least; y0, gamma where the base turned or
rose: a whisking log, its follicle law turned by gamma) or a sweep folder; its known
contour comes from LOG=PROFILE, else --profile, else the folder's scene.ron (else --scene's). Several logs of
one whisker are fitted jointly, each with its own flow (q, alpha), fitted too. Start values:
--scene (else the first folder's scene.ron) under the whisker flags; k from the follicle law
of the rows. Outputs (--out): scene.ron (the calibrated whisker, ready for sweep and
reconstruct), residuals.csv (every row: its phase, contact point, distance to the contour,
sigma, chi) and the figures contour-N.svg (contour, points before and after) and
residuals.svg. A parameter the logs cannot determine is reported as not identifiable (JSON:
value null), with the combination they do determine.";

/// `vibrissa calibrate`.
#[derive(Debug, Clone, Args)]
pub struct CalibrateArgs {
    /// Logs: observables CSVs or sweep folders, each optionally with its contour as
    /// LOG=PROFILE.
    #[arg(value_name = "LOG[=PROFILE]", required_unless_present = "advise", num_args = 1..)]
    pub logs: Vec<String>,
    /// A RON scene file with the whisker's start values and the units (default: the first
    /// sweep folder's scene.ron).
    #[arg(long, value_name = "SCENE.ron")]
    pub scene: Option<PathBuf>,
    /// Start values of the whisker (override the scene).
    #[command(flatten)]
    pub whisker: WhiskerFlags,
    /// The known contour of every log without its own (LOG=PROFILE).
    #[arg(long, value_name = "P")]
    pub profile: Option<String>,
    /// The parameters to fit, a comma-separated list of theta, a, b, k, ei (ei, the bending
    /// stiffness E·Ib, in physical units only), mu (the friction coefficient at the contact,
    /// from the sliding rows) [default: theta,a,b,k]
    #[arg(long, value_name = "LIST")]
    pub fit: Option<String>,
    /// Local fits at most, from the best of 96 seeded candidate starts (the guard against
    /// local minima) [default: 4]
    #[arg(long, value_name = "N")]
    pub starts: Option<String>,
    /// Advice before any experiment, instead of a calibration: for each candidate object P
    /// (repeat the flag), the standard errors a sweep past it would give the parameters of
    /// --fit, for the start whisker under the flow (--q, --alpha-deg or the scene's) at the
    /// sensor's noise level (--noise).
    #[arg(long, value_name = "P")]
    pub advise: Vec<String>,
    /// The flow: with both --q and --alpha-deg it is known and held fixed for every log
    /// (else fitted per log, --q alone as its start); with --advise, the flow of the planned
    /// sweeps [default: fitted; with --advise the scene's, else 0]
    #[command(flatten)]
    pub fluid: FluidFlags,
    /// With --advise: the sensor's relative noise level [default: 1e-4]
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub noise: Option<String>,
    /// With --advise: contact rows of each planned sweep [default: 100]
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub points: Option<String>,
    /// Print one JSON object on stdout instead of a human summary.
    #[arg(long)]
    pub json: bool,
    /// Output directory: scene.ron, residuals.csv (+ units), contour-N.svg, residuals.svg. A
    /// symbolic link is followed; a DIR holding files vibrissa did not write is refused.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

// The library's model values (`vibrissa_io::resolve`), as typed, from the flags.

/// A flag's text as the library's value (parsed, and refused naming the flag, there).
pub fn text(raw: &Option<String>) -> Option<vibrissa_io::resolve::Value> {
    raw.clone().map(vibrissa_io::resolve::Value::Text)
}

impl From<LoadArg> for vibrissa_io::scene_file::LoadKind {
    fn from(l: LoadArg) -> Self {
        match l {
            LoadArg::Dp => vibrissa_io::scene_file::LoadKind::Dp,
            LoadArg::Ap => vibrissa_io::scene_file::LoadKind::Ap,
        }
    }
}

impl From<&WhiskerFlags> for vibrissa_io::resolve::WhiskerFlags {
    fn from(w: &WhiskerFlags) -> Self {
        vibrissa_io::resolve::WhiskerFlags {
            theta: text(&w.theta),
            a: text(&w.a),
            b: text(&w.b),
            k: text(&w.k),
        }
    }
}

impl From<&TipFlags> for vibrissa_io::resolve::TipFlags {
    fn from(t: &TipFlags) -> Self {
        vibrissa_io::resolve::TipFlags {
            f: text(&t.f),
            beta_deg: text(&t.beta_deg),
            load: t.load.map(Into::into),
        }
    }
}

impl From<&FluidFlags> for vibrissa_io::resolve::FluidFlags {
    fn from(f: &FluidFlags) -> Self {
        vibrissa_io::resolve::FluidFlags {
            q: text(&f.q),
            alpha_deg: text(&f.alpha_deg),
        }
    }
}

impl From<&MethodFlags> for vibrissa_io::resolve::MethodFlags {
    fn from(m: &MethodFlags) -> Self {
        vibrissa_io::resolve::MethodFlags {
            method: m.method.clone(),
            n: text(&m.n),
            tol: text(&m.tol),
        }
    }
}

impl From<&ModelFlags> for vibrissa_io::resolve::ModelFlags {
    fn from(m: &ModelFlags) -> Self {
        vibrissa_io::resolve::ModelFlags {
            whisker: (&m.whisker).into(),
            tip: (&m.tip).into(),
            fluid: (&m.fluid).into(),
            method: (&m.method).into(),
        }
    }
}
