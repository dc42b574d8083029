//! Linkages against geometry computed another way (distances of world points, the loop closed by
//! bisection) and their derivatives against central differences.

use super::crank_rod::CrankNumbers;
use super::*;
use crate::model::matrix_row::Branch;
use crate::model::Robot;
use crate::testing;
use nalgebra::Vector3;

/// A 3-joint arm with skew axes and rotated link frames: a shoulder about z, an upper arm, a
/// forearm and a hand (l3), a bracket fixed to the upper arm.
const URDF: &str = r#"<robot name="linkages">
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="bracket"/>
  <link name="l2"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l3"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="fix" type="fixed"><parent link="l1"/><child link="bracket"/>
    <origin xyz="0.05 0.02 0.01" rpy="0.3 -0.2 0.5"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.3 0 0" rpy="0.1 0 0.2"/><axis xyz="0.1 1 0.2"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0.03 0" rpy="0 0.3 0"/><axis xyz="0 0.3 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;

fn dynamics() -> Dynamics {
    let mut task = testing::task();
    task.tcp.link = "l3".into();
    task.payload.at.link = "l3".into();
    Dynamics::new(Robot::from_urdf_str(URDF, "linkages.urdf", &task).unwrap())
}

fn anchor(dynamics: &Dynamics, link: &str, coordinates: [Entry; 3]) -> Anchor {
    let chain = dynamics.robot().chain();
    let frame = chain.links.iter().find(|f| f.name == link).unwrap();
    Anchor::new(frame, coordinates)
}

fn constant(v: [f64; 3]) -> [Entry; 3] {
    v.map(Entry::Constant)
}

fn ratio(index: usize, scale: f64) -> Entry {
    Entry::Ratio { index, scale }
}

/// A screw from the bracket (x a design parameter) to the hand, lead 4 mm * r1.
fn screw(dynamics: &Dynamics) -> Linkage {
    Linkage::Linear(LinearActuator {
        from: anchor(
            dynamics,
            "bracket",
            [ratio(0, 1.0), Entry::Constant(0.04), Entry::Constant(0.0)],
        ),
        to: anchor(dynamics, "l3", constant([0.1, -0.02, 0.05])),
        lead: ratio(1, 0.004),
        stroke: None,
    })
}

/// A crank on the bracket (radius r1 * 0.05, rod r3) driving a point of the forearm.
fn crank(dynamics: &Dynamics, branch: Branch) -> Linkage {
    let crank = anchor(dynamics, "bracket", constant([0.0, 0.0, 0.0]));
    let to = anchor(
        dynamics,
        "l2",
        [Entry::Constant(0.08), ratio(0, 0.2), Entry::Constant(0.0)],
    );
    let numbers = CrankNumbers {
        radius: ratio(1, 0.05),
        ratio: Entry::Constant(-12.0),
        rod: ratio(2, 1.0),
    };
    let axis = Vector3::new(0.2, 0.1, 1.0);
    let r = design();
    Linkage::CrankRod(CrankRod::new(crank, axis, numbers, to, branch, (dynamics, &r)).unwrap())
}

fn design() -> Vec<f64> {
    vec![0.05, 2.5, 0.32]
}

const Q: [f64; 3] = [0.4, 0.7, -0.5];

/// The angle's jet to `order` in every joint the linkage spans and all its parameters.
fn jet_at(
    dynamics: &Dynamics,
    linkage: &Linkage,
    q: &[f64],
    r: &[f64],
    order: usize,
) -> (Variables, Vec<f64>) {
    let variables = Variables {
        joints: linkage.joints(),
        parameters: linkage.parameters(),
    };
    let shape = variables.shape(order);
    let mut data = dynamics.workspace();
    let jet = linkage
        .angle(dynamics, &mut data, (q, r), &variables, &shape)
        .unwrap();
    (variables, jet.coefficients().to_vec())
}

