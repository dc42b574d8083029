//! The arm itself, drawn from its kinematics: a filmstrip of poses along the trajectory
//! ([`POSES_FILE`], as the paper's Fig. 1) and an animation that plays the motion in any browser
//! ([`MOTION_FILE`]: an SVG animated with SMIL, no script and no network).
//!
//! The links are the segments between the joints' origins (the base at the world origin first,
//! the TCP last); each linkage row of the transmission is drawn over them (a screw's anchors and
//! the line between them, with its length; a crank's circle, the crank and the rod); the payload
//! is marked where the task fixes it, with its mass. A planar arm is projected on the world
//! plane the TCP's path spans most ([`path_plane`]); a spatial arm, whose points extend along
//! every world axis, is drawn in two views, from the side (the vertical world z against the
//! horizontal axis it reaches furthest along) and from the top (x-y). Every panel has the base
//! and a scale bar. A belt's pulleys are not drawn: the task gives their ratios, not their radii.

mod marks;

use super::world::{path_plane, plot_title, WorldAxis};
use super::ReportError;
use crate::store::files::write_atomic;
use codesign_core::problem::Formulation;
use codesign_core::solve::TrajectoryResult;
use codesign_core::transmission::linkage::Linkage;
use marks::{linkage, text_lines, wrap, Kind, Panel};
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

/// An arm is spatial, and drawn in two views, when its points extend along each world axis by
/// at least this share of the furthest.
const SPATIAL: f64 = 0.25;

/// The arm at one node, in the world, m: the base, the joints' origins and the TCP; the payload;
/// each linkage row's points ([`Linkage::drawn_points`]), None where its loop does not close.
struct Pose {
    arm: Vec<Vector3<f64>>,
    payload: Vector3<f64>,
    linkages: Vec<Option<Vec<Vector3<f64>>>>,
}

/// A world plane the arm is drawn in.
struct Plane {
    /// Its (horizontal, vertical) axes.
    axes: (WorldAxis, WorldAxis),
    /// `side` or `top` for a spatial arm's views; None for a planar arm's one plane.
    view: Option<&'static str>,
    /// (lower corner, upper corner) of everything drawn in it, m.
    bounds: ([f64; 2], [f64; 2]),
}

impl Plane {
    /// The plane of `axes` around every point of `poses`.
    fn new(axes: (WorldAxis, WorldAxis), view: Option<&'static str>, poses: &[Pose]) -> Plane {
        let mut plane = Plane {
            axes,
            view,
            bounds: ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        };
        let mut bounds = plane.bounds;
        for point in poses.iter().flat_map(points_of) {
            let p = plane.project(point);
            for (i, value) in p.into_iter().enumerate() {
                bounds.0[i] = bounds.0[i].min(value);
                bounds.1[i] = bounds.1[i].max(value);
            }
        }
        plane.bounds = bounds;
        plane
    }

    /// A world point in the plane, m.
    fn project(&self, p: &Vector3<f64>) -> [f64; 2] {
        [p[self.axes.0.index()], p[self.axes.1.index()]]
    }
}

/// Every point drawn of a pose.
fn points_of(pose: &Pose) -> impl Iterator<Item = &Vector3<f64>> {
    let linkages = pose.linkages.iter().flatten().flatten();
    pose.arm.iter().chain([&pose.payload]).chain(linkages)
}

/// The poses of every node, the linkage rows' kinds and the planes they are drawn in.
struct Drawing {
    poses: Vec<Pose>,
    kinds: Vec<Kind>,
    planes: Vec<Plane>,
}

