//! Checks of the dynamics: the reference vectors of `tests/data/dynamics_vectors.json`
//! (Pinocchio and an independent symbolic RNEA) for the belt arm, and central finite differences
//! of this module's own functions for the belt arm and random 6-joint chains with skew axes (one
//! with two prismatic joints).

use super::Dynamics;
use crate::model::chain::JointKind;
use crate::model::task::Task;
use crate::model::Robot;
use crate::testing::{self, Random};
use nalgebra::DMatrix;
use serde::Deserialize;

fn default_task() -> Task {
    testing::task()
}

fn belt_arm(payload_kg: f64) -> Dynamics {
    Dynamics::new(
        Robot::load(&default_task())
            .unwrap()
            .with_payload(payload_kg),
    )
}

// ---------------------------------------------------------------------------------------------
// Reference vectors

#[derive(Deserialize)]
struct Vectors {
    cases: Vec<Case>,
}

#[derive(Deserialize)]
struct Case {
    payload_kg: f64,
    samples: Vec<Sample>,
}

#[derive(Deserialize)]
struct Sample {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    #[serde(rename = "lambda_")]
    lambda: Vec<f64>,
    tau: Vec<f64>,
    mass_matrix: Vec<Vec<f64>>,
    nonlinear_effects: Vec<f64>,
    gravity: Vec<f64>,
    forward_dynamics_of_tau: Vec<f64>,
    dtau_dq: Vec<Vec<f64>>,
    dtau_dv: Vec<Vec<f64>>,
    tcp_position: Vec<f64>,
    tcp_jacobian: Vec<Vec<f64>>,
    tcp_hessian_y: Vec<Vec<f64>>,
    tcp_hessian_z: Vec<Vec<f64>>,
    hessian_lambda_tau: Vec<Vec<f64>>,
}

fn rows(matrix: &DMatrix<f64>) -> Vec<Vec<f64>> {
    matrix
        .row_iter()
        .map(|row| row.iter().copied().collect())
        .collect()
}

/// The agreement the reference promises, 1e-9 relative, measured against the field's scale:
/// |got - want| <= 1e-9 * max(|want|, largest |entry| of the reference field). Entries far below
/// the field's scale (e.g. 1e-16 where the field is of order 1) are thus held to 1e-9 of the scale.
fn assert_field(context: &str, field: &str, got: &[Vec<f64>], want: &[Vec<f64>]) {
    assert_eq!(got.len(), want.len(), "{context} {field}: row count");
    let scale = want.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for (r, (got_row, want_row)) in got.iter().zip(want).enumerate() {
        assert_eq!(got_row.len(), want_row.len(), "{context} {field}: length");
        for (c, (g, w)) in got_row.iter().zip(want_row).enumerate() {
            let tolerance = 1e-9 * w.abs().max(scale);
            assert!(
                (g - w).abs() <= tolerance,
                "{context} {field}[{r}][{c}]: got {g:e}, reference {w:e} (off by {:e}, allowed {tolerance:e})",
                (g - w).abs()
            );
        }
    }
}