fn derivative(dynamics: &Dynamics, linkage: &Linkage, q: &[f64], r: &[f64], of: &[usize]) -> f64 {
    let (variables, coefficients) = jet_at(dynamics, linkage, q, r, of.len().max(1));
    let shape = variables.shape(of.len().max(1));
    Jet::from_coefficients(&shape, coefficients).derivative(of)
}

#[test]
fn a_screw_turns_its_motor_two_pi_per_lead_of_length() {
    let dynamics = dynamics();
    let linkage = screw(&dynamics);
    let Linkage::Linear(screw) = &linkage else {
        unreachable!()
    };
    assert_eq!(linkage.joints(), 1..3);
    assert_eq!(linkage.parameters(), vec![0, 1]);
    let r = design();
    let mut data = dynamics.workspace();
    let ends = [&screw.from, &screw.to].map(|a| {
        let point = crate::model::chain::PointOnBody {
            body: a.body(),
            point: a.on_body(&r),
        };
        dynamics.point_position(&mut data, &Q, &point)
    });
    let expected = std::f64::consts::TAU * (ends[1] - ends[0]).norm() / (0.004 * r[1]);
    let (_, coefficients) = jet_at(&dynamics, &linkage, &Q, &r, 0);
    assert!((coefficients[0] - expected).abs() < 1e-12 * expected);
}

/// The crank angle that closes the loop, found by bisection on the distance from pin to rod end
/// over the branch's half turn from the line of centres.
fn closed_by_bisection(dynamics: &Dynamics, crank: &CrankRod, q: &[f64], r: &[f64]) -> f64 {
    let mut data = dynamics.workspace();
    let pose = dynamics.body_pose(&mut data, q, crank.crank.body());
    let centre = pose.apply(&crank.crank.on_body(r));
    let end_pose = dynamics.body_pose(&mut data, q, crank.to.body());
    let end = end_pose.apply(&crank.to.on_body(r));
    let [e1, e2] = crank.across.map(|d| pose.rotation * d);
    let (a, b) = (crank.radius.value(r), crank.rod.value(r));
    let w = end - centre;
    let line = w.dot(&e2).atan2(w.dot(&e1));
    let gap = |theta: f64| (centre + (e1 * theta.cos() + e2 * theta.sin()) * a - end).norm() - b;
    let sign = crank.branch.sign();
    // From the line of centres (pin nearest the end: gap < 0) to half a turn away (gap > 0).
    let (mut low, mut high) = (0.0, std::f64::consts::PI);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if gap(line + sign * middle) < 0.0 {
            low = middle
        } else {
            high = middle
        }
    }
    line + sign * 0.5 * (low + high)
}

#[test]
fn a_crank_closes_its_loop_on_its_branch() {
    let dynamics = dynamics();
    for branch in [Branch::Positive, Branch::Negative] {
        let linkage = crank(&dynamics, branch);
        let Linkage::CrankRod(crank) = &linkage else {
            unreachable!()
        };
        assert_eq!(linkage.joints(), 1..2);
        assert_eq!(linkage.parameters(), vec![0, 1, 2]);
        for q in [Q, [0.0; 3], [-1.0, -0.3, 2.0]] {
            let r = design();
            let expected = -12.0 * closed_by_bisection(&dynamics, crank, &q, &r);
            let (_, coefficients) = jet_at(&dynamics, &linkage, &q, &r, 0);
            let found = coefficients[0];
            let turns = ((found - expected) / (-12.0 * std::f64::consts::TAU)).round();
            assert!(
                (found - expected - turns * -12.0 * std::f64::consts::TAU).abs() < 1e-9,
                "{branch:?} at {q:?}: {found} against {expected}"
            );
        }
    }
}

