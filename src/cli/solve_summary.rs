//! What `codesign solve` prints about a result: its verdict, peaks against the limits, the
//! envelope, the static hold, the elastic measures, J by term and the solve's time.

use codesign_core::model::task::{PerMotor, ViaTime};
use codesign_core::problem::{EndHold, Formulation, Space, StaticHold};
use codesign_core::solve::{least_envelope_margin, CostTerms, ElasticMeasures, TrajectoryResult};
use codesign_core::text::rounded;

/// `max motor torque 1.234 N m (limit 1.7)` where every motor has one limit, else each
/// motor's peak beside the motors' limits: `max motor torques (1.234, 0.5) N m (limits [1.7,
/// 0.9])`; (largest, peaks, decimals) of the trajectory.
fn peak_text(name: &str, unit: &str, peaks: (f64, &[f64], usize), limits: &PerMotor) -> String {
    let (largest, each, decimals) = peaks;
    match limits {
        PerMotor::All(_) => {
            format!("max motor {name} {largest:.decimals$} {unit} (limit {limits})")
        }
        PerMotor::Each(_) => {
            let texts: Vec<String> = each.iter().map(|p| format!("{p:.decimals$}")).collect();
            format!(
                "max motor {name}s ({}) {unit} (limits {limits})",
                texts.join(", ")
            )
        }
    }
}

/// A margin within this of 0, N m, is the envelope reached: IPOPT holds rows to about its `tol`.
const REACHED_NM: f64 = 1e-6;

/// The torque-speed envelope, for the summary (None without one): where the trajectory comes
/// closest to it, reaches it or exceeds it most.
fn envelope_text(formulation: &Formulation, result: &TrajectoryResult) -> Option<String> {
    let no_load = formulation.task().motors.no_load_speed_rad_s.as_ref()?;
    let least = least_envelope_margin(formulation, &result.trajectory)?;
    let margin = least.margin_nm;
    let state = if margin >= REACHED_NM {
        format!("least margin {margin:.3} N m")
    } else if margin > -REACHED_NM {
        format!("reached (margin {margin:.1e} N m)")
    } else {
        format!("EXCEEDED by {:.3e} N m", -margin)
    };
    Some(format!(
        "torque-speed envelope (no-load speed {no_load} rad/s): {state}, motor {} at t = {:.3} s",
        least.motor + 1,
        result.trajectory.time[least.node]
    ))
}

/// The load held at rest, for the summary: each end's least margin, or what it lacks.
fn hold_text(hold: &StaticHold) -> String {
    let judged = if hold.judged {
        ""
    } else {
        " (reported, not required: ends paper)"
    };
    if let Some(reason) = hold.reason() {
        return format!("static hold{judged}: {reason}");
    }
    let least = |end: &EndHold| end.margins_nm.iter().copied().fold(f64::INFINITY, f64::min);
    format!(
        "static hold: the load is held at rest at the start and the goal (least {} margin {:.3} and {:.3} N m)",
        hold.rows.name(),
        least(&hold.start),
        least(&hold.goal)
    )
}

/// Whether the motors can execute a joint-space trajectory, for the summary (None in the
/// actuation space, whose controls are the motors' own).
fn execute_text(formulation: &Formulation, result: &TrajectoryResult) -> Option<String> {
    let execute = result.motors_execute.as_ref()?;
    (formulation.space() == Space::Joint).then(|| {
        format!(
            "joint space, {} limits: {}",
            formulation.modes().torque.name(),
            execute.text()
        )
    })
}

/// `feasible (judged by solving the trajectory problem directly)`: the verdict and, in plain
/// words, the solve that gave it (docs/model.md, section 8); for a design infeasible by the
/// static hold alone, the hold, and the motion's own verdict after it.
fn verdict_text(result: &TrajectoryResult) -> String {
    if result.infeasible_by_hold_alone() {
        let motion =
            (result.verdict_by).map_or(String::new(), |by| format!(" ({})", by.describe(true)));
        return format!(
            "INFEASIBLE: the motors cannot hold the load at rest at an end (the static hold \
             below); the motion itself is feasible{motion}"
        );
    }
    let verdict = if result.feasible {
        "feasible"
    } else {
        "INFEASIBLE"
    };
    match result.verdict_by {
        Some(by) => format!("{verdict} ({})", by.describe(result.feasible)),
        None => verdict.to_owned(),
    }
}

/// What the relaxed (elastic) problem measured, in plain words with units.
fn elastic_text(elastic: &ElasticMeasures) -> String {
    format!(
        "relaxed problem (limits may give way, at a price added to J): over the motion the \
         motors lack {} N m s of torque and exceed their speed limits by {} rad, at one node by \
         at most {} N m or rad/s; J with the price {:.6}",
        rounded(elastic.torque_deficit),
        rounded(elastic.speed_excess),
        rounded(elastic.largest_slack),
        elastic.objective
    )
}

