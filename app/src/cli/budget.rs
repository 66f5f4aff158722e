//! A program's time for all the families of a run together (`--budget` of `check --suite`
//! and of each submission `grade` runs).

use anyhow::{bail, Result};
use std::time::Duration;

/// A program's time for all the families of a run together (--budget, of a suite's runs or
/// a submission's): each run gets its --timeout or what is left, whichever is less, and none
/// runs once it is gone.
#[derive(Clone, Copy, Debug)]
pub(super) struct Budget {
    total: Duration,
    spent: Duration,
    /// Whether it is the default, 5 × --timeout (said where it runs out: a student who set
    /// none read of "the --budget of 50 s").
    default: bool,
}

impl Budget {
    /// As given (more than 0, at most 1e7 seconds), or 5 × --timeout.
    pub(super) fn new(budget: Option<f64>, timeout: f64) -> Result<Budget> {
        let default = budget.is_none();
        let budget = budget.unwrap_or(5.0 * timeout);
        if !(budget > 0.0 && budget <= 1e7) {
            bail!("--budget {budget:?} must be > 0 and at most 1e7 seconds");
        }
        let total = Duration::from_secs_f64(budget);
        Ok(Budget {
            total,
            spent: Duration::ZERO,
            default,
        })
    }

    /// The time the next run may take, `timeout` or less, and whether the budget cut it;
    /// `None` once the budget is gone (the run is skipped).
    pub(super) fn next_run(&self, timeout: Duration) -> Option<(Duration, bool)> {
        let left = self.total.saturating_sub(self.spent);
        (!left.is_zero()).then(|| (timeout.min(left), left < timeout))
    }

    /// Counts a run's time.
    pub(super) fn spend(&mut self, run: Duration) {
        self.spent += run;
    }

    /// "--budget of N s ran out" (with "5 × --timeout" where none was given), for the
    /// messages of a run cut or skipped.
    pub(super) fn ran_out(&self) -> String {
        let default = match self.default {
            true => " (5 × --timeout, as none was given)",
            false => "",
        };
        format!(
            "--budget of {} s{default} ran out",
            self.total.as_secs_f64()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::Budget;

    /// A budget run out names itself, and says it is the default where none was given.
    #[test]
    fn a_budget_says_where_it_is_the_default() {
        let given = Budget::new(Some(2.5), 1.0).unwrap();
        assert_eq!(given.ran_out(), "--budget of 2.5 s ran out");
        let default = Budget::new(None, 10.0).unwrap();
        assert_eq!(
            default.ran_out(),
            "--budget of 50 s (5 × --timeout, as none was given) ran out"
        );
    }
}