/// The points that draw a linkage: a screw's ends are its length apart; a crank's pin is its
/// radius from its centre and its rod's length from the rod's end.
#[test]
fn a_linkages_drawn_points_keep_its_lengths() {
    let dynamics = dynamics();
    let r = design();
    let mut data = dynamics.workspace();
    let linkage = screw(&dynamics);
    let ends = linkage
        .drawn_points(&dynamics, &mut data, (&Q, &r))
        .unwrap();
    let variables = Variables {
        joints: linkage.joints(),
        parameters: Vec::new(),
    };
    let shape = variables.shape(0);
    let length = linkage
        .measure(&dynamics, &mut data, (&Q, &r), &variables, &shape)
        .unwrap()
        .value();
    assert_eq!(ends.len(), 2);
    assert!(((ends[1] - ends[0]).norm() - length).abs() < 1e-12);
    for branch in [Branch::Positive, Branch::Negative] {
        let points = crank(&dynamics, branch)
            .drawn_points(&dynamics, &mut data, (&Q, &r))
            .unwrap();
        let [centre, pin, end] = [points[0], points[1], points[2]];
        assert!(
            ((pin - centre).norm() - 0.05 * r[1]).abs() < 1e-12,
            "{branch:?}"
        );
        assert!(((end - pin).norm() - r[2]).abs() < 1e-9, "{branch:?}");
    }
    let short = [0.05, 2.5, 0.01];
    let open = crank(&dynamics, Branch::Positive).drawn_points(&dynamics, &mut data, (&Q, &short));
    assert!(matches!(open, Err(LinkageError::Open { .. })), "{open:?}");
}

/// Central differences of the jet's derivative `of` minus its last variable, in that variable,
/// against the jet's derivative `of`; variables beyond the joints are design parameters.
fn check_by_differences(dynamics: &Dynamics, linkage: &Linkage, of: &[usize]) {
    let (variables, _) = jet_at(dynamics, linkage, &Q, &design(), 0);
    let (&last, lower) = of.split_last().unwrap();
    let h = 1e-5;
    let shifted = |sign: f64| {
        let (mut q, mut r) = (Q.to_vec(), design());
        match last.checked_sub(variables.joints.len()) {
            None => q[variables.joints.start + last] += sign * h,
            Some(p) => r[variables.parameters[p]] += sign * h,
        }
        derivative(dynamics, linkage, &q, &r, lower)
    };
    let difference = (shifted(1.0) - shifted(-1.0)) / (2.0 * h);
    let exact = derivative(dynamics, linkage, &Q, &design(), of);
    assert!(
        (exact - difference).abs() <= 1e-6 * (1.0 + exact.abs()),
        "d{of:?}: {exact} against {difference}"
    );
}

#[test]
fn screw_and_crank_derivatives_match_central_differences() {
    let dynamics = dynamics();
    let screw = screw(&dynamics);
    // Joints 1 and 2 are variables 0 and 1; r1 and r2 are 2 and 3.
    for of in [
        &[0][..],
        &[1],
        &[2],
        &[3],
        &[0, 1],
        &[1, 1],
        &[0, 2],
        &[1, 3],
        &[0, 0, 1],
        &[0, 1, 1, 1],
        &[0, 0, 1, 2],
    ] {
        check_by_differences(&dynamics, &screw, of);
    }
    let crank = crank(&dynamics, Branch::Negative);
    // Joint 1 is variable 0; r1, r2 and r3 are 1, 2 and 3.
    for of in [
        &[0][..],
        &[1],
        &[2],
        &[3],
        &[0, 0],
        &[0, 1],
        &[0, 3],
        &[0, 0, 0],
        &[0, 0, 2],
        &[0, 0, 0, 0],
        &[0, 0, 0, 1],
    ] {
        check_by_differences(&dynamics, &crank, of);
    }
}

#[test]
fn a_rod_too_short_leaves_the_loop_open() {
    let dynamics = dynamics();
    let linkage = crank(&dynamics, Branch::Positive);
    let variables = Variables {
        joints: linkage.joints(),
        parameters: vec![],
    };
    let shape = variables.shape(2);
    let mut data = dynamics.workspace();
    let mut r = design();
    r[2] = 0.01;
    match linkage.angle(&dynamics, &mut data, (&Q, &r), &variables, &shape) {
        Err(LinkageError::Open { reach }) => assert!(reach > 1.0),
        other => panic!("{other:?}"),
    }
    r[2] = -0.3;
    assert!(matches!(
        linkage.angle(&dynamics, &mut data, (&Q, &r), &variables, &shape),
        Err(LinkageError::Length {
            what: "rod length",
            ..
        })
    ));
}

