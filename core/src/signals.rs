//! What INT, TERM and HUP (a closed terminal or ssh session) do to this process: the process
//! groups of running workers are killed with everything they started, then the process ends as
//! the signal would have; but never in the middle of writing a file. A signal that arrives while
//! a [`Deferral`] lives takes effect when the last one ends, once the file being written is in
//! place (or its temporary removed). The handler makes only async-signal-safe calls.
//!
//! A host that handles the signals itself (the Python package, whose interpreter owns INT) calls
//! [`leave_signals_to_host`] first: no handler is installed, and the host stops one piece of work
//! at a time. It runs each piece [`under`] a [`StopToken`] of its own and stops it with
//! [`StopToken::stop`]: the IPOPT solves of that work (on its thread and the threads
//! [`crate::parallel::in_order`] starts for it) end at their next iteration with
//! [`crate::ipopt::Error::Stopped`], never with a verdict, and a co-design run stops before its
//! next evaluation, its log kept for `--resume`. Work under other tokens, or none, runs on.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, AtomicI32, AtomicUsize, Ordering};
use std::sync::{Arc, Once};

/// The most worker process groups alive at once in one process.
pub const MAX_GROUPS: usize = 4096;

/// The process groups of the running workers (0: a free slot), for the handler, which may only
/// read atomics.
static GROUPS: [AtomicI32; MAX_GROUPS] = [const { AtomicI32::new(0) }; MAX_GROUPS];

/// How many deferrals live (writes under way, on any thread).
static DEFERRING: AtomicUsize = AtomicUsize::new(0);

/// A signal that arrived during a deferral (0: none).
static PENDING: AtomicI32 = AtomicI32::new(0);

/// Whether the host handles INT, TERM and HUP ([`leave_signals_to_host`]).
static HOSTED: AtomicBool = AtomicBool::new(false);

/// Installs no handler, now or later: the host process handles INT, TERM and HUP and stops its
/// work through [`StopToken`]s. Call it before any work starts.
pub fn leave_signals_to_host() {
    HOSTED.store(true, Ordering::SeqCst);
}

/// The request to stop one piece of work: clones share it.
#[derive(Clone, Debug, Default)]
pub struct StopToken(Arc<AtomicBool>);

impl StopToken {
    /// A token not yet stopped.
    pub fn new() -> StopToken {
        StopToken::default()
    }

    /// Asks the work under this token to stop as soon as it can; it cannot be withdrawn.
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether [`StopToken::stop`] was called.
    pub fn stopped(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

thread_local! {
    /// The token of the work running on this thread ([`under`]).
    static CURRENT: RefCell<Option<StopToken>> = const { RefCell::new(None) };
}

/// Runs `work` on this thread under `token` (None: under no token, never stopped), then puts
/// back the token this thread had.
pub fn under<T>(token: Option<StopToken>, work: impl FnOnce() -> T) -> T {
    /// Puts the earlier token back, even when `work` panics.
    struct Restore(Option<StopToken>);
    impl Drop for Restore {
        fn drop(&mut self) {
            CURRENT.with(|current| *current.borrow_mut() = self.0.take());
        }
    }
    let _restore = Restore(CURRENT.with(|current| current.replace(token)));
    work()
}

/// The token of the work on this thread, for the threads it starts to run [`under`].
pub fn current() -> Option<StopToken> {
    CURRENT.with(|current| current.borrow().clone())
}

/// Whether the work on this thread was asked to stop (its token's [`StopToken::stop`]).
pub fn stop_requested() -> bool {
    CURRENT.with(|current| current.borrow().as_ref().is_some_and(StopToken::stopped))
}

/// Notes a worker's process group, so that INT, TERM or HUP kill it; false when the table is
/// full.
pub fn register_group(group: i32) -> bool {
    install();
    group > 0
        && GROUPS.iter().any(|slot| {
            slot.compare_exchange(0, group, Ordering::SeqCst, Ordering::SeqCst)
                .is_ok()
        })
}

/// Forgets a worker's process group (the worker was killed and reaped).
pub fn forget_group(group: i32) {
    for slot in &GROUPS {
        let _ = slot.compare_exchange(group, 0, Ordering::SeqCst, Ordering::SeqCst);
    }
}

/// While alive, INT, TERM and HUP wait: see the module's documentation.
#[must_use = "signals wait only while the deferral lives"]
pub struct Deferral(());

/// Defers INT, TERM and HUP until the returned deferral (and any other alive) is dropped.
pub fn defer() -> Deferral {
    install();
    DEFERRING.fetch_add(1, Ordering::SeqCst);
    Deferral(())
}

impl Drop for Deferral {
    fn drop(&mut self) {
        if DEFERRING.fetch_sub(1, Ordering::SeqCst) == 1 {
            let pending = PENDING.swap(0, Ordering::SeqCst);
            if pending != 0 {
                terminate(pending);
            }
        }
    }
}

/// The handler of INT, TERM and HUP: noted while a deferral lives, else acted on at once.
extern "C" fn on_signal(signal: libc::c_int) {
    if DEFERRING.load(Ordering::SeqCst) > 0 {
        PENDING.store(signal, Ordering::SeqCst);
    } else {
        terminate(signal);
    }
}

/// Kills every worker's process group, then ends this process as `signal` would have. Only
/// async-signal-safe calls.
fn terminate(signal: libc::c_int) {
    for slot in &GROUPS {
        let group = slot.load(Ordering::SeqCst);
        if group > 0 {
            // SAFETY: kill with a negative pid signals the process group the worker leads.
            unsafe { libc::kill(-group, libc::SIGKILL) };
        }
    }
    // SAFETY: signal and raise are async-signal-safe; the default action ends the process.
    unsafe {
        libc::signal(signal, libc::SIG_DFL);
        libc::raise(signal);
    }
}

/// Installs [`on_signal`] for INT, TERM and HUP, once per process, unless the host handles them.
fn install() {
    static INSTALLED: Once = Once::new();
    if HOSTED.load(Ordering::SeqCst) {
        return;
    }
    INSTALLED.call_once(|| {
        for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            // SAFETY: the handler only makes async-signal-safe calls.
            unsafe { libc::signal(signal, on_signal as *const () as libc::sighandler_t) };
        }
    });
}

#[cfg(test)]
mod tests {
    use super::defer;
    use std::os::unix::process::ExitStatusExt;
    use std::path::PathBuf;

    /// Set in the child process the test starts (the test binary again, running this test).
    const CHILD: &str = "CODESIGN_SIGNALS_TEST_FOLDER";

    #[test]
    fn a_signal_during_a_deferral_takes_effect_when_it_ends() {
        if let Some(folder) = std::env::var_os(CHILD).map(PathBuf::from) {
            let deferral = defer();
            // SAFETY: a signal to this process, which the handler defers.
            unsafe { libc::raise(libc::SIGINT) };
            std::fs::write(folder.join("after-signal"), "").unwrap();
            drop(deferral);
            std::fs::write(folder.join("after-deferral"), "").unwrap();
            return;
        }
        let folder = std::env::temp_dir().join(format!("codesign-signals-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&folder);
        std::fs::create_dir_all(&folder).unwrap();
        let status = std::process::Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "signals::tests::a_signal_during_a_deferral_takes_effect_when_it_ends",
            ])
            .env(CHILD, &folder)
            .stdout(std::process::Stdio::null())
            .status()
            .unwrap();
        assert_eq!(status.signal(), Some(libc::SIGINT), "{status:?}");
        assert!(
            folder.join("after-signal").exists(),
            "the signal did not wait"
        );
        assert!(
            !folder.join("after-deferral").exists(),
            "the signal was lost"
        );
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
