//! `NativeSolution`: one solve's document, kept in Rust and read on demand: its figures by
//! getters, its trajectories as numpy arrays, its JSON text only when asked (`to_json`), the
//! point where it ended, to start another solve from, and what it was solved for, to resample
//! it at a controller's rate.

use crate::errors::Failure;
use codesign::design::run::OptimizeDocument;
use codesign::report::export::{resample, ExportError};
use codesign::report::solve_document::SolveDocument;
use codesign::report::trajectory::charts;
use codesign::store::document::document_json;
use codesign_core::problem::Formulation;
use codesign_core::solve::StartPoint;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// One solve (see `codesign.Solution`).
#[pyclass(module = "codesign._native", frozen)]
pub struct NativeSolution {
    /// The document `codesign solve --out` writes for it.
    pub(crate) document: SolveDocument,
    /// Where it ended: IPOPT's point and multipliers, and what they fit; None for a run's best
    /// design read from the run's document.
    pub(crate) point: Option<StartPoint>,
    /// The formulation it was solved for (task, robot, space), to resample it; None for a run's
    /// best design read from the run's document.
    pub(crate) formulation: Option<Formulation>,
}

/// Rows of equal length as a 2-D array of shape (rows, `width`).
pub(crate) fn rows<'py>(
    py: Python<'py>,
    rows: &[Vec<f64>],
    width: usize,
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = PyArray1::from_vec(py, flat);
    array
        .reshape([rows.len(), width])
        .unwrap_or_else(|_| PyArray2::zeros(py, [0, width], false))
}

impl NativeSolution {
    /// The formulation it was solved for, or the error of `method` (`resample`, `plot`) for a
    /// run's best design, which keeps none.
    fn formulation(&self, py: Python<'_>, method: &str) -> PyResult<&Formulation> {
        self.formulation.as_ref().ok_or_else(|| {
            Failure::input(format!(
                "{method}: a run's best solution keeps no robot; solve its design first \
                 (ratios=run.best.ratios)"
            ))
            .into_py(py)
        })
    }
}

#[pymethods]
impl NativeSolution {
    /// The best design of the co-design run whose document is `text`, as the run solved it;
    /// None where it found no feasible design.
    #[staticmethod]
    fn of_run_best(py: Python<'_>, text: &str) -> PyResult<Option<NativeSolution>> {
        let run: OptimizeDocument = serde_json::from_str(text)
            .map_err(|e| Failure::solver(format!("run document not read: {e}")).into_py(py))?;
        Ok(
            SolveDocument::of_run_best(&run).map(|document| NativeSolution {
                document,
                point: None,
                formulation: None,
            }),
        )
    }

    /// The charts `solve --plot` draws, each as its file's name and the chart as JSON
    /// (`Chart::to_json`), in the order it writes them.
    fn charts(&self, py: Python<'_>) -> PyResult<Vec<(String, String)>> {
        let formulation = self.formulation(py, "plot")?;
        let charts = charts(formulation, &self.document.result)
            .map_err(|e| Failure::solver(format!("plot: {e}")).into_py(py))?;
        let charts = charts.into_iter();
        Ok(charts
            .map(|(file, chart)| (file, chart.to_json().to_string()))
            .collect())
    }