impl Drawing {
    /// The arm at every node of `result`'s trajectory.
    fn of(formulation: &Formulation, result: &TrajectoryResult) -> Drawing {
        let t = &result.trajectory;
        let dynamics = formulation.dynamics();
        let rows = formulation.transmission().linkages();
        let mut data = dynamics.workspace();
        let payload_point = *dynamics.robot().payload_point();
        let poses: Vec<Pose> =
            t.q.iter()
                .map(|q| {
                    let mut arm = vec![Vector3::zeros()];
                    arm.extend(dynamics.skeleton(&mut data, q));
                    let payload = dynamics.point_position(&mut data, q, &payload_point);
                    let linkages = rows
                        .iter()
                        .map(|row| {
                            let at = (q.as_slice(), result.ratios.as_slice());
                            row.linkage.drawn_points(dynamics, &mut data, at).ok()
                        })
                        .collect();
                    Pose {
                        arm,
                        payload,
                        linkages,
                    }
                })
                .collect();
        let kinds = rows
            .iter()
            .map(|row| match row.linkage {
                Linkage::Linear(_) => Kind::Screw,
                Linkage::CrankRod(_) => Kind::CrankRod,
            })
            .collect();
        let planes = planes(&poses, path_plane(t));
        Drawing {
            poses,
            kinds,
            planes,
        }
    }
}

/// The planes of `poses`: a side and a top view where the arm extends along every world axis
/// (by [`SPATIAL`] of the furthest), else the one plane `path` of the TCP's path.
fn planes(poses: &[Pose], path: (WorldAxis, WorldAxis)) -> Vec<Plane> {
    let axes = [WorldAxis::X, WorldAxis::Y, WorldAxis::Z];
    let extent = axes.map(|axis| {
        let values = poses.iter().flat_map(points_of).map(|p| p[axis.index()]);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        (hi - lo).max(0.0)
    });
    let furthest = extent.iter().copied().fold(0.0, f64::max);
    if furthest > 0.0 && extent.iter().all(|e| *e >= SPATIAL * furthest) {
        let across = match extent[0] >= extent[1] {
            true => WorldAxis::X,
            false => WorldAxis::Y,
        };
        vec![
            Plane::new((across, WorldAxis::Z), Some("side"), poses),
            Plane::new((WorldAxis::X, WorldAxis::Y), Some("top"), poses),
        ]
    } else {
        vec![Plane::new(path, None, poses)]
    }
}

/// The TCP's path with its start (circle) and goal (square) marked, in one panel.
fn path(svg: &mut String, drawing: &Drawing, panel: &Panel) {
    let tcp: Vec<Vector3<f64>> = drawing
        .poses
        .iter()
        .filter_map(|p| p.arm.last().copied())
        .collect();
    let _ = write!(
        svg,
        r##"<polyline points="{}" fill="none" stroke="#999" stroke-dasharray="4 3"/>"##,
        panel.points(&tcp)
    );
    if let (Some(start), Some(goal)) = (tcp.first(), tcp.last()) {
        let (x, y) = panel.at(start);
        let _ = write!(
            svg,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="5" fill="#2a9d3a"/>"##
        );
        let (x, y) = panel.at(goal);
        let _ = write!(
            svg,
            r##"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="#c0392b"/>"##,
            x - 5.0,
            y - 5.0
        );
    }
}

/// The arm at `pose` in `panel`: links, linkages, joints, TCP and payload.
fn arm(svg: &mut String, (pose, kinds): (&Pose, &[Kind]), panel: &Panel, mass_kg: f64) {
    let _ = write!(
        svg,
        r##"<polyline class="links" points="{}" fill="none" stroke="#1f4e79" stroke-width="5" stroke-linejoin="round" stroke-linecap="round"/>"##,
        panel.points(&pose.arm)
    );
    for (row, (kind, points)) in kinds.iter().zip(&pose.linkages).enumerate() {
        if let Some(points) = points {
            linkage(svg, panel, (*kind, row), points);
        }
    }
    for joint in &pose.arm[1..pose.arm.len() - 1] {
        let (x, y) = panel.at(joint);
        let _ = write!(
            svg,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="white" stroke="#1f4e79"/>"##
        );
    }
    if mass_kg > 0.0 {
        let (x, y) = panel.at(&pose.payload);
        let _ = write!(
            svg,
            r##"<rect x="{:.1}" y="{:.1}" width="12" height="12" fill="#e67e22"/>"##,
            x - 6.0,
            y - 6.0
        );
        panel.label(svg, (x + 8.0, y - 8.0), &format!("{mass_kg} kg"), 10.0);
    }
}

