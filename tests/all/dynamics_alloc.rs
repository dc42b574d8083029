//! The dynamics allocate nothing per call once the outputs have their shapes: counted by a global
//! allocator, on this thread only.

use codesign_core::dynamics::Dynamics;
use codesign_core::model::task::Task;
use codesign_core::model::Robot;
use nalgebra::DMatrix;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        System.dealloc(pointer, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(|count| count.get())
}

#[test]
fn evaluating_nodes_allocates_nothing() {
    let task = Task::built_in().expect("the built-in task loads");
    let dynamics = Dynamics::new(Robot::load(&task).unwrap().with_payload(1.0));
    let mut data = dynamics.workspace();
    let n = dynamics.dof();
    let mut tau = vec![0.0; n];
    let mut a = vec![0.0; n];
    let (mut dq, mut dv, mut mass) = (
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
    );
    let mut hessian = DMatrix::zeros(3 * n, 3 * n);
    let mut jacobian = DMatrix::zeros(3, n);
    let mut tcp_hessians = [
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
    ];
    let mut evaluate = |k: usize| {
        let x = k as f64 * 0.37;
        let q = [x.sin(), x.cos(), 0.5 * x, -x];
        let v = [1.0, -x, 0.3, 2.0];
        let acceleration = [x, 2.0, -1.0, 0.5];
        let lambda = [0.2, -0.4, x, 1.0];
        dynamics.rnea(&mut data, &q, &v, &acceleration, &mut tau);
        dynamics.rnea_derivatives(
            &mut data,
            &q,
            &v,
            &acceleration,
            &mut tau,
            &mut dq,
            &mut dv,
            &mut mass,
        );
        dynamics.rnea_hessian(&mut data, &q, &v, &acceleration, &lambda, &mut hessian);
        dynamics.mass_matrix(&mut data, &q, &mut mass);
        dynamics.nonlinear_effects(&mut data, &q, &v, &mut tau);
        dynamics.gravity_torques(&mut data, &q, &mut tau);
        dynamics.forward_dynamics(&mut data, &q, &v, &tau, &mut a);
        std::hint::black_box(dynamics.tcp_position(&mut data, &q));
        dynamics.tcp_jacobian(&mut data, &q, &mut jacobian);
        dynamics.tcp_hessians(&mut data, &q, &mut tcp_hessians);
    };
    // The first calls size the caches.
    evaluate(0);
    let before = allocations();
    for k in 1..100 {
        evaluate(k);
    }
    assert_eq!(allocations() - before, 0);
}
