//! The measured child process: wall time, time limit, crash by signal, missing program.

use harness::runners::process::{check_exit, run_measured};
use harness::runners::RunError;
use std::process::Command;
use std::time::Duration;

fn sh(script: &str) -> Command {
    let mut c = Command::new("sh");
    c.args(["-c", script]);
    c
}

#[test]
fn sleep_is_timed_and_exits_zero() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_measured(
        sh("sleep 0.2"),
        dir.path(),
        "sleep",
        Duration::from_secs(10),
    )
    .unwrap();
    assert!(s.wall_seconds >= 0.2, "wall {}", s.wall_seconds);
    assert!(s.wall_seconds < 5.0, "wall {}", s.wall_seconds);
    assert_eq!(s.exit_code, Some(0));
    assert_eq!(s.signal, None);
    assert!(!s.timed_out);
    assert!(s.peak_rss_bytes > 0);
    assert!(check_exit("sleep", s).is_ok());
}

#[test]
fn child_is_killed_at_the_time_limit() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_measured(
        sh("sleep 30"),
        dir.path(),
        "slow",
        Duration::from_millis(300),
    )
    .unwrap();
    assert!(s.timed_out);
    assert!(
        s.wall_seconds >= 0.3 && s.wall_seconds < 10.0,
        "wall {}",
        s.wall_seconds
    );
    assert_eq!(s.signal, Some(libc_sigkill()));
    assert!(matches!(
        check_exit("slow", s),
        Err(RunError::Failed { .. })
    ));
}

#[test]
fn crash_is_a_signal_and_stderr_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let cmd = sh("echo first >&2; echo 'last words' >&2; kill -SEGV $$");
    let s = run_measured(cmd, dir.path(), "crash", Duration::from_secs(10)).unwrap();
    assert_eq!(s.signal, Some(11));
    assert_eq!(s.exit_code, None);
    assert!(s.stderr_tail.ends_with("last words"), "{:?}", s.stderr_tail);
    match check_exit("crash", s) {
        Err(RunError::Failed { message, .. }) => assert!(message.contains("signal 11")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn exit_code_and_cpu_time() {
    let dir = tempfile::tempdir().unwrap();
    let busy = "i=0; while [ $i -lt 200000 ]; do i=$((i+1)); done; exit 7";
    let s = run_measured(sh(busy), dir.path(), "busy", Duration::from_secs(60)).unwrap();
    assert_eq!(s.exit_code, Some(7));
    assert!(s.cpu_seconds > 0.0);
    assert!(s.cpu_seconds <= s.wall_seconds * 1.5 + 0.05);
}

#[test]
fn missing_program_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let cmd = Command::new("/nonexistent/peer-binary");
    let r = run_measured(cmd, dir.path(), "none", Duration::from_secs(1));
    assert!(matches!(r, Err(RunError::Missing(_))), "{r:?}");
}

fn libc_sigkill() -> i32 {
    9
}