/// The legend under the title: what each mark is, and the plane or views.
fn legend(drawing: &Drawing) -> String {
    let planes: Vec<String> = drawing
        .planes
        .iter()
        .map(|p| {
            let (h, v) = p.axes;
            match p.view {
                Some(view) => format!("{view} view in the world {}-{} plane", h.name(), v.name()),
                None => format!("in the world {}-{} plane", h.name(), v.name()),
            }
        })
        .collect();
    let mut text = format!(
        "links between joint origins (circles) from the base (triangle, hatched ground), {}; \
         TCP path dashed, start ● goal ■, payload orange",
        planes.join(" and ")
    );
    if drawing.kinds.contains(&Kind::Screw) {
        text.push_str("; screw (vermilion) between its anchors, its length in m");
    }
    if drawing.kinds.contains(&Kind::CrankRod) {
        text.push_str("; crank (green; its circle dotted in the filmstrip) and rod (pink)");
    }
    text
}

/// The title and `legend` wrapped to `width` px, written at the top: the height they take, px.
fn head(svg: &mut String, title: &str, legend: &str, width: f64) -> f64 {
    let mut height = 4.0;
    height += text_lines(svg, &wrap(title, 13.0, width - 16.0), (8.0, height), 13.0);
    height += text_lines(svg, &wrap(legend, 10.0, width - 16.0), (8.0, height), 10.0);
    height + 6.0
}

/// An SVG document of `width` by `height` px around `body`.
fn document(width: f64, height: f64, body: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height:.0}" viewBox="0 0 {width} {height:.0}" font-family="sans-serif"><rect width="100%" height="100%" fill="white"/>{body}</svg>
"##
    )
}

/// The filmstrip: [`FRAMES`] columns of the arm at evenly spaced nodes, a row per plane, the
/// time under each column.
fn filmstrip(formulation: &Formulation, result: &TrajectoryResult, drawing: &Drawing) -> String {
    let last = drawing.poses.len().saturating_sub(1);
    let frames = FRAMES.min(last + 1);
    let width = PANEL * frames as f64;
    let mut body = String::new();
    let title = plot_title(formulation, result);
    let top = head(&mut body, &title, &legend(drawing), width);
    let mass = formulation.task().payload.mass_kg;
    for (k, plane) in drawing.planes.iter().enumerate() {
        let row_top = top + PANEL * k as f64;
        for frame in 0..frames {
            let node = if frames > 1 {
                frame * last / (frames - 1)
            } else {
                0
            };
            let panel = Panel::new(plane, (PANEL * frame as f64, row_top), PANEL);
            panel.base(&mut body);
            path(&mut body, drawing, &panel);
            arm(
                &mut body,
                (&drawing.poses[node], &drawing.kinds),
                &panel,
                mass,
            );
            if frame == 0 {
                panel.name(&mut body);
            }
            if frame + 1 == frames {
                panel.scale_bar(&mut body);
            }
        }
    }
    let bottom = top + PANEL * drawing.planes.len() as f64;
    for frame in 0..frames {
        let node = if frames > 1 {
            frame * last / (frames - 1)
        } else {
            0
        };
        let time = result.trajectory.time.get(node).copied().unwrap_or(0.0);
        let _ = write!(
            body,
            r##"<text x="{:.1}" y="{:.1}" font-size="11">t = {time:.2} s</text>"##,
            PANEL * frame as f64 + 8.0,
            bottom + 12.0
        );
    }
    document(width, bottom + 18.0, &body)
}

