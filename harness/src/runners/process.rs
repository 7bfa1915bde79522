//! A measured child process: wall time, user + system CPU and peak RSS from
//! `wait4`'s rusage, a time limit (the child's process group is killed with SIGKILL when
//! it is exceeded), the exit code or signal, and the tail of stderr.
//!
//! The child writes stdout and stderr to files in the run's work directory (no pipe can
//! fill up and block it). The wait wakes when the child exits (a pidfd polled with the
//! time left; `wait4` polling as a fallback on kernels without pidfds), so the wall time
//! is exact to the wake-up, not to a polling period. Nothing here panics: every failure
//! is a [`RunError`] or a field of [`ProcessStats`].

use super::{ProcessStats, RunError};
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Default per-run time limit.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(600);

/// How many stderr lines the stats keep.
pub const STDERR_TAIL_LINES: usize = 20;

/// Runs `cmd` in `workdir` (its stdout/stderr go to `<log_name>.stdout` / `.stderr`
/// there) until it exits or `timeout` passes, and measures it.
///
/// `Err` only when the child could not be started; [`RunError::Missing`] when the program
/// does not exist.
pub fn run_measured(
    mut cmd: Command,
    workdir: &Path,
    log_name: &str,
    timeout: Duration,
) -> Result<ProcessStats, RunError> {
    let out_path = workdir.join(format!("{log_name}.stdout"));
    let err_path = workdir.join(format!("{log_name}.stderr"));
    let out = std::fs::File::create(&out_path).map_err(|e| io_err(&out_path, e))?;
    let err = std::fs::File::create(&err_path).map_err(|e| io_err(&err_path, e))?;
    cmd.current_dir(workdir)
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .process_group(0);
    let start = Instant::now();
    let child = cmd.spawn().map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => {
            RunError::Missing(format!("{:?} not found", cmd.get_program()))
        }
        _ => RunError::Io(format!("cannot start {:?}: {e}", cmd.get_program())),
    })?;
    let pid = child.id() as libc::pid_t;
    let (status, usage, timed_out) = wait_with_limit(pid, start, timeout);
    let mut stats = ProcessStats {
        wall_seconds: start.elapsed().as_secs_f64(),
        cpu_seconds: cpu_seconds(&usage),
        // Linux reports ru_maxrss in KiB.
        peak_rss_bytes: (usage.ru_maxrss.max(0) as u64) * 1024,
        timed_out,
        stderr_tail: tail_lines(&err_path, STDERR_TAIL_LINES),
        ..ProcessStats::default()
    };
    if let Some(status) = status {
        if libc::WIFEXITED(status) {
            stats.exit_code = Some(libc::WEXITSTATUS(status));
        } else if libc::WIFSIGNALED(status) {
            stats.signal = Some(libc::WTERMSIG(status));
        }
    }
    Ok(stats)
}

/// Waits for the child to exit, at most until `timeout`: blocks on a pidfd of the child
/// (readable when it exits) with the time left; past the limit kills its process group
/// and reaps it. Falls back to [`poll_with_limit`] when the kernel has no pidfds.
fn wait_with_limit(
    pid: libc::pid_t,
    start: Instant,
    timeout: Duration,
) -> (Option<libc::c_int>, libc::rusage, bool) {
    // SAFETY: pidfd_open takes a pid and flags and returns a new descriptor or -1.
    let fd = unsafe { libc::syscall(libc::SYS_pidfd_open, pid, 0) } as libc::c_int;
    if fd < 0 {
        return poll_with_limit(pid, start, timeout);
    }
    let mut timed_out = false;
    loop {
        let left = timeout.saturating_sub(start.elapsed());
        if left.is_zero() {
            timed_out = true;
            break;
        }
        let mut pfd = libc::pollfd {
            fd,
            events: libc::POLLIN,
            revents: 0,
        };
        let ms = left.as_millis().clamp(1, i32::MAX as u128) as libc::c_int;
        // SAFETY: one valid pollfd.
        let r = unsafe { libc::poll(&mut pfd, 1, ms) };
        if r > 0 {
            break;
        }
        if r < 0 && std::io::Error::last_os_error().kind() != std::io::ErrorKind::Interrupted {
            // SAFETY: our own descriptor.
            unsafe { libc::close(fd) };
            return poll_with_limit(pid, start, timeout);
        }
    }
    if timed_out {
        // SAFETY: signalling our child's own process group (set by process_group(0));
        // the child is not reaped yet, so its pid cannot have been reused.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
            libc::kill(pid, libc::SIGKILL);
        }
    }
    // SAFETY: our own descriptor.
    unsafe { libc::close(fd) };
    let mut status: libc::c_int = 0;
    // SAFETY: rusage is plain old data; all-zero is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: valid pointers to owned locals; pid is our own child (blocking wait).
        let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if r == pid {
            return (Some(status), usage, timed_out);
        }
        if r < 0 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted {
            continue;
        }
        return (None, usage, timed_out);
    }
}

