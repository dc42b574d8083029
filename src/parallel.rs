//! Independent work on threads of this process, its results in the order asked: what the
//! in-process evaluator and the experiment's capacity searches share. Whoever calls it keeps
//! MUMPS, which is not thread-safe, to one thread.

use codesign_core::ipopt::LinearSolver;
use codesign_core::signals;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::channel;

/// Runs `work` on every index below `count` on up to `threads` threads (at least one), each
/// thread taking the next index not yet taken until none is left or `stop` says to stop. The
/// threads work under the calling thread's stop token ([`signals::under`]).
/// `heard` hears each result in this thread as it finishes, in any order; its error stops the
/// threads at their next index and is returned. The results in index order, None where an
/// index was never worked on.
pub fn in_order<T: Send, E>(
    count: usize,
    threads: usize,
    stop: impl Fn() -> bool + Sync,
    work: impl Fn(usize) -> T + Sync,
    mut heard: impl FnMut(usize, &T) -> Result<(), E>,
) -> Result<Vec<Option<T>>, E> {
    let next = AtomicUsize::new(0);
    let (sender, receiver) = channel();
    let mut results: Vec<Option<T>> = Vec::new();
    results.resize_with(count, || None);
    let token = signals::current();
    std::thread::scope(|scope| -> Result<(), E> {
        for _ in 0..threads.clamp(1, count.max(1)) {
            let (sender, token) = (sender.clone(), token.clone());
            let (next, stop, work) = (&next, &stop, &work);
            scope.spawn(move || {
                signals::under(token, || loop {
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    if index >= count || stop() {
                        return;
                    }
                    if sender.send((index, work(index))).is_err() {
                        return;
                    }
                })
            });
        }
        drop(sender);
        for (index, result) in receiver.iter() {
            let heard = heard(index, &result);
            results[index] = Some(result);
            if let Err(error) = heard {
                next.store(count, Ordering::Relaxed);
                return Err(error);
            }
        }
        Ok(())
    })?;
    Ok(results)
}

/// How many threads (or worker processes) to run on: `asked`, else one per core; at least one.
pub fn threads(asked: Option<usize>) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    asked.unwrap_or(cores).max(1)
}

/// How many threads a process's independent solves run on: [`threads`], but one with MUMPS.
pub fn solve_threads(asked: Option<usize>, linear_solver: LinearSolver) -> usize {
    match linear_solver {
        LinearSolver::Mumps => 1,
        LinearSolver::Ldl => threads(asked),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_the_order_asked_whatever_the_threads() {
        for threads in [1, 2, 5] {
            let squares = in_order(7, threads, || false, |i| i * i, |_, _| Ok::<(), ()>(()));
            let expected: Vec<Option<usize>> = (0..7).map(|i| Some(i * i)).collect();
            assert_eq!(squares, Ok(expected), "{threads} threads");
        }
        let stopped = in_order(3, 2, || true, |i| i, |_, _| Ok::<(), ()>(()));
        assert_eq!(stopped, Ok(vec![None, None, None]));
        let failed = in_order(
            4,
            1,
            || false,
            |i| i,
            |i, _| if i == 1 { Err(i) } else { Ok(()) },
        );
        assert_eq!(failed, Err(1));
    }

    /// The threads work under the caller's stop token: a stopped token stops them, and work
    /// under none is never stopped.
    #[test]
    fn the_threads_work_under_the_callers_stop_token() {
        let token = signals::StopToken::new();
        token.stop();
        let asked = |_: usize| signals::stop_requested();
        let ok = |_: usize, _: &bool| Ok::<(), ()>(());
        let stopped = signals::under(Some(token), || in_order(3, 2, || false, asked, ok));
        assert_eq!(stopped, Ok(vec![Some(true); 3]));
        let free = in_order(3, 2, || false, asked, ok);
        assert_eq!(free, Ok(vec![Some(false); 3]));
    }
}