fn resolve(dynamics: &Dynamics, text: &str) -> Result<Linkage, ResolveError> {
    let spec: crate::model::matrix_row::LinkageSpec = serde_json::from_str(text).unwrap();
    Linkage::resolve(&spec, 1, dynamics, &design())
}

#[test]
fn rows_of_the_task_resolve_to_the_same_linkages() {
    let dynamics = dynamics();
    let written = r#"{"linear": {"from": {"link": "bracket", "point": ["r1", 0.04, 0]},
        "to": {"link": "l3", "point": [0.1, -0.02, 0.05]}, "lead_m": "0.004*r2"}}"#;
    assert_eq!(resolve(&dynamics, written).unwrap(), screw(&dynamics));
    let written = r#"{"crank_rod": {"crank": {"link": "bracket", "point": [0, 0, 0],
        "axis": [0.2, 0.1, 1], "radius_m": "0.05*r2", "ratio": -12}, "rod_m": "r3",
        "to": {"link": "l2", "point": [0.08, "0.2*r1", 0]}, "branch": "negative"}}"#;
    assert_eq!(
        resolve(&dynamics, written).unwrap(),
        crank(&dynamics, Branch::Negative)
    );
}

#[test]
fn a_wrong_field_of_a_linkage_row_is_named() {
    let dynamics = dynamics();
    let cases = [
        (
            r#"{"linear": {"from": {"link": "l9", "point": [0, 0, 0]}, "to": {"link": "l3", "point": [0, 0, 0]}, "lead_m": 0.01}}"#,
            "transmission.matrix[1].linear.from.link = \"l9\": the robot has no such link",
        ),
        (
            r#"{"linear": {"from": {"link": "l1", "point": [0, "r4", 0]}, "to": {"link": "l3", "point": [0, 0, 0]}, "lead_m": 0.01}}"#,
            "transmission.matrix[1].linear.from.point[1] = \"r4\" must be a number",
        ),
        (
            r#"{"linear": {"from": {"link": "l1", "point": [0, 0, 0]}, "to": {"link": "bracket", "point": [0, 0, 0]}, "lead_m": 0.01}}"#,
            "transmission.matrix[1].linear.to.link: both ends are fixed to one rigid body",
        ),
        (
            r#"{"linear": {"from": {"link": "l1", "point": [0, 0, 0]}, "to": {"link": "l2", "point": [0, 0, 0]}, "lead_m": 0.01, "stroke_m": [0.3, 0.2]}}"#,
            "transmission.matrix[1].linear.stroke_m must be [min, max]",
        ),
        (
            r#"{"crank_rod": {"crank": {"link": "l1", "point": [0, 0, 0], "axis": [0, 0, 0], "radius_m": 0.02, "ratio": 3}, "rod_m": 0.2, "to": {"link": "l2", "point": [0, 0, 0]}}}"#,
            "transmission.matrix[1].crank_rod.crank.axis must be a finite direction",
        ),
    ];
    for (text, expected) in cases {
        let error = resolve(&dynamics, text).unwrap_err().to_string();
        assert!(error.starts_with(expected), "{error}");
    }
}

