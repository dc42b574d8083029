//! The arm itself, drawn from its kinematics: a filmstrip of poses along the trajectory
//! ([`POSES_FILE`], as the paper's Fig. 1) and an animation that plays the motion in any browser
//! ([`MOTION_FILE`]: an SVG animated with SMIL, no script and no network).
//!
//! The links are the segments between the joints' origins (the base at the world origin first,
//! the TCP last), projected on the world plane the TCP's path spans most
//! ([`path_plane`]); the payload is marked where the task fixes it, with its mass.

use super::world::{path_plane, plot_title, WorldAxis};
use super::ReportError;
use crate::store::files::write_atomic;
use codesign_core::problem::Formulation;
use codesign_core::solve::TrajectoryResult;
use codesign_core::text::markup_safe;
use nalgebra::Vector3;
use std::fmt::Write;
use std::path::Path;

/// The filmstrip of poses.
pub const POSES_FILE: &str = "poses.svg";

/// The animation of the motion.
pub const MOTION_FILE: &str = "motion.svg";

/// Poses in the filmstrip: the first node, the last, and evenly between.
const FRAMES: usize = 5;

/// A panel's size, px.
const PANEL: f64 = 240.0;

/// Space above the panels for the title, px.
const HEAD: f64 = 40.0;

/// The arm at one node, projected: the base, the joints' origins and the TCP, then the payload.
struct Pose {
    arm: Vec<[f64; 2]>,
    payload: [f64; 2],
}

/// The poses of every node and the plane they are drawn in.
struct Drawing {
    poses: Vec<Pose>,
    axes: (WorldAxis, WorldAxis),
    /// (lower corner, upper corner) of everything drawn, m.
    bounds: ([f64; 2], [f64; 2]),
}

impl Drawing {
    /// The arm at every node of `result`'s trajectory.
    fn of(formulation: &Formulation, result: &TrajectoryResult) -> Drawing {
        let t = &result.trajectory;
        let axes = path_plane(t);
        let dynamics = formulation.dynamics();
        let mut data = dynamics.workspace();
        let payload_point = *dynamics.robot().payload_point();
        let project = |p: &Vector3<f64>| [p[axes.0.index()], p[axes.1.index()]];
        let poses: Vec<Pose> =
            t.q.iter()
                .map(|q| {
                    let mut arm = vec![[0.0, 0.0]];
                    arm.extend(dynamics.skeleton(&mut data, q).iter().map(project));
                    let payload = project(&dynamics.point_position(&mut data, q, &payload_point));
                    Pose { arm, payload }
                })
                .collect();
        let mut lower = [f64::INFINITY; 2];
        let mut upper = [f64::NEG_INFINITY; 2];
        for point in poses.iter().flat_map(|p| p.arm.iter().chain([&p.payload])) {
            for i in 0..2 {
                lower[i] = lower[i].min(point[i]);
                upper[i] = upper[i].max(point[i]);
            }
        }
        Drawing {
            poses,
            axes,
            bounds: (lower, upper),
        }
    }

    /// The map from the plane (m) to a panel of `size` px at (`left`, `top`): one scale for
    /// both axes, the vertical axis pointing up, a margin of 10 %.
    fn view(&self, left: f64, top: f64, size: f64) -> impl Fn(&[f64; 2]) -> (f64, f64) {
        let (lower, upper) = self.bounds;
        let span = (upper[0] - lower[0]).max(upper[1] - lower[1]).max(1e-6);
        let scale = 0.8 * size / span;
        let centre = [(lower[0] + upper[0]) / 2.0, (lower[1] + upper[1]) / 2.0];
        move |p: &[f64; 2]| {
            (
                left + size / 2.0 + (p[0] - centre[0]) * scale,
                top + size / 2.0 - (p[1] - centre[1]) * scale,
            )
        }
    }
}

