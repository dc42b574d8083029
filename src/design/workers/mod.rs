//! Worker processes that evaluate designs, one solve at a time each.
//!
//! MUMPS is not thread-safe, so parallel evaluation runs in separate processes: `codesign worker`
//! reads a [`WorkerSetup`] line and then one [`Request`] per line on stdin, and answers each with
//! one [`Response`] line on stdout. The [`Pool`] feeds them, checks each answer with the check
//! its owner gives, and replaces a worker that crashes, exceeds the time limit or answers what
//! the check refuses: its design is retried once on a fresh worker, then answered as failed
//! with the reason. The pool knows nothing of scoring: its owner
//! (`design::evaluate::WorkerEvaluator`) turns a failure into a fitness. One bad design never
//! stops a run, and the results do not depend on the worker count.

mod error;
mod process;
mod protocol;

pub use error::WorkerError;
pub use process::{Launcher, MAX_GROUPS};
pub use protocol::{
    read_line, serve, DescentRequest, Hello, Request, Response, WorkerSetup, MAX_LINE_BYTES,
};

use super::score::{Evaluation, Merit};
use codesign_core::signals;
use std::collections::VecDeque;
use std::io::{BufReader, Write};
use std::process::{Child, ChildStdin, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

/// How long one evaluation may take before its worker counts as hung, s (the default of
/// `--solve-timeout`).
pub const SOLVE_TIMEOUT_S: f64 = 600.0;

/// How often a pool waiting for answers looks whether the host asked it to stop.
const STOP_POLL: Duration = Duration::from_millis(200);

/// A message from a worker's reader thread: its slot, its incarnation, and what it read.
type Message = (usize, u64, Read);

/// What a worker's reader thread read.
enum Read {
    /// A line of the protocol.
    Line(String),
    /// The end of the worker's output: it exited.
    End,
    /// Output that is no protocol (a line too long, not UTF-8), or a failed read; the reason.
    Broken(String),
}

struct Worker {
    child: Child,
    stdin: ChildStdin,
    incarnation: u64,
    /// Whether its hello has come and matched.
    introduced: bool,
    /// The job it is working on and when it must be done.
    job: Option<(Job, Instant)>,
}

#[derive(Clone, Debug)]
struct Job {
    id: usize,
    ratios: Vec<f64>,
    attempt: u32,
}

/// What the owner of a pool believes of an answer, an evaluation with its merit when it has one:
/// None, or what it holds that cannot be (a phrase that follows "worker answered").
pub type Check = Box<dyn Fn(&Evaluation, Option<&Merit>) -> Option<String> + Send>;

/// A worker's answer for one design, as the pool gives it back.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// The worker's evaluation, for the design asked, with its merit when it has one (a
    /// descent's), believed by the owner's check.
    Evaluated {
        /// The evaluation.
        evaluation: Evaluation,
        /// The merit.
        merit: Option<Box<Merit>>,
    },
    /// Its worker failed twice (crashed, hung, answered nonsense); the design was not judged.
    Failed {
        /// The design.
        ratios: Vec<f64>,
        /// The last failure, in words.
        reason: String,
    },
}

/// A pool of worker processes (see the module documentation).
pub struct Pool {
    launcher: Launcher,
    setup_line: String,
    /// The hello every worker must send.
    hello: Hello,
    /// What an answer must pass to be believed.
    check: Check,
    timeout: Duration,
    workers: Vec<Worker>,
    sender: Sender<Message>,
    receiver: Receiver<Message>,
    incarnations: u64,
    /// The anchor every request carries (see [`Request::anchor`]).
    anchor: Option<Vec<f64>>,
    /// What every request of the gradient method carries (see [`Request::descent`]).
    descent: Option<DescentRequest>,
}

/// What the pool heard from its workers while it waited.
enum Heard {
    /// A worker answered the job it held.
    Answer(Job, Response),
    /// These workers failed, with the reason (possibly none).
    Failed(Vec<(usize, String)>),
}

