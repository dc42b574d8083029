//! The progress line of a co-design run on a terminal: evaluations done of the total, the best
//! feasible fitness so far, the invalid and infeasible designs met, the time elapsed and an
//! estimate of the time left from the mean time per evaluation so far (unknown until a design
//! was solved: designs outside the design space take no time, and finish first). Redrawn in place on
//! stderr when stderr is a terminal; nothing is written otherwise (pipes, CI logs).

use crate::design::optimize::Progress;
use crate::design::score::Evaluation;
use crate::design::verdicts::{VerdictKind, VerdictTally};
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// The least time between two redraws: replayed evaluations and fast solves finish by the
/// hundred a second, faster than anyone reads.
const REDRAW: Duration = Duration::from_millis(100);

/// The progress of one run of `total` evaluations, drawn on `out` when `shown`.
pub struct ProgressLine<W: Write> {
    out: W,
    shown: bool,
    label: String,
    total: u64,
    /// Evaluations replayed from a resumed run's log: done, but taking no time.
    replayed: u64,
    /// Whether an evaluation of this invocation ran a solve (inside the design space).
    timed: bool,
    verdicts: VerdictTally,
    best: Option<f64>,
    started: Instant,
    drawn: Option<Instant>,
}

impl<W: Write> ProgressLine<W> {
    /// The progress of a run of `total` evaluations labelled `label`, drawn on `out` when
    /// `shown` (a terminal), from now.
    pub fn new(out: W, shown: bool, total: u64, label: String) -> ProgressLine<W> {
        ProgressLine {
            out,
            shown,
            label,
            total,
            replayed: 0,
            timed: false,
            verdicts: VerdictTally::default(),
            best: None,
            started: Instant::now(),
            drawn: None,
        }
    }

    /// Evaluations done.
    fn done(&self) -> u64 {
        self.verdicts.evaluations() as u64
    }

    /// The line after `elapsed`, e.g. `actuation 3 kg seed 0: 37/144, best 1234.5678 (12
    /// invalid, 3 infeasible), 0:42 elapsed, about 2:01 left`.
    pub fn line(&self, elapsed: Duration) -> String {
        let best = self.best.map_or_else(
            || "no feasible design yet".to_owned(),
            |best| format!("best {best:.4}"),
        );
        let solved = self.done() - self.replayed;
        let left = self.total.saturating_sub(self.done());
        let remaining = match self.timed {
            false if left > 0 => "time left unknown".to_owned(),
            _ => {
                let each = elapsed.as_secs_f64() / solved.max(1) as f64;
                format!("about {} left", clock(each * left as f64))
            }
        };
        format!(
            "{}: {}/{}, {best} ({} invalid, {} infeasible), {} elapsed, {remaining}",
            self.label,
            self.done(),
            self.total,
            self.verdicts.invalid.designs,
            self.verdicts.infeasible.designs,
            clock(elapsed.as_secs_f64()),
        )
    }

    /// Redraws the line in place (unless drawn less than [`REDRAW`] ago, the last evaluation
    /// aside).
    fn draw(&mut self) {
        let now = Instant::now();
        let recent = self.drawn.is_some_and(|at| now - at < REDRAW);
        if !self.shown || (recent && self.done() < self.total) {
            return;
        }
        let line = self.line(now - self.started);
        // A terminal that refuses the line loses only the progress, never the run.
        let _ = write!(self.out, "\r{line}\x1b[K").and_then(|()| self.out.flush());
        self.drawn = Some(now);
    }
}

impl<W: Write> Progress for ProgressLine<W> {
    fn evaluated(&mut self, evaluation: &Evaluation, replayed: bool) {
        self.verdicts.add(evaluation);
        self.replayed += u64::from(replayed);
        self.timed |= !replayed && VerdictKind::of(evaluation) != VerdictKind::Invalid;
        if VerdictKind::of(evaluation) == VerdictKind::Feasible {
            self.best = Some(
                self.best
                    .map_or(evaluation.cost, |b| b.min(evaluation.cost)),
            );
        }
        self.draw();
    }
}

impl<W: Write> Drop for ProgressLine<W> {
    /// Leaves the last state drawn on its own line.
    fn drop(&mut self) {
        if self.shown && self.drawn.is_some() {
            self.drawn = None;
            self.draw();
            let _ = writeln!(self.out);
        }
    }
}

/// A duration in seconds as `m:ss`, or `h:mm:ss` from an hour.
fn clock(seconds: f64) -> String {
    let whole = seconds.max(0.0).round() as u64;
    let (hours, minutes, seconds) = (whole / 3600, whole / 60 % 60, whole % 60);
    match hours {
        0 => format!("{minutes}:{seconds:02}"),
        _ => format!("{hours}:{minutes:02}:{seconds:02}"),
    }
}