/// The animation: the arm moving through every node in real time, looping, in a panel per
/// plane side by side.
fn animation(formulation: &Formulation, result: &TrajectoryResult, drawing: &Drawing) -> String {
    let size = 2.0 * PANEL;
    let width = size * drawing.planes.len() as f64;
    let seconds = result
        .trajectory
        .time
        .last()
        .copied()
        .unwrap_or(1.0)
        .max(0.1);
    let mut body = String::new();
    let legend = format!(
        "plays the motion in real time ({seconds:.2} s), looping; {}",
        legend(drawing)
    );
    let top = head(&mut body, &plot_title(formulation, result), &legend, width);
    for (k, plane) in drawing.planes.iter().enumerate() {
        let panel = Panel::new(plane, (size * k as f64, top), size);
        panel.base(&mut body);
        path(&mut body, drawing, &panel);
        panel.name(&mut body);
        panel.scale_bar(&mut body);
        moving(&mut body, formulation, drawing, (&panel, seconds));
    }
    document(width, top + size, &body)
}

/// An animated `points` (or other attribute) of `values`, one per node, over `seconds`.
fn animate(attribute: &str, seconds: f64, values: &[String]) -> String {
    format!(
        r##"<animate attributeName="{attribute}" dur="{seconds}s" repeatCount="indefinite" values="{}"/>"##,
        values.join(";")
    )
}

/// The moving marks of the animation in `panel`: the links, each linkage and the payload.
fn moving(
    svg: &mut String,
    formulation: &Formulation,
    drawing: &Drawing,
    (panel, seconds): (&Panel, f64),
) {
    let frames: Vec<String> = drawing.poses.iter().map(|p| panel.points(&p.arm)).collect();
    let _ = write!(
        svg,
        r##"<polyline class="links" points="{}" fill="none" stroke="#1f4e79" stroke-width="6" stroke-linejoin="round" stroke-linecap="round">{}</polyline>"##,
        frames[0],
        animate("points", seconds, &frames)
    );
    for (row, kind) in drawing.kinds.iter().enumerate() {
        moving_linkage(svg, drawing, (*kind, row), (panel, seconds));
    }
    if formulation.task().payload.mass_kg > 0.0 {
        let at: Vec<(f64, f64)> = drawing.poses.iter().map(|p| panel.at(&p.payload)).collect();
        let xs: Vec<String> = at.iter().map(|(x, _)| format!("{:.1}", x - 6.0)).collect();
        let ys: Vec<String> = at.iter().map(|(_, y)| format!("{:.1}", y - 6.0)).collect();
        let _ = write!(
            svg,
            r##"<rect class="payload" x="{}" y="{}" width="12" height="12" fill="#e67e22">{}{}</rect>"##,
            xs[0],
            ys[0],
            animate("x", seconds, &xs),
            animate("y", seconds, &ys)
        );
    }
}

/// Linkage `row` moving in `panel`: a screw's line, or a crank and its rod, each an animated
/// polyline (at a node where its loop does not close, as at the last node before where it
/// does, or the first); nothing where it closes at no node.
fn moving_linkage(
    svg: &mut String,
    drawing: &Drawing,
    (kind, row): (Kind, usize),
    (panel, seconds): (&Panel, f64),
) {
    let Some(mut last) = (drawing.poses.iter()).find_map(|p| p.linkages[row].clone()) else {
        return;
    };
    let frames: Vec<Vec<Vector3<f64>>> = (drawing.poses.iter())
        .map(|p| {
            if let Some(points) = &p.linkages[row] {
                last = points.clone();
            }
            last.clone()
        })
        .collect();
    let parts: &[(std::ops::Range<usize>, &str, &str)] = match kind {
        Kind::Screw => &[(0..2, "screw-body", "#d55e00")],
        Kind::CrankRod => &[(0..2, "crank", "#009e73"), (1..3, "rod", "#cc79a7")],
    };
    let _ = write!(svg, r##"<g class="{}">"##, kind.class());
    for (points, class, colour) in parts {
        let values: Vec<String> = (frames.iter())
            .map(|f| panel.points(&f[points.clone()]))
            .collect();
        let _ = write!(
            svg,
            r##"<polyline class="{class}" points="{}" fill="none" stroke="{colour}" stroke-width="3">{}</polyline>"##,
            values[0],
            animate("points", seconds, &values)
        );
    }
    svg.push_str("</g>");
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
