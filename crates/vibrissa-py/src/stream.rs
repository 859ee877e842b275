//! `vibrissa.Streamer`: one sensor row in, its contact point out, as
//! `vibrissa reconstruct --stream` does it (`profile_recon::Streamer`).

use std::panic::{catch_unwind, AssertUnwindSafe};

use beam_model::Whisker;
use profile_recon::{KnownFlow, ObservableRow, ReconPoint, ReconSettings, RowPose};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vibrissa_io::recon::{recon_model, ReconOptions};
use vibrissa_io::units::{Quantity, UnitSystem};
use vibrissa_io::IoError;

use crate::errors::{compute, py_error, to_py, Kind};
use crate::reconstruct::{recon_flags, LOG_ORIGIN};

/// A panic in the stream (an internal error) as a `SolverError`, not a `PanicException`.
fn internal(py: Python<'_>) -> PyErr {
    py_error(
        py,
        Kind::SolverError,
        "internal error in the stream (please report)".to_string(),
    )
}

/// An incremental reconstruction: `push` one row of base observables (in the scene's units),
/// get its contact point as soon as it is known.
#[pyclass(module = "vibrissa._core")]
pub struct Streamer {
    inner: Option<profile_recon::Streamer>,
    units: UnitSystem,
    /// The points released so far, in row order, as dicts.
    released: Vec<Py<PyDict>>,
    rows: usize,
    /// The flow the stream ended with (kept after `finish`).
    final_flow: Option<beam_model::FluidLoad>,
}

impl Streamer {
    fn point<'py>(&self, py: Python<'py>, p: &ReconPoint) -> PyResult<Bound<'py, PyDict>> {
        let (l, f) = (
            self.units.scale(Quantity::Length),
            self.units.scale(Quantity::Force),
        );
        let d = PyDict::new(py);
        d.set_item("row", p.row)?;
        d.set_item("x0", p.x0 * l)?;
        d.set_item("x", p.x * l)?;
        d.set_item("y", p.y * l)?;
        d.set_item("s1", p.s1 * l)?;
        d.set_item("f", p.f * f)?;
        d.set_item("psi", p.psi)?;
        d.set_item("phase", p.phase.label())?;
        d.set_item("sigma", p.sigma * l)?;
        d.set_item("residual", p.residual)?;
        d.set_item("hypotheses", p.alternatives)?;
        Ok(d)
    }

    fn error(&self, py: Python<'_>, e: profile_recon::ReconError) -> PyErr {
        let row = match &e {
            profile_recon::ReconError::NonFinite { row, .. }
            | profile_recon::ReconError::InconsistentRow { row, .. } => *row + 1,
            _ => self.rows,
        };
        to_py(
            py,
            IoError::Csv {
                path: LOG_ORIGIN.into(),
                line: row,
                column: None,
                reason: e.to_string(),
            },
        )
    }
}

#[pymethods]
impl Streamer {
    /// A stream for the whisker of `spec` (`theta, a, b, k, units`); `q`, `alpha_deg` fix
    /// the flow (else the first pre-contact row fixes it), `noise` the relative noise level.
    #[new]
    fn new(py: Python<'_>, spec: &Bound<'_, PyDict>) -> PyResult<Self> {
        let flags = recon_flags(spec)?;
        let file = crate::params::units_scene(spec)?;
        let (whisker, known, settings, units): (Whisker, KnownFlow, ReconSettings, UnitSystem) =
            compute(py, move || {
                let opts = ReconOptions::parse_stream(&flags)?;
                let r = recon_model(&flags, file)?;
                let (known, settings) = (opts.known_flow(&flags, &r), opts.settings());
                Ok((r.scene.whisker, known, settings, r.units()))
            })?;
        let inner = profile_recon::Streamer::new(&whisker, known, &settings)
            .map_err(|e| py_error(py, Kind::InvalidInput, e.to_string()))?;
        Ok(Streamer {
            inner: Some(inner),
            units,
            released: Vec::new(),
            rows: 0,
            final_flow: None,
        })
    }

    /// Takes the next row (x0, Ax, Ay, MA, phi0 in the scene's units); returns its contact
    /// point (a dict: row, x0, x, y, s1, f, psi, phase, sigma, residual, hypotheses) or
    /// `None` for a row before contact or held until the flow is known. Every point that
    /// becomes known (held rows included) is also appended to `points`.
    /// A row of any base motion gives its pose `y0` (a length) and `gamma` (radians) too
    /// (issue 38; 0 for the translating sweep).
    #[allow(non_snake_case, clippy::too_many_arguments)]
    #[pyo3(signature = (x0, Ax, Ay, MA, phi0, y0 = 0.0, gamma = 0.0))]
    fn push<'py>(
        &mut self,
        py: Python<'py>,
        x0: f64,
        Ax: f64,
        Ay: f64,
        MA: f64,
        phi0: f64,
        y0: f64,
        gamma: f64,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let u = &self.units;
        let row = ObservableRow {
            x0: x0 / u.scale(Quantity::Length),
            ax: Ax / u.scale(Quantity::Force),
            ay: Ay / u.scale(Quantity::Force),
            ma: MA / u.scale(Quantity::Moment),
            phi0,
        };
        let pose = RowPose::new(y0 / u.scale(Quantity::Length), gamma);
        self.rows += 1;
        let this = self.rows - 1;
        let Some(inner) = self.inner.as_mut() else {
            return Err(py_error(
                py,
                Kind::InvalidInput,
                "the stream is finished: make a new Streamer".to_string(),
            ));
        };
        let result = py.detach(|| catch_unwind(AssertUnwindSafe(|| inner.push_posed(row, pose))));
        let points = match result {
            Ok(r) => r.map_err(|e| self.error(py, e))?,
            Err(_) => return Err(internal(py)),
        };
        let mut mine = None;
        for p in &points {
            let d = self.point(py, p)?;
            if p.row == this {
                mine = Some(d.clone());
            }
            self.released.push(d.unbind());
        }
        Ok(mine)
    }

    /// Ends the stream: rows still held (the flow never fixed) are reconstructed as a batch
    /// log; returns their points (also appended to `points`).
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let Some(inner) = self.inner.take() else {
            return Ok(Vec::new());
        };
        self.final_flow = inner.flow();
        let points = match py.detach(|| catch_unwind(AssertUnwindSafe(|| inner.finish()))) {
            Ok(r) => r.map_err(|e| self.error(py, e))?,
            Err(_) => return Err(internal(py)),
        };
        let mut out = Vec::new();
        for p in &points {
            let d = self.point(py, p)?;
            self.released.push(d.clone().unbind());
            out.push(d);
        }
        Ok(out)
    }

    /// Every point released so far, in row order.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyDict>> {
        self.released.iter().map(|d| d.bind(py).clone()).collect()
    }

    /// Rows received so far.
    #[getter]
    fn rows(&self) -> usize {
        self.rows
    }

    /// The flow `(q, alpha_deg)` once known (q in the scene's units), else `None`.
    #[getter]
    fn flow(&self) -> Option<(f64, f64)> {
        let flow = match &self.inner {
            Some(inner) => inner.flow()?,
            None => self.final_flow?,
        };
        Some((
            flow.q * self.units.scale(Quantity::LineLoad),
            flow.alpha.to_degrees(),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "Streamer(rows={}, points={}, flow={})",
            self.rows,
            self.released.len(),
            match self.flow() {
                Some((q, a)) => format!("(q={q:.6}, alpha_deg={a:.4})"),
                None => "unknown".to_string(),
            }
        )
    }
}
