//! End to end: `codesign dynamics --robot FILE` on URDFs written as users have them
//! (tests/data/urdf/): locked joints, a gripper beside the TCP link and a massless flange load with
//! as many joints as move on the chain to the TCP link (`link_4`, the task's); a prismatic joint
//! on that chain and a joint with two `<limit>`s are refused, naming the joint.

use crate::support;

use serde_json::Value;
use std::process::Output;
use support::{fails_saying, root};

/// `codesign dynamics` on the URDF `urdf` with the repository's task, whose TCP link is
/// `link_4` (without `--task`, the TCP would be the robot's own tip link).
fn dynamics(urdf: &str, q: &str) -> Output {
    let file = root().join("tests/data/urdf").join(urdf);
    let task = support::task_path();
    support::codesign(&[
        "dynamics",
        "--task",
        task.to_str().unwrap(),
        "--robot",
        file.to_str().unwrap(),
        "--q",
        q,
    ])
}

/// The robot loads, takes a state of `dof` joints, and refuses one more.
fn has_dof(urdf: &str, dof: usize) {
    let q = vec!["0.1"; dof].join(",");
    let output = dynamics(urdf, &q);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{urdf}: {stderr}");
    let printed: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert!(printed.is_object(), "{urdf}");
    let one_more = dynamics(urdf, &format!("{q},0.1"));
    fails_saying(
        &one_more,
        &format!("has {} values but the robot has {dof} joints", dof + 1),
    );
}

#[test]
fn locked_joints_and_tool_links_leave_the_chain_to_the_tcp() {
    has_dof("locked_joint.urdf", 2);
    has_dof("gripper.urdf", 2);
    has_dof("massless_flange.urdf", 2);
}

#[test]
fn a_prismatic_joint_on_the_chain_and_a_second_limit_are_named() {
    fails_saying(
        &dynamics("prismatic_on_chain.urdf", "0,0"),
        "joint 'slider': is prismatic: only revolute and continuous joints move",
    );
    fails_saying(
        &dynamics("duplicate_limit.urdf", "0,0"),
        "joint 'joint_2' <limit>: has 2 <limit> elements",
    );
}