    /// The trajectory at `rate` samples per second, as `solve --export` writes it: the columns'
    /// names and each column's values.
    #[allow(clippy::type_complexity)]
    fn resample<'py>(
        &self,
        py: Python<'py>,
        rate: f64,
    ) -> PyResult<(Vec<String>, Vec<Bound<'py, PyArray1<f64>>>)> {
        let formulation = self.formulation(py, "resample")?;
        let table = resample(formulation, &self.document.result, rate).map_err(|e| {
            match e {
                ExportError::Rate(_) => Failure::input(format!("rate={rate}: {e}")),
                _ => Failure::solver(format!("resample: {e}")),
            }
            .into_py(py)
        })?;
        let columns = table.columns.into_iter();
        let columns = columns.map(|column| PyArray1::from_vec(py, column));
        Ok((table.names, columns.collect()))
    }

    /// The moving joints' names, base outward (the columns of the joint arrays).
    fn joint_names(&self) -> Vec<String> {
        self.document.result.joints.clone()
    }

    /// The motors' names (the task's `motors.names`, else `motor 1`, `motor 2`, ...).
    fn motor_names(&self) -> Vec<String> {
        let count = self.document.inputs.task.task.transmission.matrix.len();
        match &self.document.inputs.task.task.motors.names {
            Some(names) => names.clone(),
            None => (1..=count).map(|i| format!("motor {i}")).collect(),
        }
    }

    /// The document as JSON text, as `solve --out` writes it (without the final newline).
    fn json(&self, py: Python<'_>) -> PyResult<String> {
        document_json(&self.document)
            .map_err(|e| Failure::solver(format!("result not encoded: {e}")).into_py(py))
    }

    /// Whether the design is feasible.
    fn feasible(&self) -> bool {
        self.document.result.feasible
    }

    /// Why it is infeasible (None when feasible).
    fn reason(&self) -> Option<String> {
        self.document.result.reason.clone()
    }

    /// The optimal cost J.
    fn cost(&self) -> f64 {
        self.document.result.cost
    }

    /// J by term: (position, velocity, control, cartesian_box), where recorded.
    fn cost_terms(&self) -> Option<(f64, f64, f64, f64)> {
        let terms = self.document.result.cost_terms.as_ref()?;
        Some((
            terms.position,
            terms.velocity,
            terms.control,
            terms.cartesian_box,
        ))
    }

    /// The physical figures (per motor and in total) as JSON, where recorded.
    fn figures(&self) -> Option<String> {
        let figures = self.document.result.figures.as_ref()?;
        serde_json::to_string(figures).ok()
    }

    /// dJ*/dr, where feasible.
    fn cost_gradient(&self) -> Option<Vec<f64>> {
        self.document.result.cost_gradient.clone()
    }

    /// IPOPT's status, its iterations, the design, the payload (kg), the space, the task hash.
    fn summary(&self) -> (String, usize, Vec<f64>, f64, String, String) {
        let (result, inputs) = (&self.document.result, &self.document.inputs);
        (
            result.status.clone(),
            result.iterations,
            result.ratios.clone(),
            inputs.payload_kg,
            inputs.space.name().to_owned(),
            inputs.task_hash.0.clone().unwrap_or_default(),
        )
    }

    /// For a transmission whose ratio changes with the pose: each motor's angle per node
    /// (N+1, m) and G(q) per node, flat ((N+1) m n values, motor-major within a node); None for
    /// a constant one.
    #[allow(clippy::type_complexity)]
    fn linkage_arrays<'py>(
        &self,
        py: Python<'py>,
    ) -> Option<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>)> {
        let t = &self.document.result.trajectory;
        let m = t.motor_position.first()?.len();
        let flat: Vec<f64> = t.ratio.iter().flatten().flatten().copied().collect();
        Some((rows(py, &t.motor_position, m), PyArray1::from_vec(py, flat)))
    }

    /// The trajectory as arrays: t (N+1), q, v (N+1, n), a, tau (N, n), tau_u (N, m),
    /// motor_speed (N+1, m), tcp (N+1, 3).
    #[allow(clippy::type_complexity)]
    fn arrays<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, [Bound<'py, PyArray2<f64>>; 7]) {
        let t = &self.document.result.trajectory;
        let n = t.q.first().map_or(0, Vec::len);
        let m = t.motor_speed.first().map_or(0, Vec::len);
        let tcp: Vec<Vec<f64>> = (0..t.time.len())
            .map(|k| {
                let at = |axis: &[f64]| axis.get(k).copied().unwrap_or(f64::NAN);
                vec![at(&t.tcp_x), at(&t.tcp_y), at(&t.tcp_z)]
            })
            .collect();
        (
            PyArray1::from_slice(py, &t.time),
            [
                rows(py, &t.q, n),
                rows(py, &t.v, n),
                rows(py, &t.a, n),
                rows(py, &t.joint_torque, n),
                rows(py, &t.motor_torque, m),
                rows(py, &t.motor_speed, m),
                rows(py, &tcp, 3),
            ],
        )
    }
}
