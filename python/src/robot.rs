//! `NativeRobot`: the core's robot model and its dynamics (`codesign_core::model::Robot`,
//! `codesign_core::dynamics::Dynamics`), loaded from a URDF or from a task, with its joints,
//! inverse dynamics, mass matrix and TCP kinematics; and, for a task's robot, its transmission:
//! G at a design and a pose.

use crate::errors::{Failure, Outcome};
use crate::solution::rows;
use crate::task::NativeTask;
use codesign_core::dynamics::Dynamics;
use codesign_core::model::Robot;
use codesign_core::text::number;
use codesign_core::transmission::Transmission;
use nalgebra::DMatrix;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A robot and, where it comes from a task, that task's transmission (see `codesign.Robot`).
#[pyclass(module = "codesign._native", frozen)]
pub struct NativeRobot {
    dynamics: Dynamics,
    transmission: Option<Transmission>,
}

/// A matrix as a 2-D array.
fn matrix<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    let values: Vec<Vec<f64>> = m
        .row_iter()
        .map(|row| row.iter().copied().collect())
        .collect();
    rows(py, &values, m.ncols())
}

impl NativeRobot {
    /// `values` (keyword `name`) checked: one finite number per joint.
    fn joints<'v>(&self, name: &str, values: &'v [f64]) -> Outcome<&'v [f64]> {
        let n = self.dynamics.dof();
        if values.len() != n {
            return Err(Failure::input(format!(
                "{name}: {} values for a robot of {n} joints",
                values.len()
            )));
        }
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(Failure::input(format!(
                "{name}[{i}] = {} is not a finite number",
                number(values[i])
            ))),
            None => Ok(values),
        }
    }
}

#[pymethods]
impl NativeRobot {
    /// The robot of the URDF at `path` alone: gravity 9.81 m/s^2 down world z, the TCP at the
    /// origin of its chain's tip link, no payload, no transmission.
    #[staticmethod]
    fn from_urdf(py: Python<'_>, path: PathBuf) -> PyResult<NativeRobot> {
        let robot =
            Robot::from_urdf(&path).map_err(|e| Failure::input(e.to_string()).into_py(py))?;
        Ok(NativeRobot {
            dynamics: Dynamics::new(robot),
            transmission: None,
        })
    }

    /// The robot of `task` (its URDF, gravity, TCP and payload, `payload` kg instead where given)
    /// with the task's transmission.
    #[staticmethod]
    #[pyo3(signature = (task, payload=None))]
    fn of_task(py: Python<'_>, task: &NativeTask, payload: Option<f64>) -> PyResult<NativeRobot> {
        let read = || -> Outcome<NativeRobot> {
            let mut robot = task.read.robot.clone();
            if let Some(kg) = payload {
                codesign_core::model::task::check_payload(kg)
                    .map_err(|e| Failure::input(format!("payload={}: {e}", number(kg))))?;
                robot = robot.with_payload(kg);
            }
            let dynamics = Dynamics::new(robot);
            let spec = &task.read.file.task.transmission;
            let transmission = Transmission::on_chain(spec, &dynamics)
                .map_err(|e| Failure::input(format!("task: {e}")))?;
            Ok(NativeRobot {
                dynamics,
                transmission: Some(transmission),
            })
        };
        read().map_err(|e| e.into_py(py))
    }

    /// The moving joints' names, from the base outward.
    fn joint_names(&self) -> Vec<String> {
        self.dynamics.robot().joint_names().to_vec()
    }

    /// Each joint's position limits (lower, upper), rad (m for a prismatic joint).
    fn position_limits(&self) -> Vec<(f64, f64)> {
        self.dynamics.robot().position_limits().to_vec()
    }

    /// The payload carried, kg.
    fn payload(&self) -> f64 {
        self.dynamics.robot().payload_kg()
    }

    /// Inverse dynamics tau = M(q) a + b(q, v), N m.
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        v: Vec<f64>,
        a: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let checked = || -> Outcome<Vec<f64>> {
            let (q, v, a) = (
                self.joints("q", &q)?,
                self.joints("v", &v)?,
                self.joints("a", &a)?,
            );
            let mut tau = vec![0.0; q.len()];
            let mut data = self.dynamics.workspace();
            self.dynamics.rnea(&mut data, q, v, a, &mut tau);
            Ok(tau)
        };
        Ok(PyArray1::from_vec(
            py,
            checked().map_err(|e| e.into_py(py))?,
        ))
    }

    /// The joint-space mass matrix M(q), kg m^2, n x n.
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.joints("q", &q).map_err(|e| e.into_py(py))?;
        let n = q.len();
        let mut mass = DMatrix::zeros(n, n);
        self.dynamics
            .mass_matrix(&mut self.dynamics.workspace(), q, &mut mass);
        Ok(matrix(py, &mass))
    }

    /// The TCP's world position (m) and its Jacobian d p / d q (3 x n) at q.
    #[allow(clippy::type_complexity)]
    fn tcp<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>)> {
        let q = self.joints("q", &q).map_err(|e| e.into_py(py))?;
        let mut data = self.dynamics.workspace();
        let position = self.dynamics.tcp_position(&mut data, q);
        let mut jacobian = DMatrix::zeros(3, q.len());
        self.dynamics.tcp_jacobian(&mut data, q, &mut jacobian);
        Ok((
            PyArray1::from_vec(py, position.iter().copied().collect()),
            matrix(py, &jacobian),
        ))
    }

    /// The task's transmission's original design and the bounds of its ratios; None for a
    /// robot read from a URDF alone.
    #[allow(clippy::type_complexity)]
    fn design(&self) -> Option<(Vec<f64>, Vec<(f64, f64)>)> {
        let t = self.transmission.as_ref()?;
        let bounds = t.bounds().iter().map(|&[lo, hi]| (lo, hi)).collect();
        Some((t.original().to_vec(), bounds))
    }

    /// G (motors x joints) at the design `ratios` and the pose q (rad): motor speeds are G v.
    /// A constant G does not depend on q; a linkage's does.
    fn ratio_matrix<'py>(
        &self,
        py: Python<'py>,
        ratios: Vec<f64>,
        q: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let at = || -> Outcome<DMatrix<f64>> {
            let t = self.transmission.as_ref().ok_or_else(|| {
                Failure::input(
                    "a robot read from a URDF alone has no transmission: use Task.robot()",
                )
            })?;
            let q = self.joints("q", &q)?;
            let coupling = t
                .coupling_at(&ratios, (&self.dynamics, q), "the pose q")
                .map_err(|e| Failure::input(format!("ratios: {e}")))?;
            Ok(coupling.matrix().clone())
        };
        Ok(matrix(py, &at().map_err(|e| e.into_py(py))?))
    }
}