impl Pool {
    /// Starts `count` workers with `launcher`, each told `setup`; an answer is believed when
    /// it is for the design asked and passes `check`.
    pub fn new(
        launcher: Launcher,
        setup: &WorkerSetup,
        count: usize,
        timeout: Duration,
        check: Check,
    ) -> Result<Pool, WorkerError> {
        if count == 0 {
            return Err(WorkerError::NoWorkers);
        }
        let (sender, receiver) = channel();
        let mut pool = Pool {
            launcher,
            setup_line: serde_json::to_string(setup).map_err(WorkerError::Encode)?,
            hello: Hello::expected(setup)?,
            check,
            timeout,
            workers: Vec::with_capacity(count),
            sender,
            receiver,
            incarnations: 0,
            anchor: None,
            descent: None,
        };
        for slot in 0..count {
            let worker = pool.spawn(slot)?;
            pool.workers.push(worker);
        }
        Ok(pool)
    }

    /// What the next requests carry: the designs start from the solution of `anchor` (see
    /// [`Request::anchor`]; the standard guess when None), or with `descent` they are scored for
    /// the gradient method (see [`Request::descent`]).
    pub fn set_start(&mut self, anchor: Option<Vec<f64>>, descent: Option<DescentRequest>) {
        self.anchor = anchor;
        self.descent = descent;
    }

    /// Process ids of the running workers (for monitoring).
    pub fn worker_ids(&self) -> Vec<u32> {
        self.workers.iter().map(|w| w.child.id()).collect()
    }