/// The progress line of a run of `total` evaluations labelled `label`, on stderr when it is a
/// terminal.
pub fn progress_line(total: u64, label: String) -> Box<dyn Progress> {
    let stderr = std::io::stderr();
    let shown = stderr.is_terminal();
    Box::new(ProgressLine::new(stderr, shown, total, label))
}

#[cfg(test)]
mod tests {
    use super::{clock, ProgressLine};
    use crate::design::optimize::Progress;
    use crate::design::penalty::Penalty;
    use crate::design::score::{Evaluation, Score, Status, Verdict};
    use std::time::Duration;

    fn evaluation(status: &str, feasible: bool, cost: f64) -> Evaluation {
        let unsolved = Score::unsolved(Verdict::Invalid {
            distance: 1.0,
            reason: "r".into(),
        });
        let mut evaluation = Evaluation::new(&[6.0], &unsolved, &Penalty::PAPER);
        (evaluation.status, evaluation.feasible) = (Status::from(status), feasible);
        evaluation.cost = cost;
        evaluation
    }

    #[test]
    fn the_line_says_done_best_elapsed_and_left() {
        let mut line = ProgressLine::new(Vec::new(), false, 10, "joint 1 kg seed 0".to_owned());
        assert_eq!(
            line.line(Duration::from_secs(3)),
            "joint 1 kg seed 0: 0/10, no feasible design yet (0 invalid, 0 infeasible), 0:03 \
             elapsed, time left unknown"
        );
        // A design outside the design space finishes at once: no time per solve yet.
        line.evaluated(&evaluation("Invalid_Design", false, 1e6), false);
        assert!(line
            .line(Duration::from_secs(3))
            .ends_with("time left unknown"));
        line.evaluated(&evaluation("Solve_Succeeded", true, 250.5), false);
        line.evaluated(&evaluation("Solve_Succeeded", true, 120.25), false);
        line.evaluated(&evaluation("Elastic_Deficit", false, 1e6), false);
        // 4 solved in 20 s: 5 s each, 6 left.
        assert_eq!(
            line.line(Duration::from_secs(20)),
            "joint 1 kg seed 0: 4/10, best 120.2500 (1 invalid, 1 infeasible), 0:20 elapsed, \
             about 0:30 left"
        );
    }

    #[test]
    fn replayed_evaluations_take_no_time_in_the_estimate() {
        let mut line = ProgressLine::new(Vec::new(), false, 8, "run".to_owned());
        for _ in 0..4 {
            line.evaluated(&evaluation("Solve_Succeeded", true, 10.0), true);
        }
        assert!(line
            .line(Duration::from_secs(1))
            .ends_with("time left unknown"));
        line.evaluated(&evaluation("Solve_Succeeded", true, 9.0), false);
        // One solved in 2 s: 3 left at 2 s each.
        assert!(line
            .line(Duration::from_secs(2))
            .ends_with("best 9.0000 (0 invalid, 0 infeasible), 0:02 elapsed, about 0:06 left"));
    }

    #[test]
    fn only_a_terminal_sees_the_line() {
        let mut hidden = ProgressLine::new(Vec::new(), false, 2, "run".to_owned());
        hidden.evaluated(&evaluation("Solve_Succeeded", true, 1.0), false);
        hidden.evaluated(&evaluation("Solve_Succeeded", true, 1.0), false);
        let mut out = Vec::new();
        std::mem::swap(&mut out, &mut hidden.out);
        drop(hidden);
        assert!(out.is_empty());

        let mut written = Vec::new();
        {
            let mut shown = ProgressLine::new(&mut written, true, 2, "run".to_owned());
            shown.evaluated(&evaluation("Solve_Succeeded", true, 1.0), false);
            shown.evaluated(&evaluation("Solve_Succeeded", true, 0.5), false);
        }
        let text = String::from_utf8(written).unwrap();
        assert!(text.starts_with("\rrun: 1/2, best 1.0000"), "{text:?}");
        // The last evaluation is drawn however soon it comes, and again, kept, at the end.
        assert!(text.contains("\rrun: 2/2, best 0.5000"), "{text:?}");
        assert!(text.ends_with("left\x1b[K\n"), "{text:?}");
    }

    #[test]
    fn durations_read_as_a_clock() {
        assert_eq!(clock(0.4), "0:00");
        assert_eq!(clock(59.6), "1:00");
        assert_eq!(clock(3599.0), "59:59");
        assert_eq!(clock(3725.0), "1:02:05");
    }
}
