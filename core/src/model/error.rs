//! The error of loading a robot model.

use std::fmt;

/// A robot description that could not be read or does not describe a supported robot.
///
/// It names the file, the element or field at fault (e.g. `joint 'joint_arm_2' <axis>` or
/// `task tcp.link`) and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError {
    /// The URDF file (or the name given for a URDF read from a string).
    pub file: String,
    /// The element or field at fault.
    pub element: String,
    /// What is wrong.
    pub message: String,
}

impl ModelError {
    /// An error about `element` of `file`.
    pub fn new(file: &str, element: impl Into<String>, message: impl Into<String>) -> ModelError {
        ModelError {
            file: file.to_owned(),
            element: element.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.element, self.message)
    }
}

impl std::error::Error for ModelError {}