/// A lead, a crank's radius or a rod outside a micrometre to a hundred metres is refused where
/// the row is read, naming the field: its motor angle's derivatives would overflow (a lead of
/// 1e-300 made G(q) infinite and nalgebra's SVD panic), and a subnormal is no exception.
#[test]
fn a_linkage_length_outside_its_range_is_refused_naming_the_field() {
    let dynamics = dynamics();
    let screw = |lead: &str| {
        format!(
            r#"{{"linear": {{"from": {{"link": "bracket", "point": [0, 0, 0]}},
            "to": {{"link": "l3", "point": [0.1, 0, 0]}}, "lead_m": {lead}}}}}"#
        )
    };
    let crank = |radius: &str, rod: &str| {
        format!(
            r#"{{"crank_rod": {{"crank": {{"link": "bracket", "point": [0, 0, 0],
            "axis": [0.2, 0.1, 1], "radius_m": {radius}, "ratio": -12}}, "rod_m": {rod},
            "to": {{"link": "l2", "point": [0.08, 0.05, 0]}}}}}}"#
        )
    };
    let cases = [
        (
            screw("1e-300"),
            "linear.lead_m = 1e-300 m is outside [1e-6, 100] m",
        ),
        (screw("5e-324"), "linear.lead_m = 5e-324 m is outside"),
        (screw("0"), "linear.lead_m = 0 m is outside"),
        (screw("1000"), "linear.lead_m = 1000 m is outside"),
        (
            crank("1e-300", "0.2"),
            "crank_rod.crank.radius_m = 1e-300 m is outside",
        ),
        (
            crank("0.05", "1e-300"),
            "crank_rod.rod_m = 1e-300 m is outside",
        ),
        (crank("0.05", "-0.2"), "crank_rod.rod_m = -0.2 m is outside"),
    ];
    for (text, expected) in cases {
        let error = resolve(&dynamics, &text).unwrap_err().to_string();
        let expected = format!("transmission.matrix[1].{expected}");
        assert!(error.starts_with(&expected), "{error}");
    }
    assert!(resolve(&dynamics, &screw("0.000001")).is_ok());
    assert!(resolve(&dynamics, &crank("0.05", "100")).is_ok());
}

/// A crank's axis is scaled by its largest component before it is normalised: [0, -1e308, 0]
/// (whose norm overflows) and [0, -1e-300, 0] (whose square underflows) are [0, -1, 0].
#[test]
fn a_crank_axis_of_huge_or_tiny_components_keeps_its_direction() {
    let dynamics = dynamics();
    let crank = |axis: &str| {
        let text = format!(
            r#"{{"crank_rod": {{"crank": {{"link": "bracket", "point": [0, 0, 0],
            "axis": {axis}, "radius_m": 0.05, "ratio": -12}}, "rod_m": 0.2,
            "to": {{"link": "l2", "point": [0.08, 0.05, 0]}}}}}}"#
        );
        resolve(&dynamics, &text)
    };
    let unit = crank("[0, -1, 0]").unwrap();
    for axis in [
        "[0, -1e308, 0]",
        "[0, -1e-300, 0]",
        "[0, -5e-324, 0]",
        "[0, -2, 0]",
    ] {
        assert_eq!(crank(axis).unwrap(), unit, "{axis}");
    }
    let error = crank("[0, 0, 0]").unwrap_err().to_string();
    assert!(
        error.contains("crank.axis must be a finite direction"),
        "{error}"
    );
}

fn row_at(dynamics: &Dynamics, linkage: &Linkage, q: &[f64]) -> RowDerivatives {
    let mut data = dynamics.workspace();
    let shape = RowShape::new(linkage, 4);
    RowDerivatives::of(linkage, &shape, dynamics, &mut data, (q, &design())).unwrap()
}

fn shifted(q: &[f64], along: &[f64], h: f64) -> Vec<f64> {
    q.iter().zip(along).map(|(q, d)| q + h * d).collect()
}

fn assert_close(exact: &nalgebra::DMatrix<f64>, difference: &nalgebra::DMatrix<f64>, what: &str) {
    let scale = 1.0 + exact.amax();
    assert!(
        (exact - difference).amax() < 1e-6 * scale,
        "{what}: {exact} against {difference}"
    );
}

