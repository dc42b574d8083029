//! Timings of the dynamics of the belt arm (payload 1 kg): median ns per call over batches.
//!
//! Run with `cargo bench --bench dynamics`. Each call is made at another of 51 random states (as
//! the 51 nodes of a trajectory), so results cached for the previous state are never reused; the
//! per-node set evaluates everything one node needs at one state, reusing what the calls share.

use codesign::stats::median;
use codesign_core::dynamics::Dynamics;
use codesign_core::model::task::Task;
use codesign_core::model::Robot;
use codesign_core::transmission::linkage::{Linkage, RowDerivatives, RowShape};
use nalgebra::DMatrix;
use std::hint::black_box;
use std::time::Instant;

const NODES: usize = 51;
const BATCHES: usize = 21;
const CALLS_PER_BATCH: usize = 20 * NODES;

/// A node's state: q, v, a and the multipliers lambda.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
}

/// Caller-side outputs, allocated once.
struct Outputs {
    tau: Vec<f64>,
    dtau_dq: DMatrix<f64>,
    dtau_dv: DMatrix<f64>,
    mass: DMatrix<f64>,
    hessian: DMatrix<f64>,
    jacobian: DMatrix<f64>,
    tcp_hessians: [DMatrix<f64>; 3],
}

impl Outputs {
    /// Outputs for `n` joints.
    fn new(n: usize) -> Outputs {
        let square = || DMatrix::zeros(n, n);
        Outputs {
            tau: vec![0.0; n],
            dtau_dq: square(),
            dtau_dv: square(),
            mass: square(),
            hessian: DMatrix::zeros(3 * n, 3 * n),
            jacobian: DMatrix::zeros(3, n),
            tcp_hessians: [square(), square(), square()],
        }
    }
}

