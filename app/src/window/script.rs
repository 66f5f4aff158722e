//! Scripted input for `raylab --frames N --script FILE`: timed key and mouse events replayed
//! through the same paths as real ones.
//!
//! One event per line, `<ms> <event> [args]`, times in milliseconds from the first frame shown,
//! non-decreasing; `#` lines and blank lines are skipped:
//! - `key <Name> down|up` (W A S D Q E Left Right Up Down Shift Ctrl Tab Plus Minus R I C N H
//!   F1 F5 F12 Escape, and the digits 1 to 5)
//! - `mouse <dx> <dy>`: mouse-look motion (as a right-drag), in device units
//! - `wheel <lines>`: positive zooms in
//! - `set <control> <value>`: what the panel's widget of that image control does (any row of
//!   [`raylab::render::CONTROLS`], the `.view` file's names and values: `set spp 3`,
//!   `set cracks on`)
//! - `step flat|direct|shadows|indirect`: `set step …`
//! - `drop <path>`: as if the file were dropped on the window (paths without spaces)
//! - `changed <path>`: as if the file watcher saw the file change on disk (at once, where the
//!   watcher looks every 250 ms)
//! - `focal <px>`: what the panel's focal-length slider does
//! - `scale <s>`: the panel's resolution scale slider (0.05..=1 of the window)
//! - `resize <w> <h>`: asks the window system for that inner size; `resize 0 0` minimises (the
//!   0×0 resize a minimised window gets, delivered to the same handler: X cannot make a
//!   zero-size window)
//! - `restore`: back from `resize 0 0` at the window's real size
//! - `lose-surface`: the next draw fails as on a lost window surface
//! - `resize-in-draw <w> <h>`: the window takes that inner size during the next draw, after
//!   the draw read its size and before it asks the surface for a texture (the race of a
//!   user's drag of the window's corner)
//! - `fail-render`: the next render to finish fails (as a render error would)
//! - `select <level>`: what clicking a push level in the panel's scene tree does (highlights
//!   its primitives); `select none` clears it
//! - `inspect <i> <j>`: what a left click on pixel (i, j) of the full-size image does with the
//!   ray inspector on (the run prints the inspection at the end)
//! - `await <path>`: holds the rest of the script (and the run's end) until the file exists,
//!   looked for every [`AWAIT_POLL`]: a test's real-input driver creates it when done, so the
//!   run lasts as long as the driver, not a fixed time

use super::input::Key;
use std::time::Duration;

/// A scripted run that has not finished by then fails; its events come before.
pub const RUN_LIMIT: Duration = Duration::from_secs(120);

/// How often an `await` looks for its file.
pub const AWAIT_POLL: Duration = Duration::from_millis(50);

/// One scripted event.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// A key press or release.
    Key(Key, bool),
    /// Mouse-look motion.
    Mouse(f64, f64),
    /// Wheel lines.
    Wheel(f64),
    /// Set an image control (its name in [`raylab::render::CONTROLS`], a value it takes).
    Set(&'static str, String),
    /// Drop a file on the window.
    Drop(std::path::PathBuf),
    /// The file watcher's report that a file changed on disk.
    Changed(std::path::PathBuf),
    /// Set the focal length (pixels of the full-resolution image).
    Focal(f64),
    /// Set the resolution scale.
    Scale(f32),
    /// Resize the window (0×0: minimise).
    Resize(u32, u32),
    /// Undo a minimise.
    Restore,
    /// Select a push level of the scene tree (`None`: no selection).
    Select(Option<usize>),
    /// Inspect pixel (i, j) of the full-size image.
    Inspect(u32, u32),
    /// Make the next draw fail as a lost window surface does (wgpu's `SurfaceError::Lost`
    /// cannot be provoked under a CPU Vulkan driver): the app must report it and draw again.
    LoseSurface,
    /// Resize the window inside the next draw, after it read the window's size: the surface
    /// is then stale when a texture is asked of it, and the draw must recover.
    ResizeInDraw(u32, u32),
    /// Make the next render to finish fail: the app must say so and not ask for it again
    /// until something changes.
    FailRender,
    /// Hold the rest of the script until this file exists (passed once it does).
    Await(std::path::PathBuf),
}