/// Polls `wait4(pid, WNOHANG)` until the child exits; past `timeout` kills its process
/// group and reaps it. Returns the wait status (None if waiting failed), the rusage and
/// whether the limit was hit.
fn poll_with_limit(
    pid: libc::pid_t,
    start: Instant,
    timeout: Duration,
) -> (Option<libc::c_int>, libc::rusage, bool) {
    let mut status: libc::c_int = 0;
    // SAFETY: rusage is plain old data; all-zero is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let mut timed_out = false;
    loop {
        // SAFETY: valid pointers to owned locals; pid is our own child.
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            return (Some(status), usage, timed_out);
        }
        if r < 0 {
            let e = std::io::Error::last_os_error();
            if e.kind() == std::io::ErrorKind::Interrupted {
                continue;
            }
            return (None, usage, timed_out);
        }
        let elapsed = start.elapsed();
        if !timed_out && elapsed >= timeout {
            timed_out = true;
            // SAFETY: signalling our child's own process group (set by process_group(0)).
            unsafe {
                libc::kill(-pid, libc::SIGKILL);
                libc::kill(pid, libc::SIGKILL);
            }
            continue;
        }
        // Fine polling first (short runs are timed to the millisecond), coarser later.
        let nap = if elapsed < Duration::from_millis(200) {
            1
        } else {
            10
        };
        std::thread::sleep(Duration::from_millis(nap));
    }
}

fn cpu_seconds(u: &libc::rusage) -> f64 {
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    tv(u.ru_utime) + tv(u.ru_stime)
}

/// The last `n` lines of a text file (lossy UTF-8), at most 64 KiB read from its end.
pub fn tail_lines(path: &Path, n: usize) -> String {
    use std::io::{Read, Seek, SeekFrom};
    let Ok(mut f) = std::fs::File::open(path) else {
        return String::new();
    };
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    let from = len.saturating_sub(64 * 1024);
    let mut buf = Vec::new();
    if f.seek(SeekFrom::Start(from)).is_err() || f.read_to_end(&mut buf).is_err() {
        return String::new();
    }
    let text = String::from_utf8_lossy(&buf);
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

fn io_err(path: &Path, e: std::io::Error) -> RunError {
    RunError::Io(format!("{}: {e}", path.display()))
}

/// Turns the stats of a finished child into `Ok` when it exited 0, or a
/// [`RunError::Failed`] that says how it ended.
pub fn check_exit(what: &str, stats: ProcessStats) -> Result<ProcessStats, RunError> {
    let how = if stats.timed_out {
        format!(
            "{what}: killed at the time limit after {:.1} s",
            stats.wall_seconds
        )
    } else if let Some(sig) = stats.signal {
        format!("{what}: killed by signal {sig}")
    } else if stats.exit_code == Some(0) {
        return Ok(stats);
    } else {
        match stats.exit_code {
            Some(c) => format!("{what}: exit code {c}"),
            None => format!("{what}: ended without an exit status"),
        }
    };
    let message = if stats.stderr_tail.is_empty() {
        how
    } else {
        format!("{how}; stderr: {}", stats.stderr_tail)
    };
    Err(RunError::Failed { message, stats })
}

/// Exit code by which the Python scripts say their peer module cannot be imported.
pub const EXIT_MISSING_MODULE: i32 = 3;

/// Runs `scripts/<script>` with the venv's Python in `workdir` with `args`, measured.
/// Exit code [`EXIT_MISSING_MODULE`] or a missing venv is [`RunError::Missing`]; the JSON
/// the script wrote to `workdir/meta.json` is returned with the stats.
pub fn run_python_script(
    script: &str,
    args: &[String],
    workdir: &Path,
    timeout: Duration,
) -> Result<(ProcessStats, serde_json::Value), RunError> {
    let python = super::venv_python();
    if !python.exists() {
        return Err(RunError::Missing(format!(
            "{} not found: run scripts/setup.sh --peers",
            python.display()
        )));
    }
    let path = super::project_root().join("scripts").join(script);
    let mut cmd = Command::new(&python);
    cmd.arg(&path).args(args);
    let log = script.trim_end_matches(".py");
    let stats = run_measured(cmd, workdir, log, timeout)?;
    if stats.exit_code == Some(EXIT_MISSING_MODULE) {
        return Err(RunError::Missing(stats.stderr_tail));
    }
    let stats = check_exit(script, stats)?;
    let meta_path = workdir.join("meta.json");
    let meta = std::fs::read_to_string(&meta_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or(serde_json::Value::Null);
    Ok((stats, meta))
}