fn states(n: usize) -> Vec<State> {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |scale: f64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        scale * ((seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
    };
    (0..NODES)
        .map(|_| State {
            q: (0..n).map(|_| next(3.0)).collect(),
            v: (0..n).map(|_| next(5.0)).collect(),
            a: (0..n).map(|_| next(20.0)).collect(),
            lambda: (0..n).map(|_| next(1.0)).collect(),
        })
        .collect()
}

/// Times `call(k)` for k = 0, 1, ... and prints the median, min and max ns per call over batches.
fn bench(name: &str, mut call: impl FnMut(usize)) {
    for k in 0..CALLS_PER_BATCH {
        call(k);
    }
    let mut per_call: Vec<f64> = (0..BATCHES)
        .map(|_| {
            let start = Instant::now();
            for k in 0..CALLS_PER_BATCH {
                call(k);
            }
            start.elapsed().as_nanos() as f64 / CALLS_PER_BATCH as f64
        })
        .collect();
    per_call.sort_by(f64::total_cmp);
    println!(
        "{name:<58} median {:>8.1} ns/call   (min {:.1}, max {:.1})",
        median(&per_call),
        per_call[0],
        per_call[BATCHES - 1]
    );
}

fn main() {
    let task = Task::built_in().expect("the built-in task loads");
    let robot = Robot::load(&task).unwrap().with_payload(1.0);
    let dynamics = Dynamics::new(robot);
    let mut data = dynamics.workspace();
    let n = dynamics.dof();
    let states = states(n);
    let mut out = Outputs::new(n);
    println!("belt arm, {n} joints, payload 1 kg; {BATCHES} batches of {CALLS_PER_BATCH} calls");
    let state = |k: usize| &states[k % NODES];

    bench("rnea", |k| {
        let s = state(k);
        dynamics.rnea(&mut data, &s.q, &s.v, &s.a, &mut out.tau);
        black_box(&out.tau);
    });
    bench("rnea_derivatives (tau, dtau/dq, dtau/dv, M)", |k| {
        let s = state(k);
        dynamics.rnea_derivatives(
            &mut data,
            &s.q,
            &s.v,
            &s.a,
            &mut out.tau,
            &mut out.dtau_dq,
            &mut out.dtau_dv,
            &mut out.mass,
        );
        black_box(&out.dtau_dq);
    });
    bench("rnea_hessian (12 x 12)", |k| {
        let s = state(k);
        dynamics.rnea_hessian(&mut data, &s.q, &s.v, &s.a, &s.lambda, &mut out.hessian);
        black_box(&out.hessian);
    });
    bench("tcp terms (position, Jacobian, 3 Hessians)", |k| {
        let s = state(k);
        black_box(dynamics.tcp_position(&mut data, &s.q));
        dynamics.tcp_jacobian(&mut data, &s.q, &mut out.jacobian);
        dynamics.tcp_hessians(&mut data, &s.q, &mut out.tcp_hessians);
        black_box((&out.jacobian, &out.tcp_hessians));
    });
    bench(
        "per-node set (rnea_derivatives + rnea_hessian + tcp terms)",
        |k| {
            let s = state(k);
            dynamics.rnea_derivatives(
                &mut data,
                &s.q,
                &s.v,
                &s.a,
                &mut out.tau,
                &mut out.dtau_dq,
                &mut out.dtau_dv,
                &mut out.mass,
            );
            dynamics.rnea_hessian(&mut data, &s.q, &s.v, &s.a, &s.lambda, &mut out.hessian);
            black_box(dynamics.tcp_position(&mut data, &s.q));
            dynamics.tcp_jacobian(&mut data, &s.q, &mut out.jacobian);
            dynamics.tcp_hessians(&mut data, &s.q, &mut out.tcp_hessians);
            black_box((&out.dtau_dq, &out.hessian, &out.tcp_hessians));
        },
    );
    linkages(&dynamics, &mut data, &states);
    bench("mass_matrix", |k| {
        dynamics.mass_matrix(&mut data, &state(k).q, &mut out.mass);
        black_box(&out.mass);
    });
    bench("forward_dynamics", |k| {
        let s = state(k);
        dynamics.forward_dynamics(&mut data, &s.q, &s.v, &s.a, &mut out.tau);
        black_box(&out.tau);
    });
}

/// The derivatives one pose-dependent row of G needs per node (docs/model.md, section 17), on
/// the belt arm: a ball screw across the elbow (one joint) and a crank on the upper arm with a
/// rod to the forearm (two joints), to the third and the fourth order, at poses within 0.05 rad
/// of the zero pose, where the rod reaches.
fn linkages(dynamics: &Dynamics, data: &mut codesign_core::dynamics::Workspace, states: &[State]) {
    let screw = r#"{"linear": {"from": {"link": "link_1", "point": [0.25, 0.05, 0]},
        "to": {"link": "link_2", "point": [0.1, 0.04, 0]}, "lead_m": 0.01}}"#;
    let crank = r#"{"crank_rod": {"crank": {"link": "link_1", "point": [0.3, 0.06, 0],
        "axis": [0, 0, 1], "radius_m": 0.03, "ratio": 10}, "rod_m": 0.55,
        "to": {"link": "link_3", "point": [0.05, 0.02, 0]}}}"#;
    let original = [1.0; 4];
    for (name, text) in [("screw, 1 joint", screw), ("crank-rod, 2 joints", crank)] {
        let spec = serde_json::from_str(text).expect("a linkage row");
        let linkage = Linkage::resolve(&spec, 0, dynamics, &original).expect("it resolves");
        for order in [3, 4] {
            let label = format!("linkage row to order {order} ({name})");
            let shape = RowShape::new(&linkage, order);
            bench(&label, |k| {
                let q: Vec<f64> = states[k % NODES].q.iter().map(|q| q / 60.0).collect();
                let row = RowDerivatives::of(&linkage, &shape, dynamics, data, (&q, &original));
                black_box(row.expect("the linkage closes near the zero pose"));
            });
        }
    }
}
