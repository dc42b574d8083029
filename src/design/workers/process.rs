//! Worker processes as the operating system sees them: each started in a process group of its
//! own, so that a hung worker is killed with everything it started (a shell's children, an
//! `srun` step), and all of them are killed when the run ends, fails, or is interrupted by INT,
//! TERM or HUP, and by a watchdog in each group when the run's process dies any other way
//! (SIGKILL, a crash).

use codesign_core::signals;
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Child, Command};
use std::sync::OnceLock;

pub use codesign_core::signals::MAX_GROUPS;

/// How a worker process is started.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Launcher {
    /// `PROGRAM worker` (normally this executable).
    Program(PathBuf),
    /// A shell command (`sh -c`) that starts one worker speaking the protocol on its
    /// stdin/stdout, e.g. `srun --ntasks=1 /path/codesign worker` or `ssh node7 codesign worker`.
    Shell(String),
}

impl Launcher {
    /// The process to start: in a process group of its own, killed if this process dies.
    pub(super) fn command(&self) -> Command {
        let mut command = match self {
            Launcher::Program(program) => {
                let mut command = Command::new(program);
                command.arg("worker");
                command
            }
            Launcher::Shell(line) => {
                let mut command = Command::new("sh");
                command.arg("-c").arg(line);
                command
            }
        };
        command.process_group(0);
        let lifeline = lifeline();
        // SAFETY: the closure runs in the child between fork and exec and only makes
        // async-signal-safe calls (prctl, getpid, fork, and in the watchdog read, kill, close).
        unsafe {
            command.pre_exec(move || {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                if let Some(read_end) = lifeline {
                    start_watchdog(read_end)?;
                }
                Ok(())
            });
        }
        command
    }
}

/// The read end of a pipe whose write end only this process holds, for the workers' watchdogs:
/// it reads end of file exactly when this process is gone, however it died. None when no pipe
/// could be made (the workers then have only `PR_SET_PDEATHSIG`).
fn lifeline() -> Option<libc::c_int> {
    static LIFELINE: OnceLock<Option<libc::c_int>> = OnceLock::new();
    *LIFELINE.get_or_init(|| {
        let mut ends = [0; 2];
        // SAFETY: pipe2 writes two descriptors into `ends`; both close on exec, so no program a
        // worker runs holds the write end, and this process keeps both open for its lifetime.
        (unsafe { libc::pipe2(ends.as_mut_ptr(), libc::O_CLOEXEC) } == 0).then_some(ends[0])
    })
}

/// In a worker's process between fork and exec (its process group already its own): forks a
/// watchdog into the group that blocks reading the lifeline and, at its end of file (the run's
/// process died, even by SIGKILL), kills the whole group: the worker and all it started. The
/// watchdog first closes every other descriptor, so that it holds no worker's pipe open; it
/// dies with the group when the run kills a worker.
///
/// # Safety
/// Only between fork and exec, where only async-signal-safe calls are allowed.
unsafe fn start_watchdog(read_end: libc::c_int) -> std::io::Result<()> {
    let group = libc::getpid();
    match libc::fork() {
        -1 => Err(std::io::Error::last_os_error()),
        0 => {
            libc::dup2(read_end, 0);
            if libc::syscall(libc::SYS_close_range, 1u32, u32::MAX, 0u32) != 0 {
                for fd in 1..65_536 {
                    libc::close(fd);
                }
            }
            let mut byte = 0u8;
            while libc::read(0, (&raw mut byte).cast(), 1) != 0
                && std::io::Error::last_os_error().raw_os_error() == Some(libc::EINTR)
            {}
            libc::kill(-group, libc::SIGKILL);
            libc::_exit(0)
        }
        _ => Ok(()),
    }
}

impl std::fmt::Display for Launcher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Launcher::Program(program) => write!(f, "{} worker", program.display()),
            Launcher::Shell(line) => f.write_str(line),
        }
    }
}

/// Notes the process group of a worker just started (its pid), so that INT, TERM or HUP kill
/// it; false when the table is full.
pub(super) fn register(child: &Child) -> bool {
    signals::register_group(i32::try_from(child.id()).unwrap_or(0))
}

/// Kills a worker's whole process group, reaps the worker and forgets the group.
pub(super) fn kill(child: &mut Child) {
    let group = i32::try_from(child.id()).unwrap_or(0);
    if group > 0 {
        // SAFETY: kill with a negative pid signals the process group the worker leads.
        unsafe { libc::kill(-group, libc::SIGKILL) };
    }
    let _ = child.kill();
    let _ = child.wait();
    signals::forget_group(group);
}