    fn spawn(&mut self, slot: usize) -> Result<Worker, WorkerError> {
        let mut child = self
            .launcher
            .command()
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|source| WorkerError::Start {
                launcher: self.launcher.to_string(),
                source,
            })?;
        if !process::register(&child) {
            process::kill(&mut child);
            return Err(WorkerError::TooMany);
        }
        let mut stdin = child.stdin.take().ok_or(WorkerError::NoPipe("stdin"))?;
        let stdout = child.stdout.take().ok_or(WorkerError::NoPipe("stdout"))?;
        if writeln!(stdin, "{}", self.setup_line).is_err() {
            return Err(ended_early(&self.launcher.to_string(), &mut child));
        }
        self.incarnations += 1;
        let incarnation = self.incarnations;
        let sender = self.sender.clone();
        std::thread::spawn(move || {
            let mut stdout = BufReader::new(stdout);
            loop {
                let read = match read_line(&mut stdout) {
                    Ok(Some(line)) => Read::Line(line),
                    Ok(None) => Read::End,
                    Err(error) => Read::Broken(error.to_string()),
                };
                let last = !matches!(read, Read::Line(_));
                if sender.send((slot, incarnation, read)).is_err() || last {
                    return;
                }
            }
        });
        Ok(Worker {
            child,
            stdin,
            incarnation,
            introduced: false,
            job: None,
        })
    }

    /// Replaces the worker in `slot` (killing it if it still runs) and returns its job, if any.
    fn replace(&mut self, slot: usize) -> Result<Option<Job>, WorkerError> {
        let fresh = self.spawn(slot)?;
        let mut old = std::mem::replace(&mut self.workers[slot], fresh);
        process::kill(&mut old.child);
        Ok(old.job.take().map(|(job, _)| job))
    }

    /// Evaluates every design, in any order across workers, and returns the answers in the
    /// order given. `done` is called as each one finishes (for logging and progress); its error,
    /// or the pool's, stops the evaluation.
    pub fn evaluate_all<E: From<WorkerError>>(
        &mut self,
        designs: &[(usize, Vec<f64>)],
        mut done: impl FnMut(usize, &Answer) -> Result<(), E>,
    ) -> Result<Vec<Answer>, E> {
        let mut queue: VecDeque<Job> = designs
            .iter()
            .map(|(id, ratios)| Job {
                id: *id,
                ratios: ratios.clone(),
                attempt: 0,
            })
            .collect();
        let mut results: Vec<Option<Answer>> = vec![None; designs.len()];
        let position = |id: usize| designs.iter().position(|(d, _)| *d == id);
        let mut remaining = designs.len();
        while remaining > 0 {
            self.dispatch(&mut queue)?;
            let failed = match self.listen()? {
                Heard::Answer(job, response) => {
                    if let Some(index) = position(job.id) {
                        let answer = Answer::Evaluated {
                            evaluation: response.evaluation,
                            merit: response.merit,
                        };
                        done(job.id, &answer)?;
                        results[index] = Some(answer);
                        remaining -= 1;
                    }
                    continue;
                }
                Heard::Failed(failed) => failed,
            };
            self.retry_or_fail(
                failed,
                &mut queue,
                &mut results,
                &position,
                &mut remaining,
                &mut done,
            )?;
        }
        Ok(results.into_iter().flatten().collect())
    }

    /// Hands the next queued jobs to the idle workers, each with its deadline.
    fn dispatch(&mut self, queue: &mut VecDeque<Job>) -> Result<(), WorkerError> {
        for worker in &mut self.workers {
            if worker.job.is_some() {
                continue;
            }
            let Some(job) = queue.pop_front() else { break };
            let line = serde_json::to_string(&Request {
                id: job.id,
                ratios: job.ratios.clone(),
                anchor: self.anchor.clone(),
                descent: self.descent.clone(),
            })
            .map_err(WorkerError::Encode)?;
            let deadline = Instant::now() + self.timeout;
            // A worker that died between jobs fails to take it: its reader reports EOF and the
            // job is retried.
            let _ = writeln!(worker.stdin, "{line}").and_then(|()| worker.stdin.flush());
            worker.job = Some((job, deadline));
        }
        Ok(())
    }

    /// Waits, at most until the nearest deadline, for one worker's answer; classifies what came:
    /// an answer to the job its worker holds, or the workers that failed (crashed, answered
    /// nonsense, ran past their deadline; none when a replaced worker's late line came). A
    /// worker whose first line is no matching hello, or that says none in time, fails the run.
    fn listen(&mut self) -> Result<Heard, WorkerError> {
        let next_deadline = self
            .workers
            .iter()
            .filter_map(|w| w.job.as_ref().map(|(_, d)| *d))
            .min();
        let wait = next_deadline
            .map_or(self.timeout, |d| {
                d.saturating_duration_since(Instant::now())
            })
            .min(STOP_POLL);
        if signals::stop_requested() {
            return Err(WorkerError::Interrupted);
        }
        let failed = |slot: usize, why: String| Ok(Heard::Failed(vec![(slot, why)]));
        match self.receiver.recv_timeout(wait) {
            Ok((slot, incarnation, _)) if self.workers[slot].incarnation != incarnation => {
                Ok(Heard::Failed(Vec::new()))
            }
            Ok((slot, _, Read::Line(line))) if !self.workers[slot].introduced => {
                self.introduce(slot, &line)?;
                Ok(Heard::Failed(Vec::new()))
            }
            Ok((slot, _, Read::Broken(why))) if !self.workers[slot].introduced => {
                self.introduce(slot, &why)?;
                Ok(Heard::Failed(Vec::new()))
            }
            Ok((slot, _, Read::End)) if !self.workers[slot].introduced => {
                let launcher = self.launcher.to_string();
                Err(ended_early(&launcher, &mut self.workers[slot].child))
            }
            Ok((slot, _, Read::End)) => failed(slot, "worker process crashed".to_owned()),
            Ok((slot, _, Read::Broken(why))) => failed(slot, format!("worker sent {why}")),
            Ok((slot, _, Read::Line(line))) => Ok(self.answer(slot, &line)),
            Err(RecvTimeoutError::Timeout) if signals::stop_requested() => {
                Err(WorkerError::Interrupted)
            }
            Err(RecvTimeoutError::Timeout) => self.late(),
            Err(RecvTimeoutError::Disconnected) => Err(WorkerError::ReadersStopped),
        }
    }

    /// The answer `line` of the worker in `slot`, checked against the job it holds: the same
    /// design, and an evaluation the owner's check believes. Anything else fails the worker.
    fn answer(&mut self, slot: usize, line: &str) -> Heard {
        let fail = |why: String| Heard::Failed(vec![(slot, why)]);
        let response = match serde_json::from_str::<Response>(line) {
            Ok(response) => response,
            Err(e) => return fail(format!("worker sent a malformed answer: {e}")),
        };
        let worker = &mut self.workers[slot];
        let Some((job, _)) = worker.job.take_if(|(job, _)| job.id == response.id) else {
            return fail("worker answered a design it was not given".to_owned());
        };
        let evaluation = &response.evaluation;
        let why = if evaluation.ratios != job.ratios {
            format!(
                "worker answered for r = {:?} when asked for r = {:?}",
                evaluation.ratios, job.ratios
            )
        } else if let Some(why) = (self.check)(evaluation, response.merit.as_deref()) {
            format!("worker answered {why}")
        } else {
            return Heard::Answer(job, response);
        };
        worker.job = Some((job, Instant::now() + self.timeout));
        fail(why)
    }

    /// The workers past their deadline; an error when one of them never said its hello.
    fn late(&self) -> Result<Heard, WorkerError> {
        let now = Instant::now();
        let late: Vec<usize> = (0..self.workers.len())
            .filter(
                |&slot| matches!(&self.workers[slot].job, Some((_, deadline)) if *deadline <= now),
            )
            .collect();
        if late.iter().any(|&slot| !self.workers[slot].introduced) {
            return Err(WorkerError::NoHello {
                launcher: self.launcher.to_string(),
                seconds: self.timeout.as_secs_f64(),
            });
        }
        let why = format!("solve exceeded {:.0} s", self.timeout.as_secs_f64());
        Ok(Heard::Failed(
            late.into_iter().map(|slot| (slot, why.clone())).collect(),
        ))
    }

    /// Checks a worker's first line, its hello, against the pool's: a worker of another build, or
    /// one that reads the setup otherwise, fails the run.
    fn introduce(&mut self, slot: usize, line: &str) -> Result<(), WorkerError> {
        let refuse = |what: String| {
            Err(WorkerError::Refused {
                launcher: self.launcher.to_string(),
                what,
                expected: Box::new(self.hello.clone()),
            })
        };
        match serde_json::from_str::<Hello>(line) {
            Ok(hello) if hello == self.hello => {
                self.workers[slot].introduced = true;
                Ok(())
            }
            Ok(hello) => refuse(format!("it is {hello}")),
            Err(_) => {
                let start: String = line.chars().take(120).collect();
                refuse(format!(
                    "its first line is no codesign hello (an older codesign, or something \
                     printing on stdout?): {start:?}"
                ))
            }
        }
    }

    /// Replaces each failed worker; its job goes back to the queue once, then is answered as
    /// failed.
    fn retry_or_fail<E: From<WorkerError>>(
        &mut self,
        failed: Vec<(usize, String)>,
        queue: &mut VecDeque<Job>,
        results: &mut [Option<Answer>],
        position: &impl Fn(usize) -> Option<usize>,
        remaining: &mut usize,
        done: &mut impl FnMut(usize, &Answer) -> Result<(), E>,
    ) -> Result<(), E> {
        for (slot, reason) in failed {
            let Some(mut job) = self.replace(slot)? else {
                continue;
            };
            if job.attempt == 0 {
                eprintln!(
                    "warning: {reason} on design {:?}; retrying it on a fresh worker",
                    job.ratios
                );
                job.attempt += 1;
                queue.push_front(job);
            } else if let Some(index) = position(job.id) {
                let answer = Answer::Failed {
                    ratios: job.ratios,
                    reason,
                };
                done(job.id, &answer)?;
                results[index] = Some(answer);
                *remaining -= 1;
            }
        }
        Ok(())
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        for worker in &mut self.workers {
            process::kill(&mut worker.child);
        }
    }
}

