//! Keyboard and mouse state, translated from winit (or from a script) into the core's plain
//! [`ControlInput`].

use raylab::controller::ControlInput;
use std::time::Instant;
use winit::keyboard::KeyCode;

/// The keys the viewer reacts to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    W,
    A,
    S,
    D,
    Q,
    E,
    Left,
    Right,
    Up,
    Down,
    Shift,
    Ctrl,
    Tab,
    Plus,
    Minus,
    R,
    I,
    C,
    N,
    H,
    P,
    F1,
    F5,
    F12,
    Escape,
    /// A digit 1 to 5: the lab step of that number (2 is the camera's, no shading of its own).
    Step(u32),
}

impl Key {
    /// Maps a physical key (layout-independent: WASD stays under the left hand everywhere).
    pub fn from_code(code: KeyCode) -> Option<Key> {
        Some(match code {
            KeyCode::KeyW => Key::W,
            KeyCode::KeyA => Key::A,
            KeyCode::KeyS => Key::S,
            KeyCode::KeyD => Key::D,
            KeyCode::KeyQ => Key::Q,
            KeyCode::KeyE => Key::E,
            KeyCode::ArrowLeft => Key::Left,
            KeyCode::ArrowRight => Key::Right,
            KeyCode::ArrowUp => Key::Up,
            KeyCode::ArrowDown => Key::Down,
            KeyCode::ShiftLeft | KeyCode::ShiftRight => Key::Shift,
            KeyCode::ControlLeft | KeyCode::ControlRight => Key::Ctrl,
            KeyCode::Tab => Key::Tab,
            KeyCode::Equal | KeyCode::NumpadAdd => Key::Plus,
            KeyCode::Minus | KeyCode::NumpadSubtract => Key::Minus,
            KeyCode::KeyR => Key::R,
            KeyCode::KeyI => Key::I,
            KeyCode::KeyC => Key::C,
            KeyCode::KeyN => Key::N,
            KeyCode::KeyH => Key::H,
            KeyCode::KeyP => Key::P,
            KeyCode::F1 => Key::F1,
            KeyCode::F5 => Key::F5,
            KeyCode::F12 => Key::F12,
            KeyCode::Escape => Key::Escape,
            KeyCode::Digit1 | KeyCode::Numpad1 => Key::Step(1),
            KeyCode::Digit2 | KeyCode::Numpad2 => Key::Step(2),
            KeyCode::Digit3 | KeyCode::Numpad3 => Key::Step(3),
            KeyCode::Digit4 | KeyCode::Numpad4 => Key::Step(4),
            KeyCode::Digit5 | KeyCode::Numpad5 => Key::Step(5),
            _ => return None,
        })
    }

    /// Parses a script's key name (`W`, `Left`, `Shift`, ...).
    pub fn from_name(name: &str) -> Option<Key> {
        const ALL: [(&str, Key); 25] = [
            ("W", Key::W),
            ("A", Key::A),
            ("S", Key::S),
            ("D", Key::D),
            ("Q", Key::Q),
            ("E", Key::E),
            ("Left", Key::Left),
            ("Right", Key::Right),
            ("Up", Key::Up),
            ("Down", Key::Down),
            ("Shift", Key::Shift),
            ("Ctrl", Key::Ctrl),
            ("Tab", Key::Tab),
            ("Plus", Key::Plus),
            ("Minus", Key::Minus),
            ("R", Key::R),
            ("I", Key::I),
            ("C", Key::C),
            ("N", Key::N),
            ("H", Key::H),
            ("P", Key::P),
            ("F1", Key::F1),
            ("F5", Key::F5),
            ("F12", Key::F12),
            ("Escape", Key::Escape),
        ];
        let step = (name.parse::<u32>().ok()).filter(|n| (1..=5).contains(n));
        ALL.iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, k)| *k)
            .or(step.map(Key::Step))
    }

    /// Keys that move or turn while held (the rest act once, on press).
    pub fn is_held_motion(self) -> bool {
        matches!(
            self,
            Key::W
                | Key::A
                | Key::S
                | Key::D
                | Key::Q
                | Key::E
                | Key::Left
                | Key::Right
                | Key::Up
                | Key::Down
                | Key::Shift
                | Key::Ctrl
        )
    }
}

/// Which motion keys are held and for how long, plus mouse and wheel motion since the last
/// frame.
#[derive(Default, Debug)]
pub struct InputState {
    /// The keys held, each with when it went down or the last frame took it, if later.
    held: Vec<(Key, Instant)>,
    /// Seconds each key released since the last frame was held in it: a tap between two
    /// frames still moves (a slow frame took both its press and its release).
    released: Vec<(Key, f64)>,
    mouse: (f64, f64),
    wheel: f64,
    orbit: (f64, f64),
    pan: (f64, f64),
}

impl InputState {
    /// Records a press or release of a motion key at `now`; returns false for other keys.
    pub fn key_at(&mut self, key: Key, pressed: bool, now: Instant) -> bool {
        if !key.is_held_motion() {
            return false;
        }
        if let Some(i) = self.held.iter().position(|(k, _)| *k == key) {
            let (_, since) = self.held.remove(i);
            self.released
                .push((key, now.saturating_duration_since(since).as_secs_f64()));
        }
        if pressed {
            self.held.push((key, now));
        }
        true
    }