#[test]
fn a_rows_dense_derivatives_match_central_differences() {
    let dynamics = dynamics();
    let (x, y) = ([0.3, -0.8, 0.5], [-0.4, 0.6, 0.9]);
    let h = 1e-5;
    for linkage in [screw(&dynamics), crank(&dynamics, Branch::Positive)] {
        let row = row_at(&dynamics, &linkage, &Q);
        assert_eq!(row.gradient[0], 0.0, "joint 1 does not move the linkage");
        let along = |f: &dyn Fn(&RowDerivatives) -> nalgebra::DMatrix<f64>, d: &[f64]| {
            let plus = f(&row_at(&dynamics, &linkage, &shifted(&Q, d, h)));
            let minus = f(&row_at(&dynamics, &linkage, &shifted(&Q, d, -h)));
            (plus - minus) / (2.0 * h)
        };
        let gradient =
            |r: &RowDerivatives| nalgebra::DMatrix::from_column_slice(3, 1, r.gradient.as_slice());
        for (j, unit) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .iter()
            .enumerate()
        {
            let angle = |r: &RowDerivatives| nalgebra::DMatrix::from_element(1, 1, r.angle);
            assert_close(
                &gradient(&row).rows(j, 1).into(),
                &along(&angle, unit),
                "gradient",
            );
            assert_close(
                &row.hessian.columns(j, 1).into(),
                &along(&gradient, unit),
                "Hessian",
            );
        }
        assert_close(
            &row.third_along(&x),
            &along(&|r| r.hessian.clone(), &x),
            "third",
        );
        assert_close(
            &row.fourth_along(&x, &y),
            &along(&|r| r.third_along(&x), &y),
            "fourth",
        );
        // Along q(t) = q + x t + y t^2 / 2 the motor's acceleration at t = 0 is G y + x^T H x.
        let path = |t: f64| {
            let q: Vec<f64> = (0..3)
                .map(|k| Q[k] + x[k] * t + 0.5 * y[k] * t * t)
                .collect();
            row_at(&dynamics, &linkage, &q).angle
        };
        let (step, middle) = (1e-4, path(0.0));
        let second = (path(step) - 2.0 * middle + path(-step)) / (step * step);
        let acceleration = row.acceleration(&x, &y);
        assert!(
            (acceleration - second).abs() < 1e-5 * (1.0 + acceleration.abs()),
            "{acceleration} against {second}"
        );
        let first = (path(step) - path(-step)) / (2.0 * step);
        assert!((row.speed(&x) - first).abs() < 1e-7 * (1.0 + first.abs()));
    }
}

#[test]
fn a_rows_design_sensitivities_match_central_differences() {
    let dynamics = dynamics();
    let h = 1e-6;
    for linkage in [screw(&dynamics), crank(&dynamics, Branch::Negative)] {
        let mut data = dynamics.workspace();
        let sensitivity =
            RowSensitivity::of(&linkage, &dynamics, &mut data, (&Q, &design())).unwrap();
        assert_eq!(sensitivity.parameters, linkage.parameters());
        for (p, &index) in sensitivity.parameters.iter().enumerate() {
            let mut at = |sign: f64| {
                let mut r = design();
                r[index] += sign * h;
                let shape = RowShape::new(&linkage, 2);
                RowDerivatives::of(&linkage, &shape, &dynamics, &mut data, (&Q, &r)).unwrap()
            };
            let (plus, minus) = (at(1.0), at(-1.0));
            let angle = (plus.angle - minus.angle) / (2.0 * h);
            assert!((sensitivity.angle[p] - angle).abs() < 1e-6 * (1.0 + angle.abs()));
            let gradient = (&plus.gradient - &minus.gradient) / (2.0 * h);
            assert!((&sensitivity.gradient[p] - &gradient).amax() < 1e-6 * (1.0 + gradient.amax()));
            let hessian = (&plus.hessian - &minus.hessian) / (2.0 * h);
            assert_close(&sensitivity.hessian[p], &hessian, "d Hessian / dr");
        }
    }
}
