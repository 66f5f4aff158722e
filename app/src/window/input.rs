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

/// Which motion keys are held, plus mouse and wheel motion since the last frame.
#[derive(Default, Debug)]
pub struct InputState {
    held: Vec<Key>,
    mouse: (f64, f64),
    wheel: f64,
    orbit: (f64, f64),
    pan: (f64, f64),
    /// When the held keys last started moving the camera from standing still.
    motion_began: Option<Instant>,
}

impl InputState {
    /// Records a press or release of a motion key; returns false for other keys.
    pub fn key(&mut self, key: Key, pressed: bool) -> bool {
        if !key.is_held_motion() {
            return false;
        }
        let was_moving = self.is_moving();
        self.held.retain(|k| *k != key);
        if pressed {
            self.held.push(key);
        }
        if !was_moving && self.is_moving() {
            self.motion_began = Some(Instant::now());
        }
        true
    }

    /// When the held keys last started moving the camera from standing still: a motion's
    /// first frame counts from then, not from the frame before (an idle window draws none).
    pub fn motion_began(&self) -> Option<Instant> {
        self.motion_began
    }

    /// Whether `key` is held down (a motion key or a modifier).
    pub fn holds(&self, key: Key) -> bool {
        self.held.contains(&key)
    }

    /// Releases everything (focus lost: no key stays stuck down).
    pub fn release_all(&mut self) {
        self.held.clear();
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

    /// Whether a held key keeps the camera moving.
    pub fn is_moving(&self) -> bool {
        self.peek().is_moving()
    }

    fn axis(&self, plus: Key, minus: Key) -> f64 {
        let has = |k| self.held.contains(&k) as i32 as f64;
        has(plus) - has(minus)
    }

    fn peek(&self) -> ControlInput {
        ControlInput {
            forward: self.axis(Key::W, Key::S),
            right: self.axis(Key::D, Key::A),
            up: self.axis(Key::E, Key::Q),
            yaw: self.axis(Key::Right, Key::Left),
            pitch: self.axis(Key::Up, Key::Down),
            fast: self.held.contains(&Key::Shift),
            mouse: self.mouse,
            wheel: self.wheel,
            slow: self.held.contains(&Key::Ctrl),
            orbit: self.orbit,
            pan: self.pan,
        }
    }

    /// This frame's input; mouse and wheel motion are consumed.
    pub fn take(&mut self) -> ControlInput {
        let input = self.peek();
        self.mouse = (0.0, 0.0);
        self.wheel = 0.0;
        self.orbit = (0.0, 0.0);
        self.pan = (0.0, 0.0);
        input
    }
}