fn load_vectors() -> Vectors {
    let path = crate::testing::repository().join("tests/data/dynamics_vectors.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

#[test]
fn every_field_of_every_reference_sample_agrees() {
    let vectors = load_vectors();
    assert_eq!(vectors.cases.len(), 3);
    for case in &vectors.cases {
        let dynamics = belt_arm(case.payload_kg);
        let mut data = dynamics.workspace();
        let n = dynamics.dof();
        for (k, s) in case.samples.iter().enumerate() {
            let context = format!("payload {} kg, sample {k}", case.payload_kg);
            let check = |field: &str, got: Vec<Vec<f64>>, want: &[Vec<f64>]| {
                assert_field(&context, field, &got, want)
            };
            let vector = |x: &[f64]| vec![x.to_vec()];
            let mut tau = vec![0.0; n];
            let mut dq = DMatrix::zeros(n, n);
            let mut dv = DMatrix::zeros(n, n);
            let mut mass = DMatrix::zeros(n, n);
            dynamics.rnea_derivatives(
                &mut data, &s.q, &s.v, &s.a, &mut tau, &mut dq, &mut dv, &mut mass,
            );
            check("tau (rnea_derivatives)", vector(&tau), &vector(&s.tau));
            check("dtau_dq", rows(&dq), &s.dtau_dq);
            check("dtau_dv", rows(&dv), &s.dtau_dv);
            check(
                "mass_matrix (rnea_derivatives)",
                rows(&mass),
                &s.mass_matrix,
            );
            dynamics.rnea(&mut data, &s.q, &s.v, &s.a, &mut tau);
            check("tau", vector(&tau), &vector(&s.tau));
            dynamics.mass_matrix(&mut data, &s.q, &mut mass);
            check("mass_matrix", rows(&mass), &s.mass_matrix);
            let mut b = vec![0.0; n];
            dynamics.nonlinear_effects(&mut data, &s.q, &s.v, &mut b);
            check(
                "nonlinear_effects",
                vector(&b),
                &vector(&s.nonlinear_effects),
            );
            dynamics.gravity_torques(&mut data, &s.q, &mut b);
            check("gravity", vector(&b), &vector(&s.gravity));
            let mut a = vec![0.0; n];
            dynamics.forward_dynamics(&mut data, &s.q, &s.v, &s.tau, &mut a);
            check(
                "forward_dynamics_of_tau",
                vector(&a),
                &vector(&s.forward_dynamics_of_tau),
            );
            let p = dynamics.tcp_position(&mut data, &s.q);
            check(
                "tcp_position",
                vector(p.as_slice()),
                &vector(&s.tcp_position),
            );
            let mut jacobian = DMatrix::zeros(3, n);
            dynamics.tcp_jacobian(&mut data, &s.q, &mut jacobian);
            check("tcp_jacobian", rows(&jacobian), &s.tcp_jacobian);
            let mut hessians = [
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
            ];
            dynamics.tcp_hessians(&mut data, &s.q, &mut hessians);
            check("tcp_hessian_y", rows(&hessians[1]), &s.tcp_hessian_y);
            check("tcp_hessian_z", rows(&hessians[2]), &s.tcp_hessian_z);
            let mut hessian = DMatrix::zeros(3 * n, 3 * n);
            dynamics.rnea_hessian(&mut data, &s.q, &s.v, &s.a, &s.lambda, &mut hessian);
            check("hessian_lambda_tau", rows(&hessian), &s.hessian_lambda_tau);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Finite differences

/// The joint types of the random chain: revolute, with a continuous joint.
const TURNING: [&str; 6] = [
    "revolute",
    "revolute",
    "revolute",
    "continuous",
    "revolute",
    "revolute",
];

/// The random chain with two prismatic joints: one inside the chain (its slide moves the axes of
/// the joints after it) and the last (it moves only the TCP's body).
const SLIDING: [&str; 6] = [
    "revolute",
    "prismatic",
    "revolute",
    "continuous",
    "revolute",
    "prismatic",
];

/// A random 6-joint chain of the joint types `kinds`: skew axes, rotated joint frames, random
/// full inertias, a fixed joint in the middle of a body.
fn random_chain_urdf(random: &mut Random, kinds: [&str; 6]) -> String {
    let mut text = String::from("<robot name=\"random\">\n");
    let link = |name: &str, random: &mut Random| {
        // Principal moments meeting the triangle inequality (any two of [0.03, 0.05] add up to
        // more than the third), turned by a random rotation.
        let principal = [
            random.real(0.03..0.05),
            random.real(0.03..0.05),
            random.real(0.03..0.05),
        ];
        let rotation = nalgebra::Rotation3::from_euler_angles(
            random.real(-3.0..3.0),
            random.real(-1.5..1.5),
            random.real(-3.0..3.0),
        );
        let inertia = rotation.matrix()
            * nalgebra::Matrix3::from_diagonal(&principal.into())
            * rotation.matrix().transpose();
        format!(
            "<link name=\"{name}\"><inertial><origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/>\
             <mass value=\"{}\"/><inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>\
             </inertial></link>\n",
            random.real(-0.2..0.2),
            random.real(-0.2..0.2),
            random.real(-0.2..0.2),
            random.real(-3.0..3.0),
            random.real(-1.5..1.5),
            random.real(-3.0..3.0),
            random.real(0.5..3.0),
            inertia[(0, 0)],
            inertia[(0, 1)],
            inertia[(0, 2)],
            inertia[(1, 1)],
            inertia[(1, 2)],
            inertia[(2, 2)],
        )
    };
    let joint = |name: &str, kind: &str, parent: &str, child: &str, random: &mut Random| {
        format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/>\
             <origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/><axis xyz=\"{} {} {}\"/>\
             <limit lower=\"-2\" upper=\"2.5\" effort=\"1\" velocity=\"1\"/></joint>\n",
            random.real(-0.4..0.4),
            random.real(-0.4..0.4),
            random.real(-0.4..0.4),
            random.real(-3.0..3.0),
            random.real(-1.5..1.5),
            random.real(-3.0..3.0),
            random.real(-1.0..1.0),
            random.real(-1.0..1.0),
            random.real(0.2..1.0),
        )
    };
    text += &link("base", random);
    let mut parent = "base".to_owned();
    for k in 1..=6 {
        let child = format!("l{k}");
        text += &link(&child, random);
        text += &joint(&format!("j{k}"), kinds[k - 1], &parent, &child, random);
        parent = child;
        if k == 3 {
            text += &link("l3b", random);
            text += &joint("j3_fixed", "fixed", "l3", "l3b", random);
            parent = "l3b".to_owned();
        }
    }
    text + "</robot>\n"
}

fn random_chain(payload_kg: f64) -> Dynamics {
    random_chain_of(payload_kg, TURNING)
}

fn random_chain_of(payload_kg: f64, kinds: [&str; 6]) -> Dynamics {
    let mut random = Random::new(7);
    let urdf = random_chain_urdf(&mut random, kinds);
    let mut task = default_task();
    task.gravity = [1.2, -3.4, -8.7];
    task.tcp.link = "l6".into();
    task.tcp.point = [0.05, -0.1, 0.2];
    task.payload.at.link = "l6".into();
    task.payload.at.point = [0.1, 0.0, -0.05];
    task.payload.mass_kg = payload_kg;
    Dynamics::new(Robot::from_urdf_str(&urdf, "random.urdf", &task).unwrap())
}

/// Central differences of `f` (R^m -> R^k) at x, column per input.
fn central_differences(x: &[f64], k: usize, mut f: impl FnMut(&[f64], &mut [f64])) -> DMatrix<f64> {
    let step = 1e-6;
    let mut out = DMatrix::zeros(k, x.len());
    let (mut plus, mut minus) = (vec![0.0; k], vec![0.0; k]);
    let mut shifted = x.to_vec();
    for c in 0..x.len() {
        shifted[c] = x[c] + step;
        f(&shifted, &mut plus);
        shifted[c] = x[c] - step;
        f(&shifted, &mut minus);
        shifted[c] = x[c];
        for r in 0..k {
            out[(r, c)] = (plus[r] - minus[r]) / (2.0 * step);
        }
    }
    out
}

/// max |got - want| <= relative * max |want| + absolute (the absolute part for the rounding noise
/// of differences: about 1e-16 * |f| / step, i.e. 1e-9 for torques of order 10 N m).
fn assert_matrix(
    context: &str,
    got: &DMatrix<f64>,
    want: &DMatrix<f64>,
    relative: f64,
    absolute: f64,
) {
    assert_eq!(got.shape(), want.shape(), "{context}: shape");
    let scale = want.amax();
    let error = (got - want).amax();
    assert!(
        error <= relative * scale + absolute,
        "{context}: off by {error:e} at scale {scale:e}\ngot {got}\nwant {want}"
    );
}

/// Every derivative against central differences of the function it differentiates, at random
/// states: dtau/dq, dtau/dv, M (and the mass matrix, b, g and forward dynamics against RNEA), the
/// Hessian against differences of the analytic gradient, the TCP Jacobian and Hessians.
fn check_against_differences(dynamics: Dynamics, seed: u64) {
    let n = dynamics.dof();
    let mut data = dynamics.workspace();
    let mut random = Random::new(seed);
    for _ in 0..5 {
        let q = random.vector(n, 3.0);
        let v = random.vector(n, 4.0);
        let a = random.vector(n, 10.0);
        let lambda = random.vector(n, 1.0);
        let mut tau = vec![0.0; n];
        let mut dq = DMatrix::zeros(n, n);
        let mut dv = DMatrix::zeros(n, n);
        let mut mass = DMatrix::zeros(n, n);
        dynamics.rnea_derivatives(&mut data, &q, &v, &a, &mut tau, &mut dq, &mut dv, &mut mass);
        let mut rnea = dynamics.workspace();
        let fd_q = central_differences(&q, n, |x, out| dynamics.rnea(&mut rnea, x, &v, &a, out));
        assert_matrix("dtau/dq", &dq, &fd_q, 1e-7, 1e-8);
        let fd_v = central_differences(&v, n, |x, out| dynamics.rnea(&mut rnea, &q, x, &a, out));
        assert_matrix("dtau/dv", &dv, &fd_v, 1e-7, 1e-8);
        let fd_a = central_differences(&a, n, |x, out| dynamics.rnea(&mut rnea, &q, &v, x, out));
        assert_matrix("dtau/da", &mass, &fd_a, 1e-7, 1e-8);
        let mut crba = DMatrix::zeros(n, n);
        dynamics.mass_matrix(&mut data, &q, &mut crba);
        assert_matrix("CRBA", &crba, &mass, 1e-13, 0.0);
        let (mut b, mut g, mut expected) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        dynamics.nonlinear_effects(&mut data, &q, &v, &mut b);
        dynamics.rnea(&mut data, &q, &v, &vec![0.0; n], &mut expected);
        assert_matrix("b", &column(&b), &column(&expected), 1e-13, 0.0);
        dynamics.gravity_torques(&mut data, &q, &mut g);
        dynamics.rnea(&mut data, &q, &vec![0.0; n], &vec![0.0; n], &mut expected);
        assert_matrix("g", &column(&g), &column(&expected), 1e-13, 0.0);
        let mut solved = vec![0.0; n];
        dynamics.forward_dynamics(&mut data, &q, &v, &tau, &mut solved);
        assert_matrix(
            "forward dynamics",
            &column(&solved),
            &column(&a),
            1e-10,
            0.0,
        );

        // The Hessian against differences of the analytic gradient (lambda^T of each derivative).
        let mut hessian = DMatrix::zeros(3 * n, 3 * n);
        dynamics.rnea_hessian(&mut data, &q, &v, &a, &lambda, &mut hessian);
        assert_matrix("Hessian symmetry", &hessian, &hessian.transpose(), 0.0, 0.0);
        let mut state = q.clone();
        state.extend(&v);
        state.extend(&a);
        let mut gradient_of = dynamics.workspace();
        let fd = central_differences(&state, 3 * n, |x, out| {
            let (mut t, mut gq, mut gv, mut m) = (
                vec![0.0; n],
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
            );
            let (xq, rest) = x.split_at(n);
            let (xv, xa) = rest.split_at(n);
            dynamics.rnea_derivatives(
                &mut gradient_of,
                xq,
                xv,
                xa,
                &mut t,
                &mut gq,
                &mut gv,
                &mut m,
            );
            let l = DMatrix::from_column_slice(1, n, &lambda);
            for (block, matrix) in [gq, gv, m].iter().enumerate() {
                let row = &l * matrix;
                out[block * n..(block + 1) * n].copy_from_slice(row.as_slice());
            }
        });
        assert_matrix("Hessian of lambda . tau", &hessian, &fd, 1e-7, 1e-8);

        // The TCP.
        let mut jacobian = DMatrix::zeros(3, n);
        dynamics.tcp_jacobian(&mut data, &q, &mut jacobian);
        let mut position_of = dynamics.workspace();
        let fd = central_differences(&q, 3, |x, out| {
            out.copy_from_slice(dynamics.tcp_position(&mut position_of, x).as_slice())
        });
        assert_matrix("TCP Jacobian", &jacobian, &fd, 1e-8, 1e-9);
        let mut hessians = [
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        ];
        dynamics.tcp_hessians(&mut data, &q, &mut hessians);
        for (axis, hessian) in hessians.iter().enumerate() {
            let mut jacobian_of = dynamics.workspace();
            let fd = central_differences(&q, n, |x, out| {
                let mut j = DMatrix::zeros(3, n);
                dynamics.tcp_jacobian(&mut jacobian_of, x, &mut j);
                for (o, value) in out.iter_mut().zip(j.row(axis).iter()) {
                    *o = *value;
                }
            });
            assert_matrix(&format!("TCP Hessian {axis}"), hessian, &fd, 1e-8, 1e-9);
        }

        // A direction fixed to a middle body and to the last.
        let d = nalgebra::Vector3::new(0.3, -0.5, 0.8);
        for body in [Some(n / 2), Some(n - 1)] {
            let mut jacobian = DMatrix::zeros(3, n);
            dynamics.direction_jacobian(&mut data, &q, (body, &d), &mut jacobian);
            let mut of = dynamics.workspace();
            let fd = central_differences(&q, 3, |x, out| {
                out.copy_from_slice(dynamics.direction_world(&mut of, x, body, &d).as_slice())
            });
            assert_matrix("direction Jacobian", &jacobian, &fd, 1e-8, 1e-9);
            let mut hessians = [0, 1, 2].map(|_| DMatrix::zeros(n, n));
            dynamics.direction_hessians(&mut data, &q, (body, &d), &mut hessians);
            for (axis, hessian) in hessians.iter().enumerate() {
                let fd = central_differences(&q, n, |x, out| {
                    let mut j = DMatrix::zeros(3, n);
                    dynamics.direction_jacobian(&mut of, x, (body, &d), &mut j);
                    for (o, value) in out.iter_mut().zip(j.row(axis).iter()) {
                        *o = *value;
                    }
                });
                assert_matrix(
                    &format!("direction Hessian {axis}"),
                    hessian,
                    &fd,
                    1e-8,
                    1e-9,
                );
            }
        }
    }
}

fn column(x: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(x.len(), 1, x)
}

#[test]
fn belt_arm_derivatives_match_finite_differences() {
    for payload in [0.0, 3.0] {
        check_against_differences(belt_arm(payload), 11);
    }
}

#[test]
fn random_six_joint_chain_derivatives_match_finite_differences() {
    let dynamics = random_chain(0.7);
    assert_eq!(dynamics.dof(), 6);
    assert_eq!(
        dynamics.robot().position_limits()[3],
        (f64::NEG_INFINITY, f64::INFINITY)
    );
    check_against_differences(dynamics, 23);
}

#[test]
fn random_chain_with_prismatic_joints_derivatives_match_finite_differences() {
    let dynamics = random_chain_of(0.7, SLIDING);
    for j in [1, 5] {
        assert_eq!(dynamics.robot().joint_kind(j), JointKind::Prismatic);
    }
    check_against_differences(dynamics, 29);
}

#[test]
fn a_prismatic_joint_slides_its_body_along_its_axis() {
    let dynamics = random_chain_of(0.0, SLIDING);
    let mut data = dynamics.workspace();
    let q = [0.3, 0.2, -0.4, 1.0, 0.5, -0.3];
    let mut slid = q;
    slid[1] += 0.25;
    let before = dynamics.body_pose(&mut data, &q, Some(1));
    let after = dynamics.body_pose(&mut data, &slid, Some(1));
    let axis = before.rotation * dynamics.bodies[1].axis;
    assert!((after.rotation - before.rotation).amax() < 1e-15);
    assert!((after.translation - before.translation - axis * 0.25).amax() < 1e-14);
}

/// A polar (RP) arm in the horizontal x-y plane, gravity along -y: a revolute joint about z,
/// then a prismatic joint along the turning x axis; each link's centre of mass on that axis.
const POLAR_ARM: &str = r#"<robot name="polar">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.2 0 0"/><mass value="1.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.03"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="0.8"/>
    <inertia ixx="0.004" ixy="0" ixz="0" iyy="0.005" iyz="0" izz="0.005"/></inertial></link>
  <joint name="turn" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="slide" type="prismatic"><parent link="l1"/><child link="l2"/>
    <axis xyz="1 0 0"/><limit lower="-0.5" upper="0.8" effort="50" velocity="1"/></joint>
</robot>"#;

#[test]
fn a_polar_arm_follows_its_lagrange_equations() {
    let mut task = default_task();
    task.gravity = [0.0, -9.81, 0.0];
    task.tcp.link = "l2".into();
    task.payload.at.link = "l2".into();
    task.payload.mass_kg = 0.0;
    let dynamics = Dynamics::new(Robot::from_urdf_str(POLAR_ARM, "polar.urdf", &task).unwrap());
    assert_eq!(dynamics.robot().joint_kind(1), JointKind::Prismatic);
    let (m1, d, i1, m2, c, i2, g) = (1.5, 0.2, 0.03, 0.8, 0.1, 0.005, 9.81);
    let mut data = dynamics.workspace();
    let mut tau = [0.0; 2];
    let mut random = Random::new(5);
    for _ in 0..5 {
        let q = random.vector(2, 1.0);
        let v = random.vector(2, 2.0);
        let a = random.vector(2, 3.0);
        dynamics.rnea(&mut data, &q, &v, &a, &mut tau);
        let (theta, rho) = (q[0], q[1] + c);
        // T = (I1 + m1 d^2 + I2 + m2 rho^2) thetadot^2 / 2 + m2 rdot^2 / 2,
        // V = (m1 d + m2 rho) g sin(theta).
        let turn = (i1 + m1 * d * d + i2 + m2 * rho * rho) * a[0]
            + 2.0 * m2 * rho * v[1] * v[0]
            + (m1 * d + m2 * rho) * g * theta.cos();
        let push = m2 * a[1] - m2 * rho * v[0] * v[0] + m2 * g * theta.sin();
        assert!((tau[0] - turn).abs() < 1e-12, "{} against {turn}", tau[0]);
        assert!((tau[1] - push).abs() < 1e-12, "{} against {push}", tau[1]);
    }
}

#[test]
#[should_panic(expected = "did not make it")]
fn a_workspace_of_another_model_is_refused() {
    let (one, other) = (belt_arm(0.0), belt_arm(1.0));
    let mut data = one.workspace();
    other.tcp_position(&mut data, &[0.0; 4]);
}

// ---------------------------------------------------------------------------------------------
// Point jets

/// The world pose of `body` at q by forward kinematics in jet arithmetic (Rodrigues' formula on
/// jets of the angles): an independent computation of what `fixed_jet` gives in closed form.
fn pose_by_jets<'s>(
    dynamics: &Dynamics,
    q: &[f64],
    body: usize,
    joints: std::ops::Range<usize>,
    shape: &'s crate::jet::JetShape,
) -> ([[crate::jet::Jet<'s>; 3]; 3], [crate::jet::Jet<'s>; 3]) {
    use crate::jet::Jet;
    let constant = |v: f64| Jet::constant(shape, v);
    let mut rotation =
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| constant(if i == j { 1.0 } else { 0.0 })));
    let mut translation = [0, 1, 2].map(|_| constant(0.0));
    for (k, model) in dynamics.bodies.iter().enumerate().take(body + 1) {
        let placement = &model.joint_placement;
        translation = [0, 1, 2].map(|i| {
            (0..3).fold(translation[i].clone(), |sum, j| {
                &sum + &(&rotation[i][j] * placement.translation[j])
            })
        });
        let joint = [0, 1, 2].map(|i| {
            [0, 1, 2].map(|j| {
                (0..3).fold(constant(0.0), |sum, l| {
                    &sum + &(&rotation[i][l] * placement.rotation[(l, j)])
                })
            })
        });
        let angle = if joints.contains(&k) {
            Jet::variable(shape, k - joints.start, q[k])
        } else {
            constant(q[k])
        };
        if model.kind == JointKind::Prismatic {
            translation = [0, 1, 2].map(|i| {
                (0..3).fold(translation[i].clone(), |sum, j| {
                    &sum + &(&(&joint[i][j] * model.axis[j]) * &angle)
                })
            });
            rotation = joint;
            continue;
        }
        let (sin, cos) = angle.sin_cos();
        let versine = cos.scaled(-1.0, 1.0);
        let turn = [0, 1, 2].map(|i| {
            [0, 1, 2].map(|j| {
                let identity = constant(if i == j { 1.0 } else { 0.0 });
                let sine = &sin * model.axis_cross[(i, j)];
                let square = &versine * model.axis_cross_squared[(i, j)];
                &(&identity + &sine) + &square
            })
        });
        rotation = [0, 1, 2].map(|i| {
            [0, 1, 2]
                .map(|j| (0..3).fold(constant(0.0), |sum, l| &sum + &(&joint[i][l] * &turn[l][j])))
        });
    }
    (rotation, translation)
}

#[test]
fn point_and_direction_jets_match_forward_kinematics_in_jets() {
    for kinds in [TURNING, SLIDING] {
        jets_match_forward_kinematics_in_jets(&random_chain_of(0.0, kinds));
    }
}

fn jets_match_forward_kinematics_in_jets(dynamics: &Dynamics) {
    use super::Fixed;
    use crate::jet::JetShape;
    let q = [0.3, -0.7, 1.1, 0.4, -1.3, 0.9];
    let mut data = dynamics.workspace();
    let local = nalgebra::Vector3::new(0.12, -0.3, 0.07);
    for (joints, body, order) in [(0..6, 5, 4), (2..5, 4, 4), (1..3, 4, 3), (0..4, 1, 4)] {
        let shape = JetShape::new(joints.len(), 1, order);
        let (rotation, translation) = pose_by_jets(dynamics, &q, body, joints.clone(), &shape);
        for vector in [Fixed::Point(local), Fixed::Direction(local)] {
            let jet = dynamics.fixed_jet(&mut data, &q, Some(body), vector, joints.clone(), &shape);
            for i in 0..3 {
                let mut expected = (0..3).fold(crate::jet::Jet::constant(&shape, 0.0), |sum, j| {
                    &sum + &(&rotation[i][j] * local[j])
                });
                if let Fixed::Point(_) = vector {
                    expected = &expected + &translation[i];
                }
                for (m, (a, b)) in jet.0[i]
                    .coefficients()
                    .iter()
                    .zip(expected.coefficients())
                    .enumerate()
                {
                    assert!(
                        (a - b).abs() < 1e-12,
                        "{vector:?} on body {body}, joints {joints:?}, coordinate {i}, monomial {:?}: {a} against {b}",
                        shape.monomials()[m]
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Derivatives in the inertial parameters

/// RNEA's derivative along the carried parts' change with a ratio (the planar example's pulley,
/// whose teeth follow r2, beside a motor of fixed mass) matches central differences of RNEA of
/// the robot carrying the parts at r2 +- h, gravity and velocity terms included; a ratio that
/// moves no part changes nothing.
#[test]
fn rnea_inertia_derivative_matches_central_differences() {
    use crate::model::carried::CarriedModel;
    let task = testing::carried_task();
    let robot = Robot::load(&task).unwrap();
    let carried = CarriedModel::on_chain(&task.carried, robot.chain(), 2).unwrap();
    let base = Dynamics::new(robot);
    let mut random = Random::new(53);
    for r in [[50.0, 12.0], [30.0, 25.0], [80.0, 6.5]] {
        let q: Vec<f64> = (0..2).map(|_| random.real(-2.0..2.0)).collect();
        let v: Vec<f64> = (0..2).map(|_| random.real(-3.0..3.0)).collect();
        let a: Vec<f64> = (0..2).map(|_| random.real(-5.0..5.0)).collect();
        let rnea_at = |r: &[f64]| {
            let carrying = base.with_carried(&carried.mass_properties(r));
            let mut tau = vec![0.0; 2];
            carrying.rnea(&mut carrying.workspace(), &q, &v, &a, &mut tau);
            tau
        };
        let h = 1e-4 * r[1];
        let (up, down) = (rnea_at(&[r[0], r[1] + h]), rnea_at(&[r[0], r[1] - h]));
        let mut analytic = vec![0.0; 2];
        let parts = carried.derivative(&r, 1);
        let mut data = base.workspace();
        base.rnea_inertia_derivative(&mut data, (&q, &v, &a), &parts, &mut analytic);
        for j in 0..2 {
            let central = (up[j] - down[j]) / (2.0 * h);
            let error = (analytic[j] - central).abs();
            assert!(
                error <= 1e-6 * central.abs().max(1e-4),
                "r {r:?} joint {j}: analytic {} central {central}",
                analytic[j]
            );
        }
        assert!(analytic[0].abs() > 1e-5, "{analytic:?}");
        assert!(carried.derivative(&r, 0).is_empty());
    }
}
