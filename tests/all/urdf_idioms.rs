//! End to end: `codesign dynamics --robot FILE` on URDFs written as users have them
//! (tests/data/urdf/): locked joints, a gripper beside the TCP link and a massless flange load with
//! as many joints as move on the chain to the TCP link (`link_4`, the task's); a prismatic joint
//! on that chain moves (it carries its links' weight along its axis); a joint with two
//! `<limit>`s is refused, naming the joint.

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
fn a_prismatic_joint_on_the_chain_moves_and_a_second_limit_is_named() {
    has_dof("prismatic_on_chain.urdf", 3);
    // The vertical slider carries link_2 and link_4 (1 kg each) whatever the angles: its static
    // force is their weight, N.
    let output = dynamics("prismatic_on_chain.urdf", "0.4,0.1,-0.7");
    let printed: Value = serde_json::from_slice(&output.stdout).unwrap();
    let gravity = printed["gravity"][1].as_f64().unwrap();
    assert!((gravity - 2.0 * 9.81).abs() < 1e-9, "{gravity}");
    fails_saying(
        &dynamics("duplicate_limit.urdf", "0,0"),
        "joint 'joint_2' <limit>: has 2 <limit> elements",
    );
}