/// Each ratio of the design at a bound of the design space, with dJ*/dr_i there.
fn print_bounds(formulation: &Formulation, result: &TrajectoryResult) {
    let space = formulation.transmission().design_space();
    for bound in space.active_bounds(&result.ratios, result.cost_gradient.as_deref()) {
        say!("  at its bounds: {bound}");
    }
}

pub(super) fn print_summary(formulation: &Formulation, result: &TrajectoryResult) {
    let task = formulation.task();
    say!(
        "{} space, r = ({}), payload {} kg: {} in {} iterations, J = {:.6}",
        formulation.space(),
        result
            .ratios
            .iter()
            .map(|r| format!("{r}"))
            .collect::<Vec<_>>()
            .join(", "),
        task.payload.mass_kg,
        result.status,
        result.iterations,
        result.cost
    );
    let t = &result.trajectory;
    say!(
        "  {}; {}, {}",
        verdict_text(result),
        peak_text(
            "torque",
            "N m",
            (result.max_motor_torque, &t.motor_torque_peaks(), 3),
            &task.motors.torque_limit_nm
        ),
        peak_text(
            "speed",
            "rad/s",
            (result.max_motor_speed, &t.motor_speed_peaks(), 1),
            &task.motors.speed_limit_rad_s
        )
    );
    if let Some(text) = envelope_text(formulation, result) {
        say!("  {text}");
    }
    print_bounds(formulation, result);
    if let Some(hold) = &result.static_hold {
        say!("  {}", hold_text(hold));
    }
    if let Some(text) = execute_text(formulation, result) {
        say!("  {text}");
    }
    if let Some(elastic) = &result.elastic {
        say!("  {}", elastic_text(elastic));
    }
    if let Some(horizon) = result.horizon_s {
        say!("  free horizon: T* = {horizon:.6} s");
    }
    if let Some(text) = via_times_text(formulation, result) {
        say!("  {text}");
    }
    if let (Some(pose), Some(goal)) = (&result.goal_pose, task.motion.goal.tcp()) {
        let beyond = result.violations.get("goal_tcp").unwrap_or(0.0);
        say!(
            "  TCP goal ({}) m within {} m: q_N = ({}) rad{}",
            (goal.tcp.iter().map(|p| format!("{p:.4}")))
                .collect::<Vec<_>>()
                .join(", "),
            goal.tol_m,
            (pose.iter().map(|q| format!("{q:.4}")))
                .collect::<Vec<_>>()
                .join(", "),
            match beyond > 0.0 {
                true => format!(", its TCP {beyond:.2e} m beyond the ball"),
                false => String::new(),
            }
        );
    }
    if let Some(t) = &result.cost_terms {
        say!("  {}", cost_terms_text(t));
    }
    let s = &result.solve_seconds;
    say!(
        "  solve {:.1} ms (callbacks {:.1} ms, IPOPT {:.1} ms)",
        s.total * 1e3,
        s.callbacks * 1e3,
        s.ipopt * 1e3
    );
}

/// "via points passed at: via[0] 0.400 s, via[1] 0.512 s (window [0.45, 0.6])", where the
/// task has via points.
fn via_times_text(formulation: &Formulation, result: &TrajectoryResult) -> Option<String> {
    let via = &formulation.task().motion.via;
    if result.via_times_s.is_empty() {
        return None;
    }
    let each =
        (via.iter().zip(&result.via_times_s).enumerate()).map(|(i, (via, t))| match via.time() {
            ViaTime::At(_) => format!("via[{i}] {t:.4} s"),
            window => format!("via[{i}] {t:.4} s (window {} s)", window.text()),
        });
    Some(format!(
        "via points passed at: {}",
        each.collect::<Vec<_>>().join(", ")
    ))
}

/// "J by term: ..." with the largest named; the duration's term only where it counts.
fn cost_terms_text(t: &CostTerms) -> String {
    let mut terms = vec![
        ("position", t.position),
        ("velocity", t.velocity),
        ("control", t.control),
        ("box", t.cartesian_box),
    ];
    if t.time != 0.0 {
        terms.push(("time", t.time));
    }
    let largest = terms
        .iter()
        .fold(terms[0], |m, &t| if t.1 > m.1 { t } else { m });
    let listed: Vec<String> = terms
        .iter()
        .map(|(name, value)| format!("{name} {value:.4}"))
        .collect();
    format!(
        "J by term: {} (the largest: {})",
        listed.join(", "),
        largest.0
    )
}
