//! The wall-clock limit of [`crate::mesh`] (issue 8): checked between the phases
//! (boundary mesh, front, optimisation). On expiry the caller chooses between the best
//! valid mesh so far (the remaining phases are skipped and the report says where it
//! stopped) and a typed error. A phase already running is not interrupted; each is
//! bounded on its own (iterations, passes, budgets).

use crate::mesh::MeshError;
use std::time::Instant;

/// What [`crate::mesh`] does when the time limit has passed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TimeLimitAction {
    /// Skip the remaining phases and return the valid mesh made so far.
    #[default]
    Best,
    /// Return [`MeshError::TimeLimit`].
    Error,
}

/// The clock of one run.
pub(crate) struct Deadline {
    start: Instant,
    limit: Option<f64>,
    action: TimeLimitAction,
}

impl Deadline {
    /// A run started at `start` with at most `limit` seconds.
    pub(crate) fn new(start: Instant, limit: Option<f64>, action: TimeLimitAction) -> Self {
        Deadline {
            start,
            limit,
            action,
        }
    }

    /// Whether the phase after `done` may run: true within the limit; past it, false
    /// (recording `done` in `stopped`) or the error, by the action.
    pub(crate) fn go_on(
        &self,
        done: &str,
        stopped: &mut Option<String>,
    ) -> Result<bool, MeshError> {
        if stopped.is_some() {
            return Ok(false);
        }
        let Some(limit) = self.limit else {
            return Ok(true);
        };
        let elapsed = self.start.elapsed().as_secs_f64();
        if elapsed <= limit {
            return Ok(true);
        }
        match self.action {
            TimeLimitAction::Best => {
                *stopped = Some(done.to_string());
                Ok(false)
            }
            TimeLimitAction::Error => Err(MeshError::TimeLimit {
                limit,
                elapsed,
                phase: done.to_string(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn within_the_limit_goes_on_and_past_it_stops_or_fails() {
        let d = Deadline::new(Instant::now(), Some(1e9), TimeLimitAction::Error);
        let mut stopped = None;
        assert!(d.go_on("boundary mesh", &mut stopped).unwrap());
        let d = Deadline::new(Instant::now(), Some(-1.0), TimeLimitAction::Best);
        assert!(!d.go_on("boundary mesh", &mut stopped).unwrap());
        assert_eq!(stopped.as_deref(), Some("boundary mesh"));
        assert!(!d.go_on("front", &mut stopped).unwrap());
        assert_eq!(stopped.as_deref(), Some("boundary mesh"));
        let d = Deadline::new(Instant::now(), Some(-1.0), TimeLimitAction::Error);
        let e = d.go_on("front", &mut None).unwrap_err();
        assert!(e.to_string().contains("after the front"), "{e}");
    }
}
