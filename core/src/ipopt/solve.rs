//! One solve: the problem handed to IPOPT through its C interface, the linear solver made ready,
//! and the solution read back. The problem's description lives in `problem.rs`, the guarded
//! callbacks in `callbacks.rs`.

use super::callbacks::{intermediate, Context};
use super::problem::{apply_options, Point, Shape};
use super::{Error, LinearSolver, Nlp, Options, Status};
use ipopt_sys as sys;
use std::ffi::c_void;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// MUMPS keeps global state and is not thread-safe: every solve with it in this process holds
/// this lock from the creation of its IPOPT problem to its release. Solves with
/// [`LinearSolver::Ldl`] keep all their state in their own IPOPT objects and do not take it.
static MUMPS_LOCK: Mutex<()> = Mutex::new(());

/// Wall-clock time of a solve, split into time spent in the problem's callbacks and the rest
/// (IPOPT itself: linear algebra, line search, bookkeeping).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// From the creation of the IPOPT problem to its release.
    pub total: Duration,
    /// Summed time inside the evaluation callbacks.
    pub callbacks: Duration,
    /// `total - callbacks`.
    pub ipopt: Duration,
}

/// The result of a solve that ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// IPOPT's return status.
    pub status: Status,
    /// The final primal point (length n).
    pub x: Vec<f64>,
    /// The constraint values g(x) at the final point (length m).
    pub g: Vec<f64>,
    /// Multipliers of the constraints (length m), in IPOPT's sign convention.
    pub lambda: Vec<f64>,
    /// Multipliers of the lower variable bounds (length n, >= 0).
    pub z_lower: Vec<f64>,
    /// Multipliers of the upper variable bounds (length n, >= 0).
    pub z_upper: Vec<f64>,
    /// f(x) at the final point.
    pub objective: f64,
    /// Iterations taken (the last iteration index IPOPT reported).
    pub iterations: usize,
    /// Where the time went.
    pub timing: Timing,
    /// Why the last point IPOPT could not evaluate lay outside the problem's domain (a linkage
    /// that does not close there), None if it evaluated every point it tried.
    pub outside_domain: Option<String>,
}

/// Solves `problem` with `options`, starting from [`Nlp::initial_point`].
///
/// Solves with MUMPS are serialised process-wide (MUMPS is not thread-safe): a second thread
/// calling this with MUMPS waits until the first has finished. Solves with the LDLᵀ run at once.
pub fn solve<P: Nlp>(problem: &mut P, options: &Options) -> Result<Solution, Error> {
    solve_from(problem, options, None)
}

/// Solves `problem` warm-started from an earlier solution of a problem of the same shape: its
/// primal point replaces [`Nlp::initial_point`] and its multipliers seed IPOPT's
/// (`warm_start_init_point = yes`). Without `start`, the same as [`solve`].
pub fn solve_from<P: Nlp>(
    problem: &mut P,
    options: &Options,
    warm: Option<&Solution>,
) -> Result<Solution, Error> {
    let _guard = linear_solver_ready(options.linear_solver)?;
    let start = Instant::now();
    let shape = Shape::of(problem)?;
    let mut point = Point::start(problem, warm, &shape)?;
    let mut options = options.clone();
    if warm.is_some() {
        options = options.str("warm_start_init_point", "yes");
    }
    let handle = shape.create::<P>()?;
    apply_options(&handle, &options)?;
    // SAFETY: the handle is valid; the callback has the signature IPOPT expects.
    unsafe { sys::SetIntermediateCallback(handle.0, Some(intermediate::<P>)) };

    let mut context = Context {
        problem,
        jacobian: shape.jacobian,
        hessian: shape.hessian,
        callback_time: Duration::ZERO,
        iterations: 0,
        error: None,
        stopped: false,
        outside_domain: None,
    };
    let mut g = vec![0.0; shape.m];
    let mut objective = f64::NAN;
    // SAFETY: all output arrays have the sizes IPOPT was given; the context outlives the call and
    // is only touched through the user-data pointer while IPOPT runs.
    let code = unsafe {
        sys::IpoptSolve(
            handle.0,
            point.x.as_mut_ptr(),
            g.as_mut_ptr(),
            &mut objective,
            point.lambda.as_mut_ptr(),
            point.z_lower.as_mut_ptr(),
            point.z_upper.as_mut_ptr(),
            (&mut context as *mut Context<P>).cast::<c_void>(),
        )
    };
    drop(handle);
    let total = start.elapsed();

    if let Some(error) = context.error {
        return Err(error);
    }
    if context.stopped {
        return Err(Error::Stopped);
    }
    let status = Status::from_code(code);
    if status == Status::InvalidOption {
        // Options whose values are checked only when the solve starts.
        return Err(Error::OptionsAtStart);
    }
    Ok(Solution {
        status,
        x: point.x,
        g,
        lambda: point.lambda,
        z_lower: point.z_lower,
        z_upper: point.z_upper,
        objective,
        iterations: usize::try_from(context.iterations).unwrap_or(0),
        timing: Timing {
            total,
            callbacks: context.callback_time,
            ipopt: total.saturating_sub(context.callback_time),
        },
        outside_domain: context.outside_domain,
    })
}