/// [`Action::Set`] of the control `name` to `value`, if the control takes that value.
fn set_control(name: &str, value: &str) -> Result<Action, String> {
    use raylab::render::settings;
    let control = settings::control(name).ok_or_else(|| {
        format!(
            "unknown control '{name}' (expected {})",
            settings::control_names()
        )
    })?;
    let mut settings = raylab::render::RenderSettings::default();
    control.set_text(&mut settings, value)?;
    settings.validate().map_err(|e| e.to_string())?;
    Ok(Action::Set(control.name, value.to_string()))
}

/// A parsed script: events sorted by time.
#[derive(Clone, Debug, Default)]
pub struct Script {
    events: Vec<(Duration, Action)>,
    next: usize,
    /// When an `await` last found its file missing.
    held_at: Option<Duration>,
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
                .filter(|ms: &f64| ms.is_finite() && *ms >= 0.0)
                .ok_or_else(|| err(format!("'{}' is not a time in ms", w[0])))?;
            // (Refused up front: an event the run cannot reach would only end in its timeout.)
            if ms >= RUN_LIMIT.as_millis() as f64 {
                return Err(err(format!(
                    "{ms} ms is past the scripted run's limit: a scripted run ends within {} s",
                    RUN_LIMIT.as_secs()
                )));
            }
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
                Some("set") => {
                    want(4)?;
                    set_control(w[2], w[3]).map_err(err)?
                }
                Some("step") => {
                    want(3)?;
                    set_control("step", w[2]).map_err(err)?
                }
                Some("drop") => {
                    want(3)?;
                    Action::Drop(w[2].into())
                }
                Some("changed") => {
                    want(3)?;
                    Action::Changed(w[2].into())
                }
                Some("focal") => {
                    want(3)?;
                    Action::Focal(num(2)?)
                }
                Some("scale") => {
                    want(3)?;
                    let s = num(2)?;
                    if !(0.05..=1.0).contains(&s) {
                        return Err(err(format!("scale {s} is not in 0.05..=1")));
                    }
                    Action::Scale(s as f32)
                }
                Some(name @ ("resize" | "resize-in-draw")) => {
                    want(4)?;
                    let side = |k: usize| {
                        num(k).and_then(|x| {
                            if (0.0..=32767.0).contains(&x) && x.fract() == 0.0 {
                                Ok(x as u32)
                            } else {
                                Err(err(format!("window side {x} is not an integer in 0..=32767")))
                            }
                        })
                    };
                    let size = (side(2)?, side(3)?);
                    match name {
                        "resize" => Action::Resize(size.0, size.1),
                        _ => Action::ResizeInDraw(size.0, size.1),
                    }
                }
                Some("restore") => {
                    want(2)?;
                    Action::Restore
                }
                Some("fail-render") => {
                    want(2)?;
                    Action::FailRender
                }
                Some("lose-surface") => {
                    want(2)?;
                    Action::LoseSurface
                }
                Some("select") => {
                    want(3)?;
                    match w[2] {
                        "none" => Action::Select(None),
                        n => Action::Select(Some(n.parse().map_err(|_| {
                            err(format!("select takes a level number or 'none', not '{n}'"))
                        })?)),
                    }
                }
                Some("await") => {
                    want(3)?;
                    Action::Await(w[2].into())
                }
                Some("inspect") => {
                    want(4)?;
                    let pixel = |k: usize| {
                        w[k].parse::<u32>()
                            .map_err(|_| err(format!("'{}' is not a pixel coordinate", w[k])))
                    };
                    Action::Inspect(pixel(2)?, pixel(3)?)
                }
                Some(other) => {
                    return Err(err(format!(
                        "unknown event '{other}' (key, mouse, wheel, set, step, drop, changed, focal, scale, resize, restore, lose-surface, resize-in-draw, fail-render, select, inspect, await)"
                    )))
                }
                None => return Err(err("missing event after the time".into())),
            };
            events.push((at, action));
        }
        Ok(Script {
            events,
            next: 0,
            held_at: None,
        })
    }

    /// Events due by `elapsed` that were not returned before, up to an `await` whose file
    /// does not exist yet.
    /// Each with the time it was due at.
    pub fn due(&mut self, elapsed: Duration) -> Vec<(Duration, Action)> {
        let start = self.next;
        self.held_at = None;
        while let Some((at, action)) = self.events.get(self.next) {
            if *at > elapsed {
                break;
            }
            if matches!(action, Action::Await(path) if !path.exists()) {
                self.held_at = Some(elapsed);
                break;
            }
            self.next += 1;
        }
        self.events[start..self.next].to_vec()
    }

    /// Looks again for the file of an `await` that holds the script, without returning any
    /// event: true while it still holds (its next look is [`AWAIT_POLL`] from `elapsed`).
    pub fn still_held(&mut self, elapsed: Duration) -> bool {
        let held = match self.events.get(self.next) {
            Some((at, Action::Await(path))) => *at <= elapsed && !path.exists(),
            _ => false,
        };
        self.held_at = held.then_some(elapsed);
        held
    }

    /// The file an `await` holding the script waits for.
    pub fn awaited(&self) -> Option<&std::path::Path> {
        match (self.held_at, self.events.get(self.next)) {
            (Some(_), Some((_, Action::Await(path)))) => Some(path),
            _ => None,
        }
    }

    /// Whether every event was returned.
    pub fn finished(&self) -> bool {
        self.next == self.events.len()
    }

    /// When the next event is due, if any (a held `await` looks again after [`AWAIT_POLL`]).
    pub fn next_due(&self) -> Option<Duration> {
        let (at, _) = self.events.get(self.next)?;
        Some(self.held_at.map_or(*at, |held| held + AWAIT_POLL))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The actions [`Script::due`] returns, without their times.
    fn due(s: &mut Script, elapsed: Duration) -> Vec<Action> {
        s.due(elapsed).into_iter().map(|(_, a)| a).collect()
    }

    #[test]
    fn parses_every_event_and_replays_in_time() {
        let text = "# a comment\n\n0 key W down\n100 key w up\n100 mouse -3 4.5\n250 wheel -2\n300 step shadows\n300 set cracks on\n300 drop m.obj\n300 changed m.obj\n400 focal 700\n400 scale 0.5\n400 resize 0 0\n400 restore\n400 lose-surface\n400 resize-in-draw 900 600\n400 fail-render\n400 select 2\n400 select none\n400 inspect 3 4\n";
        let mut s = Script::parse("s.txt", text).unwrap();
        assert_eq!(s.next_due(), Some(Duration::ZERO));
        assert_eq!(
            due(&mut s, Duration::from_millis(99)),
            vec![Action::Key(Key::W, true)]
        );
        assert_eq!(
            due(&mut s, Duration::from_millis(100)),
            vec![Action::Key(Key::W, false), Action::Mouse(-3.0, 4.5)]
        );
        assert!(!s.finished());
        assert_eq!(
            due(&mut s, Duration::from_secs(1)),
            vec![
                Action::Wheel(-2.0),
                Action::Set("step", "shadows".into()),
                Action::Set("cracks", "on".into()),
                Action::Drop("m.obj".into()),
                Action::Changed("m.obj".into()),
                Action::Focal(700.0),
                Action::Scale(0.5),
                Action::Resize(0, 0),
                Action::Restore,
                Action::LoseSurface,
                Action::ResizeInDraw(900, 600),
                Action::FailRender,
                Action::Select(Some(2)),
                Action::Select(None),
                Action::Inspect(3, 4),
            ]
        );
        assert!(s.finished());
        assert_eq!(s.next_due(), None);
    }

    #[test]
    fn await_holds_the_rest_until_its_file_exists() {
        let dir = tempfile::tempdir().unwrap();
        let done = dir.path().join("driver-done");
        let text = format!("0 key W down\n100 await {}\n100 key W up\n", done.display());
        let mut s = Script::parse("s.txt", &text).unwrap();
        let ms = Duration::from_millis;
        assert_eq!(due(&mut s, ms(200)), vec![Action::Key(Key::W, true)]);
        // Held: nothing more, and the next look is one poll later (not at once, in a loop).
        assert_eq!(s.next_due(), Some(ms(200) + AWAIT_POLL));
        assert_eq!(due(&mut s, ms(90_000)), vec![]);
        assert_eq!(s.next_due(), Some(ms(90_000) + AWAIT_POLL));
        assert!(!s.finished());
        std::fs::write(&done, "").unwrap();
        assert_eq!(
            due(&mut s, ms(90_050)),
            vec![Action::Await(done), Action::Key(Key::W, false)]
        );
        assert!(s.finished());
        assert_eq!(s.next_due(), None);
    }

    #[test]
    fn a_held_await_is_looked_for_without_returning_events() {
        // What the idle scripted window does between frames: look for the file, and wake
        // again one poll later while it is missing; once it exists the await is due at once.
        let dir = tempfile::tempdir().unwrap();
        let done = dir.path().join("driver-done");
        let text = format!("0 key W down\n100 await {}\n100 key W up\n", done.display());
        let mut s = Script::parse("s.txt", &text).unwrap();
        let ms = Duration::from_millis;
        assert!(!s.still_held(ms(50)), "no await is due yet");
        assert_eq!(due(&mut s, ms(200)), vec![Action::Key(Key::W, true)]);
        assert!(s.still_held(ms(700)));
        assert_eq!(s.awaited(), Some(done.as_path()));
        assert_eq!(s.next_due(), Some(ms(700) + AWAIT_POLL));
        std::fs::write(&done, "").unwrap();
        assert!(!s.still_held(ms(760)));
        assert_eq!(s.awaited(), None);
        assert_eq!(s.next_due(), Some(ms(100)), "due at once");
        assert_eq!(
            due(&mut s, ms(760)),
            vec![Action::Await(done), Action::Key(Key::W, false)]
        );
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let cases = [
            ("0 key W sideways\n", "s.txt:1: expected 'down' or 'up'"),
            ("\n0 key Z down\n", "s.txt:2: unknown key 'Z'"),
            (
                "10 key W down\n5 key W up\n",
                "s.txt:2: times must not decrease",
            ),
            ("x key W down\n", "s.txt:1: 'x' is not a time"),
            ("-5 key W down\n", "'-5' is not a time"),
            ("0 mouse 1\n", "s.txt:1: 'mouse' takes 2 arguments, found 1"),
            ("0 wheel nan\n", "needs a finite number"),
            ("0 jump\n", "unknown event 'jump'"),
            ("0\n", "missing event"),
            ("0 step glossy\n", "unknown step 'glossy'"),
            (
                "0 set gamma 2\n",
                "s.txt:1: unknown control 'gamma' (expected step, spp",
            ),
            ("0 set spp many\n", "'many' is not a whole number"),
            ("0 set spp 17\n", "supersampling 17 is out of range"),
            ("0 set cracks\n", "'set' takes 2 arguments, found 1"),
            ("0 select first\n", "select takes a level number or 'none'"),
            (
                "0 inspect 3 -1\n",
                "s.txt:1: '-1' is not a pixel coordinate",
            ),
            ("0 inspect 3\n", "'inspect' takes 2 arguments"),
            ("0 scale 2\n", "scale 2 is not in 0.05..=1"),
            ("0 resize 10 -1\n", "window side -1 is not an integer"),
            ("0 resize 10 1e6\n", "window side 1000000"),
            ("0 resize 32768 10\n", "not an integer in 0..=32767"),
            (
                "3600000 key W down\n",
                "s.txt:1: 3600000 ms is past the scripted run's limit: a scripted run ends within 120 s",
            ),
            ("120000 key W down\n", "past the scripted run's limit"),
            ("0 restore now\n", "'restore' takes 0 arguments, found 1"),
            ("0 await\n", "'await' takes 1 arguments, found 0"),
        ];
        for (text, needle) in cases {
            let e = Script::parse("s.txt", text).unwrap_err();
            assert!(e.contains(needle), "{e} lacks {needle}");
        }
    }
}