/// The error of a worker started by `launcher` that ended before its hello, with its exit
/// status where it is known within a second (the process is killed after that).
fn ended_early(launcher: &str, child: &mut Child) -> WorkerError {
    let deadline = Instant::now() + Duration::from_secs(1);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status.to_string()),
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(10)),
            _ => {
                process::kill(child);
                break None;
            }
        }
    };
    WorkerError::EndedEarly {
        launcher: launcher.to_owned(),
        status,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::evaluate::{Evaluator, WorkerEvaluator};
    use crate::design::score::{Objective, Status};
    use codesign_core::problem::Space;
    use codesign_core::solve::StartPoint;
    use std::os::unix::fs::PermissionsExt;
    use std::path::PathBuf;

    /// A stand-in worker: a shell script that reads the setup, says `hello` (as JSON), then
    /// answers, hangs or crashes.
    fn script_saying(name: &str, hello: &Hello, body: &str) -> PathBuf {
        let path =
            std::env::temp_dir().join(format!("codesign-worker-{}-{name}.sh", std::process::id()));
        let hello = serde_json::to_string(hello).unwrap();
        let text = format!("#!/bin/sh\nread setup\necho '{hello}'\n{body}\n");
        std::fs::write(&path, text).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    }

    /// A stand-in worker of this build.
    fn script(name: &str, body: &str) -> Launcher {
        Launcher::Program(script_saying(
            name,
            &Hello::expected(&setup()).unwrap(),
            body,
        ))
    }

    fn setup() -> WorkerSetup {
        let task = codesign_core::testing::task();
        WorkerSetup {
            modes: task.limit_modes,
            task,
            solve: codesign_core::testing::settings(),
            space: Space::Actuation,
            penalty: crate::design::penalty::Penalty::PAPER,
            objective: Objective::Cost,
            robot_hash: codesign_core::hash::fnv1a(codesign_core::model::BUILT_IN_URDF.as_bytes()),
        }
    }

    /// A `done` of `Pool::evaluate_all` that does nothing.
    fn none(_: usize, _: &Answer) -> Result<(), WorkerError> {
        Ok(())
    }

    /// The check of a run on the cost under the paper's penalty.
    fn check() -> Check {
        Box::new(|evaluation, _| {
            evaluation.implausible(&crate::design::penalty::Penalty::PAPER, false)
        })
    }

    fn designs() -> Vec<(usize, Vec<f64>)> {
        vec![(0, vec![6.0, 3.0, 1.0, 1.0]), (1, vec![7.0, 3.0, 1.0, 1.0])]
    }

    #[test]
    fn hung_and_crashed_workers_are_replaced_and_their_designs_penalised() {
        for (name, body, reason) in [
            ("hang", "while read request; do sleep 30; done", "exceeded"),
            ("crash", "read request; exit 3", "crashed"),
        ] {
            let launcher = script(name, body);
            let timeout = Duration::from_millis(300);
            let mut pool = WorkerEvaluator::new(launcher.clone(), &setup(), 2, timeout).unwrap();
            let mut finished = Vec::new();
            let results = pool
                .evaluate(&designs(), None, &mut |id, evaluation| {
                    finished.push((id, evaluation.clone()));
                    Ok(())
                })
                .unwrap();
            assert_eq!(results.len(), 2);
            assert_eq!(finished.len(), 2);
            for (evaluation, (_, ratios)) in results.iter().zip(designs()) {
                assert_eq!(evaluation.ratios, ratios);
                assert_eq!(evaluation.cost, 1e6);
                assert_eq!(evaluation.status, Status::WorkerFailed);
                let text = evaluation.reason.as_deref().unwrap();
                assert!(text.contains(reason) && text.contains("twice"), "{text}");
            }
            drop(pool);
            remove(launcher);
        }
    }

    fn remove(launcher: Launcher) {
        if let Launcher::Program(path) = launcher {
            std::fs::remove_file(path).unwrap();
        }
    }

    #[test]
    fn a_worker_of_another_build_is_refused_naming_both() {
        let mut other = Hello::expected(&setup()).unwrap();
        other.codesign = "0.0.1".to_owned();
        let path = script_saying("other", &other, "while read request; do sleep 30; done");
        let launcher = Launcher::Shell(format!("{} worker", path.display()));
        let mut pool = Pool::new(launcher, &setup(), 1, Duration::from_secs(20), check()).unwrap();
        let error = pool.evaluate_all(&designs(), none).unwrap_err().to_string();
        assert!(error.contains("refused the worker started by"), "{error}");
        assert!(error.contains("it is codesign 0.0.1"), "{error}");
        assert!(
            error.contains(concat!("this run is codesign ", env!("CARGO_PKG_VERSION"))),
            "{error}"
        );
        drop(pool);
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn answers_come_back_in_the_order_asked() {
        // Answers every request with its own id and a cost of 10 + id, after a delay that
        // makes later requests finish first.
        let body = r#"while read request; do
  id=$(echo "$request" | sed 's/.*"id":\([0-9]*\).*/\1/')
  ratios=$(echo "$request" | sed 's/.*"ratios":\(\[[^]]*\]\).*/\1/')
  sleep 0.$((3 - id))
  echo "{\"id\":$id,\"evaluation\":{\"ratios\":$ratios,\"cost\":1$id,\"feasible\":true,\"status\":\"Solve_Succeeded\",\"iterations\":1,\"seconds\":0.1}}"
done"#;
        let launcher = script("answer", body);
        let timeout = Duration::from_secs(20);
        let mut pool = Pool::new(launcher.clone(), &setup(), 2, timeout, check()).unwrap();
        let results = pool.evaluate_all(&designs(), none).unwrap();
        let cost = |answer: &Answer| match answer {
            Answer::Evaluated { evaluation, .. } => evaluation.cost,
            Answer::Failed { .. } => f64::NAN,
        };
        let costs: Vec<f64> = results.iter().map(cost).collect();
        assert_eq!(costs, vec![10.0, 11.0]);
        drop(pool);
        remove(launcher);
    }

    /// A writer whose reader is gone (or whose disk is full).
    struct Closed(std::io::ErrorKind);

    impl Write for Closed {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(self.0.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// The answers of a worker (run in-process) to `requests`, in order.
    fn served(requests: &[Request]) -> Vec<Evaluation> {
        responses(requests)
            .into_iter()
            .map(|r| r.evaluation)
            .collect()
    }

    /// The responses of a worker (run in-process) to `requests`, in order.
    fn responses(requests: &[Request]) -> Vec<Response> {
        let mut input = serde_json::to_string(&setup()).unwrap();
        for request in requests {
            input.push('\n');
            input.push_str(&serde_json::to_string(request).unwrap());
        }
        input.push('\n');
        let mut output = Vec::new();
        serve(input.as_bytes(), &mut output).unwrap();
        let text = String::from_utf8(output).unwrap();
        let lines: Vec<&str> = text.lines().skip(1).collect();
        let answers = lines.iter().map(|line| serde_json::from_str(line).unwrap());
        answers.collect()
    }

    /// A descent's requests answered by a worker: the evaluations and merits of this process's
    /// fitness to the bit (the warm start carried as JSON included), which the parent's check
    /// believes; a merit changed in any part it checks is refused.
    #[test]
    fn descents_are_answered_with_the_merits_of_this_process() {
        let fitness = setup().fitness().unwrap();
        let design = vec![9.0, 7.7, 3.0, 3.0];
        let start = fitness.descend_from(&design, &[]).merit.unwrap().starts;
        let request = |id: usize, ratios: &[f64], start: &[StartPoint]| Request {
            id,
            ratios: ratios.to_vec(),
            anchor: None,
            descent: Some(DescentRequest {
                starts: start.to_vec(),
            }),
        };
        let near = [8.9, 7.6, 2.9, 2.95];
        let answered = responses(&[
            request(0, &design, &[]),
            request(1, &near, &start),
            request(2, &[20.0, 7.7, 3.0, 3.0], &start),
        ]);
        let own = [
            fitness.descend_from(&design, &[]),
            fitness.descend_from(&near, &start),
            fitness.descend_from(&[20.0, 7.7, 3.0, 3.0], &start),
        ];
        let untimed = |e: &Evaluation| Evaluation {
            seconds: 0.0,
            ..e.clone()
        };
        for (response, own) in answered.iter().zip(&own) {
            assert_eq!(untimed(&response.evaluation), untimed(&own.evaluation));
            assert_eq!(response.merit.as_deref(), own.merit.as_ref());
        }
        assert!(
            answered[2].merit.is_none(),
            "an invalid design has no merit"
        );
        let (evaluation, merit) = (&answered[1].evaluation, *answered[1].merit.clone().unwrap());
        assert_eq!(fitness.implausible_merit(evaluation, &merit), None);
        let mut lies = Vec::new();
        for change in 0..5 {
            let mut lie = merit.clone();
            match change {
                0 => lie.value = f64::NAN,
                1 => lie.gradient.truncate(3),
                2 => lie.feasible_cost = lie.feasible_cost.map(|c| c + 1.0),
                3 => lie.starts[0].x.truncate(1),
                _ => lie.starts[0].z_lower[0] = -1.0,
            }
            lies.push(fitness.implausible_merit(evaluation, &lie));
        }
        assert!(lies.iter().all(Option::is_some), "{lies:?}");
    }

    #[test]
    fn designs_started_from_their_anchor_find_the_cold_optima_in_fewer_iterations() {
        // Near the 1 kg optimum (9, 7.72, 3, 3): every design is feasible from either start.
        let anchor = vec![9.0, 7.7, 3.0, 3.0];
        let designs = [
            [8.9, 7.6, 2.9, 2.95],
            [9.0, 7.8, 3.0, 2.9],
            [8.8, 7.5, 3.0, 3.0],
        ];
        let requests = |anchor: Option<&Vec<f64>>| -> Vec<Request> {
            let each = designs.iter().enumerate();
            each.map(|(id, ratios)| Request {
                id,
                ratios: ratios.to_vec(),
                anchor: anchor.cloned(),
                descent: None,
            })
            .collect()
        };
        let cold = served(&requests(None));
        let warm = served(&requests(Some(&anchor)));
        let sum = |answers: &[Evaluation]| answers.iter().map(|e| e.iterations).sum::<usize>();
        for (c, w) in cold.iter().zip(&warm) {
            assert!(c.feasible && w.feasible, "{c:?} {w:?}");
            assert!(
                (c.cost - w.cost).abs() < 1e-6 * c.cost,
                "{} vs {}",
                c.cost,
                w.cost
            );
        }
        assert!(sum(&warm) < sum(&cold), "{} vs {}", sum(&warm), sum(&cold));
        // An anchor outside the design space starts nothing: the cold answers, to the bit.
        let invalid = served(&requests(Some(&vec![20.0, 7.7, 3.0, 3.0])));
        let untimed = |answers: Vec<Evaluation>| -> Vec<Evaluation> {
            let zero = |e: Evaluation| Evaluation { seconds: 0.0, ..e };
            answers.into_iter().map(zero).collect()
        };
        assert_eq!(untimed(invalid), untimed(cold));
    }

    #[test]
    fn a_worker_whose_parent_is_gone_ends_quietly() {
        let input = format!(
            "{}\n{{\"id\":0,\"ratios\":[1.0]}}\n",
            serde_json::to_string(&setup()).unwrap()
        );
        let gone = serve(input.as_bytes(), Closed(std::io::ErrorKind::BrokenPipe));
        assert!(gone.is_ok(), "{gone:?}");
        let full = serve(input.as_bytes(), Closed(std::io::ErrorKind::StorageFull));
        let full = full.unwrap_err();
        assert!(matches!(full, WorkerError::Answer(_)), "{full:?}");
        assert!(
            full.to_string().starts_with("worker: cannot answer: "),
            "{full}"
        );
    }
}