/// Makes the linear solver ready: takes the process-wide lock for MUMPS (held by the returned
/// guard until the solve ends), installs the LDLᵀ into IPOPT once per process.
fn linear_solver_ready(solver: LinearSolver) -> Result<Option<MutexGuard<'static, ()>>, Error> {
    match solver {
        LinearSolver::Mumps => Ok(Some(
            MUMPS_LOCK
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner()),
        )),
        LinearSolver::Ldl => {
            crate::ldl::install().map_err(|e| Error::LinearSolver {
                solver,
                message: e.to_string(),
            })?;
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::{check_derivatives, DerivativeOrder, EvalError, Hs071};
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    /// HS071 with something wrong in one callback.
    struct Faulty {
        fault: Fault,
        active: Option<Arc<AtomicUsize>>,
        max_active: Option<Arc<AtomicUsize>>,
        /// Whether callbacks wait for a second solve to be inside one too.
        meet: bool,
    }

    enum Fault {
        None,
        PanicInHessian,
        ErrorInConstraints,
        WrongGradient,
    }

    impl Faulty {
        fn new(fault: Fault) -> Faulty {
            Faulty {
                fault,
                active: None,
                max_active: None,
                meet: false,
            }
        }

        /// Counts how many solves are inside a callback at the same moment. With `meet`, until two
        /// have met there, a callback waits up to a second for another solve to come in.
        fn enter(&self) {
            if let (Some(active), Some(max)) = (&self.active, &self.max_active) {
                let now = active.fetch_add(1, Ordering::SeqCst) + 1;
                max.fetch_max(now, Ordering::SeqCst);
                let waited = Instant::now();
                while self.meet
                    && max.load(Ordering::SeqCst) < 2
                    && waited.elapsed() < Duration::from_secs(1)
                {
                    std::thread::sleep(Duration::from_micros(50));
                }
                std::thread::sleep(Duration::from_micros(50));
                active.fetch_sub(1, Ordering::SeqCst);
            }
        }
    }

    impl Nlp for Faulty {
        fn num_variables(&self) -> usize {
            4
        }
        fn num_constraints(&self) -> usize {
            2
        }
        fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            Hs071.variable_bounds(lower, upper)
        }
        fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            Hs071.constraint_bounds(lower, upper)
        }
        fn initial_point(&self, x: &mut [f64]) {
            Hs071.initial_point(x)
        }
        fn objective(&mut self, x: &[f64], new_x: bool) -> Result<f64, EvalError> {
            self.enter();
            Hs071.objective(x, new_x)
        }
        fn gradient(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
            Hs071.gradient(x, new_x, g)?;
            if let Fault::WrongGradient = self.fault {
                g[2] += 0.5;
            }
            Ok(())
        }
        fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
            if let Fault::ErrorInConstraints = self.fault {
                return Err(EvalError::from("constraint evaluation refused"));
            }
            Hs071.constraints(x, new_x, g)
        }
        fn jacobian_structure(&self) -> Vec<(usize, usize)> {
            Hs071.jacobian_structure()
        }
        fn jacobian_values(
            &mut self,
            x: &[f64],
            new_x: bool,
            v: &mut [f64],
        ) -> Result<(), EvalError> {
            Hs071.jacobian_values(x, new_x, v)
        }
        fn hessian_structure(&self) -> Vec<(usize, usize)> {
            Hs071.hessian_structure()
        }
        fn hessian_values(
            &mut self,
            x: &[f64],
            new_x: bool,
            obj_factor: f64,
            lambda: &[f64],
            values: &mut [f64],
        ) -> Result<(), EvalError> {
            if let Fault::PanicInHessian = self.fault {
                panic!("hessian exploded");
            }
            Hs071.hessian_values(x, new_x, obj_factor, lambda, values)
        }
    }

    /// min x0 + x1 with x0 + x1 >= 3 inside the box [0, 1]^2: no feasible point.
    struct Infeasible;

    impl Nlp for Infeasible {
        fn num_variables(&self) -> usize {
            2
        }
        fn num_constraints(&self) -> usize {
            1
        }
        fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            lower.fill(0.0);
            upper.fill(1.0);
        }
        fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            lower[0] = 3.0;
            upper[0] = f64::INFINITY;
        }
        fn initial_point(&self, x: &mut [f64]) {
            x.fill(0.5);
        }
        fn objective(&mut self, x: &[f64], _: bool) -> Result<f64, EvalError> {
            Ok(x[0] + x[1])
        }
        fn gradient(&mut self, _: &[f64], _: bool, g: &mut [f64]) -> Result<(), EvalError> {
            g.fill(1.0);
            Ok(())
        }
        fn constraints(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> Result<(), EvalError> {
            g[0] = x[0] * x[0] + x[1];
            Ok(())
        }
        fn jacobian_structure(&self) -> Vec<(usize, usize)> {
            vec![(0, 0), (0, 1)]
        }
        fn jacobian_values(&mut self, x: &[f64], _: bool, v: &mut [f64]) -> Result<(), EvalError> {
            v[0] = 2.0 * x[0];
            v[1] = 1.0;
            Ok(())
        }
        fn hessian_structure(&self) -> Vec<(usize, usize)> {
            vec![(0, 0)]
        }
        fn hessian_values(
            &mut self,
            _: &[f64],
            _: bool,
            _: f64,
            lambda: &[f64],
            values: &mut [f64],
        ) -> Result<(), EvalError> {
            values[0] = 2.0 * lambda[0];
            Ok(())
        }
    }

    #[test]
    fn a_warm_start_from_the_optimum_converges_at_once() {
        let cold = solve(&mut Hs071, &Options::new()).unwrap();
        let warm = solve_from(
            &mut Hs071,
            &Options::new()
                .num("mu_init", 1e-9)
                .num("warm_start_bound_push", 1e-9),
            Some(&cold),
        )
        .unwrap();
        assert_eq!(warm.status, Status::SolveSucceeded);
        assert!((warm.objective - cold.objective).abs() < 1e-6);
        assert!(
            warm.iterations < cold.iterations,
            "{} vs {}",
            warm.iterations,
            cold.iterations
        );
        let mut other = Infeasible;
        assert!(matches!(
            solve_from(&mut other, &Options::new(), Some(&cold)),
            Err(Error::InvalidProblem(_))
        ));
    }

    /// A solve whose work was asked to stop ends in an error, not in a solution with a
    /// status; a solve under no token, or another token, is not stopped by it.
    #[test]
    fn a_stopped_solve_is_an_error_and_stops_no_other_work() {
        use crate::signals::{under, StopToken};
        let stopped = StopToken::new();
        stopped.stop();
        let outcome = under(Some(stopped), || solve(&mut Hs071, &Options::new()));
        assert_eq!(outcome, Err(Error::Stopped));
        let other = under(Some(StopToken::new()), || {
            solve(&mut Hs071, &Options::new())
        });
        assert_eq!(other.unwrap().status, Status::SolveSucceeded);
        assert_eq!(
            solve(&mut Hs071, &Options::new()).unwrap().status,
            Status::SolveSucceeded
        );
    }

    #[test]
    fn infeasible_problem_is_reported_as_infeasible() {
        let solution = solve(&mut Infeasible, &Options::new()).unwrap();
        assert_eq!(solution.status, Status::InfeasibleProblemDetected);
        assert!(!solution.status.is_success());
    }

    #[test]
    fn panic_in_a_callback_becomes_an_error() {
        let error = solve(&mut Faulty::new(Fault::PanicInHessian), &Options::new()).unwrap_err();
        match error {
            Error::Callback { callback, message } => {
                assert_eq!(callback, "hessian");
                assert!(message.contains("hessian exploded"), "{message}");
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn error_in_a_callback_stops_the_solve() {
        let error =
            solve(&mut Faulty::new(Fault::ErrorInConstraints), &Options::new()).unwrap_err();
        assert_eq!(
            error,
            Error::Callback {
                callback: "constraints",
                message: "constraint evaluation refused".to_owned()
            }
        );
    }

    #[test]
    fn bad_options_are_rejected_by_name() {
        let unknown = solve(&mut Hs071, &Options::new().num("tolerance_of_doom", 1.0));
        assert!(
            matches!(&unknown, Err(Error::InvalidOption { name, .. }) if name == "tolerance_of_doom"),
            "{unknown:?}"
        );
        let wrong_value = solve(&mut Hs071, &Options::new().str("mu_strategy", "sideways"));
        assert!(
            matches!(&wrong_value, Err(Error::InvalidOption { name, .. }) if name == "mu_strategy"),
            "{wrong_value:?}"
        );
        let wrong_type = solve(&mut Hs071, &Options::new().str("tol", "small"));
        assert!(
            matches!(wrong_type, Err(Error::InvalidOption { .. })),
            "{wrong_type:?}"
        );
        // A whole number for a real option is taken as a number.
        let whole = solve(&mut Hs071, &Options::new().int("max_cpu_time", 100));
        assert!(whole.is_ok_and(|s| s.status.is_success()));
    }

    #[test]
    fn derivative_checker_catches_a_wrong_gradient() {
        let mut problem = Faulty::new(Fault::WrongGradient);
        let report =
            check_derivatives(&mut problem, &Options::new(), DerivativeOrder::First).unwrap();
        assert!(report.errors >= 1, "{report:?}");
        assert!(
            report.flagged.iter().any(|line| line.contains("grad_f")),
            "{report:?}"
        );
    }

    #[test]
    fn concurrent_mumps_solves_are_serialised() {
        let active = Arc::new(AtomicUsize::new(0));
        let max_active = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..4)
            .map(|_| {
                let (active, max_active) = (Arc::clone(&active), Arc::clone(&max_active));
                std::thread::spawn(move || {
                    let mut problem = Faulty {
                        fault: Fault::None,
                        active: Some(active),
                        max_active: Some(max_active),
                        meet: false,
                    };
                    (0..5)
                        .map(|_| {
                            solve(
                                &mut problem,
                                &Options::new().linear_solver(LinearSolver::Mumps),
                            )
                            .unwrap()
                            .objective
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for thread in threads {
            for objective in thread.join().unwrap() {
                assert!((objective - crate::ipopt::HS071_OPTIMUM).abs() < 1e-6);
            }
        }
        assert_eq!(max_active.load(Ordering::SeqCst), 1);
    }

    #[test]
    fn ldl_solves_on_two_threads_run_at_once_and_match_one_after_the_other() {
        let options = Options::new().linear_solver(LinearSolver::Ldl);
        let sequential: Vec<Solution> = (0..2)
            .map(|_| solve(&mut Faulty::new(Fault::None), &options).unwrap())
            .collect();
        let active = Arc::new(AtomicUsize::new(0));
        let max_active = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..2)
            .map(|_| {
                let (active, max_active) = (Arc::clone(&active), Arc::clone(&max_active));
                let options = options.clone();
                std::thread::spawn(move || {
                    let mut problem = Faulty {
                        fault: Fault::None,
                        active: Some(active),
                        max_active: Some(max_active),
                        meet: true,
                    };
                    solve(&mut problem, &options).unwrap()
                })
            })
            .collect();
        for (thread, alone) in threads.into_iter().zip(&sequential) {
            let together = thread.join().unwrap();
            assert_eq!(together.x, alone.x);
            assert_eq!(together.lambda, alone.lambda);
            assert_eq!(together.iterations, alone.iterations);
        }
        // Each callback waits up to a second for the other thread to be inside one too.
        assert_eq!(max_active.load(Ordering::SeqCst), 2);
    }
}
