//! Scripted input for `raylab --frames N --script FILE`: timed key and mouse events replayed
//! through the same paths as real ones.
//!
//! One event per line, `<ms> <event> [args]`, times in milliseconds from the first frame shown,
//! non-decreasing; `#` lines and blank lines are skipped:
//! - `key <Name> down|up` (W A S D Q E Left Right Up Down Shift R H F1 F12 Escape)
//! - `mouse <dx> <dy>`: mouse-look motion (as a right-drag), in device units
//! - `wheel <lines>`: positive zooms in
//! - `step flat|direct|shadows|indirect`: what the panel's lab-step selector does

use super::input::Key;
use raylab::render::LabStep;
use std::time::Duration;

/// One scripted event.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// A key press or release.
    Key(Key, bool),
    /// Mouse-look motion.
    Mouse(f64, f64),
    /// Wheel lines.
    Wheel(f64),
    /// Select a lab step.
    Step(LabStep),
}

/// A parsed script: events sorted by time.
#[derive(Clone, Debug, Default)]
pub struct Script {
    events: Vec<(Duration, Action)>,
    next: usize,
}

impl Script {
    /// Parses script text; errors name the file and line.
    pub fn parse(file: &str, text: &str) -> Result<Script, String> {
        let mut events = Vec::new();
        let mut last = Duration::ZERO;
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let err = |m: String| format!("{file}:{}: {m}", i + 1);
            let w: Vec<&str> = line.split_whitespace().collect();
            let ms: f64 = w[0]
                .parse()
                .ok()
                .filter(|ms: &f64| ms.is_finite() && *ms >= 0.0 && *ms <= 3.6e6)
                .ok_or_else(|| err(format!("'{}' is not a time in ms (0..=3600000)", w[0])))?;
            let at = Duration::from_secs_f64(ms / 1e3);
            if at < last {
                return Err(err("times must not decrease".into()));
            }
            last = at;
            let num = |k: usize| -> Result<f64, String> {
                w.get(k)
                    .and_then(|s| s.parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        err(format!(
                            "'{}' needs a finite number here",
                            w.get(1).unwrap_or(&"")
                        ))
                    })
            };
            let want = |n: usize| -> Result<(), String> {
                if w.len() == n {
                    Ok(())
                } else {
                    Err(err(format!(
                        "'{}' takes {} arguments, found {}",
                        w.get(1).unwrap_or(&""),
                        n - 2,
                        w.len().saturating_sub(2)
                    )))
                }
            };
            let action = match w.get(1).copied() {
                Some("key") => {
                    want(4)?;
                    let key = Key::from_name(w[2])
                        .ok_or_else(|| err(format!("unknown key '{}'", w[2])))?;
                    let down = match w[3] {
                        "down" => true,
                        "up" => false,
                        other => {
                            return Err(err(format!("expected 'down' or 'up', found '{other}'")))
                        }
                    };
                    Action::Key(key, down)
                }
                Some("mouse") => {
                    want(4)?;
                    Action::Mouse(num(2)?, num(3)?)
                }
                Some("wheel") => {
                    want(3)?;
                    Action::Wheel(num(2)?)
                }
                Some("step") => {
                    want(3)?;
                    Action::Step(w[2].parse().map_err(err)?)
                }
                Some(other) => {
                    return Err(err(format!(
                        "unknown event '{other}' (key, mouse, wheel, step)"
                    )))
                }
                None => return Err(err("missing event after the time".into())),
            };
            events.push((at, action));
        }
        Ok(Script { events, next: 0 })
    }

    /// Events due by `elapsed` that were not returned before.
    pub fn due(&mut self, elapsed: Duration) -> Vec<Action> {
        let start = self.next;
        while self.next < self.events.len() && self.events[self.next].0 <= elapsed {
            self.next += 1;
        }
        self.events[start..self.next]
            .iter()
            .map(|(_, a)| a.clone())
            .collect()
    }

    /// Whether every event was returned.
    pub fn finished(&self) -> bool {
        self.next == self.events.len()
    }

    /// When the next event is due, if any.
    pub fn next_due(&self) -> Option<Duration> {
        self.events.get(self.next).map(|(t, _)| *t)
    }
}