    /// Whether `key` is held down (a motion key or a modifier).
    pub fn holds(&self, key: Key) -> bool {
        self.held.iter().any(|(k, _)| *k == key)
    }

    /// Releases everything (focus lost: no key stays stuck down).
    pub fn release_all(&mut self) {
        let now = Instant::now();
        for (key, _) in self.held.clone() {
            self.key_at(key, false, now);
        }
    }

    /// Adds mouse-look motion.
    pub fn mouse(&mut self, dx: f64, dy: f64) {
        self.mouse.0 += dx;
        self.mouse.1 += dy;
    }

    /// Adds an orbit drag (pixels).
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        self.orbit.0 += dx;
        self.orbit.1 += dy;
    }

    /// Adds a pan drag (pixels).
    pub fn pan(&mut self, dx: f64, dy: f64) {
        self.pan.0 += dx;
        self.pan.1 += dy;
    }

    /// Adds wheel lines (positive: wheel up, zoom in).
    pub fn wheel(&mut self, lines: f64) {
        self.wheel += lines;
    }

    /// Seconds `key` was held since the last frame, up to `now`.
    fn seconds_held(&self, key: Key, now: Instant) -> f64 {
        let released = self.released.iter().filter(|(k, _)| *k == key);
        let held = self.held.iter().filter(|(k, _)| *k == key);
        released.map(|(_, s)| s).sum::<f64>()
            + held
                .map(|(_, since)| now.saturating_duration_since(*since).as_secs_f64())
                .sum::<f64>()
    }

    /// This frame's input at `now` for a frame that moves `step` seconds (the time since the
    /// last, at most the controller's longest step): each axis the share of the step its keys
    /// were held, so a key held for half the frame moves half as far. Mouse and wheel motion
    /// and the keys' held time are consumed.
    pub fn take(&mut self, now: Instant, step: f64) -> ControlInput {
        let axis = |plus: Key, minus: Key| match step > 0.0 {
            true => {
                let net = self.seconds_held(plus, now) - self.seconds_held(minus, now);
                (net / step).clamp(-1.0, 1.0)
            }
            false => 0.0,
        };
        let input = ControlInput {
            forward: axis(Key::W, Key::S),
            right: axis(Key::D, Key::A),
            up: axis(Key::E, Key::Q),
            yaw: axis(Key::Right, Key::Left),
            pitch: axis(Key::Up, Key::Down),
            fast: self.holds(Key::Shift),
            mouse: self.mouse,
            wheel: self.wheel,
            slow: self.holds(Key::Ctrl),
            orbit: self.orbit,
            pan: self.pan,
        };
        self.mouse = (0.0, 0.0);
        self.wheel = 0.0;
        self.orbit = (0.0, 0.0);
        self.pan = (0.0, 0.0);
        self.released.clear();
        for (_, since) in &mut self.held {
            *since = now;
        }
        input
    }

    /// Whether a held key keeps the camera moving, or a key released since the last frame
    /// has yet to move it.
    pub fn is_moving(&self) -> bool {
        let pending = |plus: Key, minus: Key| {
            let held = |k: Key| self.holds(k) as i32;
            held(plus) != held(minus)
                || self.released.iter().any(|(k, _)| [plus, minus].contains(k))
        };
        pending(Key::W, Key::S)
            || pending(Key::D, Key::A)
            || pending(Key::E, Key::Q)
            || pending(Key::Right, Key::Left)
            || pending(Key::Up, Key::Down)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_key_moves_for_the_share_of_the_frame_it_was_held() {
        // (In the past: `release_all` releases at the present.)
        let t0 = Instant::now() - Duration::from_secs(2);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        let mut input = InputState::default();
        // A tap a slow frame took whole: pressed and released between two frames.
        input.key_at(Key::D, true, at(100));
        input.key_at(Key::D, false, at(200));
        assert!(input.is_moving(), "the tap has yet to move the camera");
        let frame = input.take(at(500), 0.25);
        assert!((frame.right - 0.4).abs() < 1e-9, "{frame:?}");
        assert!(!input.is_moving());
        assert_eq!(input.take(at(600), 0.1).right, 0.0, "the tap moves once");
        // Held across frames: each frame from the last, the whole step while held.
        input.key_at(Key::W, true, at(650));
        assert_eq!(input.take(at(700), 0.1).forward, 0.5);
        assert_eq!(input.take(at(800), 0.1).forward, 1.0);
        // Against each other for part of a frame: the net share.
        input.key_at(Key::S, true, at(850));
        input.key_at(Key::W, false, at(900));
        let frame = input.take(at(900), 0.1);
        assert!((frame.forward - 0.5).abs() < 1e-9, "{frame:?}");
        // Focus lost while held: held until then, and nothing stays down.
        input.release_all();
        assert!(!input.holds(Key::S));
        assert!(input.take(Instant::now(), 0.25).forward < 0.0);
        assert!(!input.is_moving());
    }
}