/// `text` with the characters XML reserves escaped, and those it refuses written as their
/// escapes ([`markup_safe`]).
fn escape(text: &str) -> String {
    markup_safe(text)
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Points as SVG's `points` attribute.
fn points(view: &impl Fn(&[f64; 2]) -> (f64, f64), of: &[[f64; 2]]) -> String {
    let pairs: Vec<String> = of
        .iter()
        .map(|p| {
            let (x, y) = view(p);
            format!("{x:.1},{y:.1}")
        })
        .collect();
    pairs.join(" ")
}

/// The TCP's path with its start (circle) and goal (square) marked, in one panel.
fn path(svg: &mut String, drawing: &Drawing, view: &impl Fn(&[f64; 2]) -> (f64, f64)) {
    let tcp: Vec<[f64; 2]> = drawing
        .poses
        .iter()
        .filter_map(|p| p.arm.last().copied())
        .collect();
    let _ = write!(
        svg,
        r##"<polyline points="{}" fill="none" stroke="#999" stroke-dasharray="4 3"/>"##,
        points(view, &tcp)
    );
    if let (Some(start), Some(goal)) = (tcp.first(), tcp.last()) {
        let (x, y) = view(start);
        let _ = write!(
            svg,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="5" fill="#2a9d3a"/>"##
        );
        let (x, y) = view(goal);
        let _ = write!(
            svg,
            r##"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="#c0392b"/>"##,
            x - 5.0,
            y - 5.0
        );
    }
}

/// The arm at `pose`: links, joints, TCP and payload.
fn arm(svg: &mut String, pose: &Pose, view: &impl Fn(&[f64; 2]) -> (f64, f64), mass_kg: f64) {
    let _ = write!(
        svg,
        r##"<polyline points="{}" fill="none" stroke="#1f4e79" stroke-width="5" stroke-linejoin="round" stroke-linecap="round"/>"##,
        points(view, &pose.arm)
    );
    let (x, y) = view(&pose.arm[0]);
    let _ = write!(
        svg,
        r##"<path d="M{:.1},{:.1} l8,12 h-16 z" fill="#333"/>"##,
        x, y
    );
    for joint in &pose.arm[1..pose.arm.len() - 1] {
        let (x, y) = view(joint);
        let _ = write!(
            svg,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="white" stroke="#1f4e79"/>"##
        );
    }
    if mass_kg > 0.0 {
        let (x, y) = view(&pose.payload);
        let _ = write!(
            svg,
            r##"<rect x="{:.1}" y="{:.1}" width="12" height="12" fill="#e67e22"/><text x="{:.1}" y="{:.1}" font-size="10">{mass_kg} kg</text>"##,
            x - 6.0,
            y - 6.0,
            x + 8.0,
            y - 8.0
        );
    }
}

/// The legend line under the title: what each mark is, and the plane.
fn legend(drawing: &Drawing) -> String {
    format!(
        "links between joint origins (circles) from the base (triangle) in the world {}-{} \
         plane; TCP path dashed, start ● goal ■, payload orange",
        drawing.axes.0.name(),
        drawing.axes.1.name()
    )
}

/// The filmstrip: [`FRAMES`] panels of the arm at evenly spaced nodes, each with its time.
fn filmstrip(formulation: &Formulation, result: &TrajectoryResult, drawing: &Drawing) -> String {
    let last = drawing.poses.len().saturating_sub(1);
    let frames = FRAMES.min(last + 1);
    let width = PANEL * frames as f64;
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{}" font-family="sans-serif"><rect width="100%" height="100%" fill="white"/><text x="8" y="16" font-size="13">{}</text><text x="8" y="32" font-size="10">{}</text>"##,
        PANEL + HEAD + 10.0,
        escape(&plot_title(formulation, result)),
        legend(drawing)
    );
    let mass = formulation.task().payload.mass_kg;
    for frame in 0..frames {
        let node = if frames > 1 {
            frame * last / (frames - 1)
        } else {
            0
        };
        let left = PANEL * frame as f64;
        let view = drawing.view(left, HEAD, PANEL);
        path(&mut svg, drawing, &view);
        arm(&mut svg, &drawing.poses[node], &view, mass);
        let time = result.trajectory.time.get(node).copied().unwrap_or(0.0);
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" font-size="11">t = {time:.2} s</text>"##,
            left + 8.0,
            HEAD + PANEL
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// The animation: the arm moving through every node in real time, looping.
fn animation(formulation: &Formulation, result: &TrajectoryResult, drawing: &Drawing) -> String {
    let size = 2.0 * PANEL;
    let view = drawing.view(0.0, HEAD, size);
    let seconds = result
        .trajectory
        .time
        .last()
        .copied()
        .unwrap_or(1.0)
        .max(0.1);
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{}" font-family="sans-serif"><rect width="100%" height="100%" fill="white"/><text x="8" y="16" font-size="13">{}</text><text x="8" y="32" font-size="10">plays the motion in real time ({seconds:.2} s), looping; {}</text>"##,
        size + HEAD,
        escape(&plot_title(formulation, result)),
        legend(drawing)
    );
    path(&mut svg, drawing, &view);
    let frames: Vec<String> = drawing
        .poses
        .iter()
        .map(|p| points(&view, &p.arm))
        .collect();
    let first = frames.first().cloned().unwrap_or_default();
    let _ = write!(
        svg,
        r##"<polyline id="arm" points="{first}" fill="none" stroke="#1f4e79" stroke-width="6" stroke-linejoin="round" stroke-linecap="round"><animate attributeName="points" dur="{seconds}s" repeatCount="indefinite" values="{}"/></polyline>"##,
        frames.join(";")
    );
    if formulation.task().payload.mass_kg > 0.0 {
        let at: Vec<(f64, f64)> = drawing.poses.iter().map(|p| view(&p.payload)).collect();
        let xs: Vec<String> = at.iter().map(|(x, _)| format!("{:.1}", x - 6.0)).collect();
        let ys: Vec<String> = at.iter().map(|(_, y)| format!("{:.1}", y - 6.0)).collect();
        let _ = write!(
            svg,
            r##"<rect id="payload" x="{}" y="{}" width="12" height="12" fill="#e67e22"><animate attributeName="x" dur="{seconds}s" repeatCount="indefinite" values="{}"/><animate attributeName="y" dur="{seconds}s" repeatCount="indefinite" values="{}"/></rect>"##,
            xs[0],
            ys[0],
            xs.join(";"),
            ys.join(";")
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Writes [`POSES_FILE`] and [`MOTION_FILE`] of `result` into `folder` (which exists).
pub fn write_poses(
    folder: &Path,
    formulation: &Formulation,
    result: &TrajectoryResult,
) -> Result<(), ReportError> {
    let drawing = Drawing::of(formulation, result);
    if drawing.poses.is_empty() {
        return Ok(());
    }
    let files = [
        (POSES_FILE, filmstrip(formulation, result, &drawing)),
        (MOTION_FILE, animation(formulation, result, &drawing)),
    ];
    for (name, text) in files {
        write_atomic(&folder.join(name), text.as_bytes())?;
    }
    Ok(())
}
