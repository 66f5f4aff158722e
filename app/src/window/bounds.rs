//! What the window renders at most, so that it stays responsive whatever the window system
//! or a dropped view asks for: a render size within [`MAX_SHOWN_PIXELS`] and the graphics
//! device's largest texture, and supersampling within [`MAX_SHOWN_SAMPLES`] a frame. A view
//! keeps its own size and samples for F5 and copy as command, which render it headless.

/// The most pixels the window renders (a 4K frame): a larger window or view is shown scaled
/// down to fit, keeping its aspect and field of view. (A 16384x8192 view at 16x16 samples is
/// 34 G rays; a 16384x16384 window 268 M pixels.)
pub const MAX_SHOWN_PIXELS: u64 = 3840 * 2160;

/// The most samples the window renders a frame (2²⁶: 4K at 2x2, 1920x1080 at 5x5, the
/// default window at 10x10); supersampling past it is shown at the largest n x n within it.
pub const MAX_SHOWN_SAMPLES: u64 = 1 << 26;

/// The size the window renders for `(w, h)`: scaled down, keeping the aspect, to
/// [`MAX_SHOWN_PIXELS`] and to `max_side` a side.
pub fn fit_shown((w, h): (u32, u32), max_side: u32) -> (u32, u32) {
    let (w, h) = (w.max(1), h.max(1));
    let pixels = w as f64 * h as f64;
    let by_pixels = (MAX_SHOWN_PIXELS as f64 / pixels).sqrt();
    let by_side = max_side as f64 / w.max(h) as f64;
    let s = by_pixels.min(by_side);
    if s >= 1.0 {
        return (w, h);
    }
    let fit = |x: u32| ((x as f64 * s).floor() as u32).clamp(1, max_side);
    (fit(w), fit(h))
}

/// The supersampling (n per axis) the window renders of `spp` at `size`
/// ([`MAX_SHOWN_SAMPLES`]).
pub fn samples_shown(spp: u32, (w, h): (u32, u32)) -> u32 {
    let pixels = (w as u64 * h as u64).max(1);
    let most = ((MAX_SHOWN_SAMPLES / pixels) as f64).sqrt().floor() as u32;
    spp.min(most).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_samples_stay_within_the_bounds() {
        assert_eq!(fit_shown((794, 698), 16384), (794, 698));
        assert_eq!(fit_shown((16384, 8192), 16384), (4072, 2036));
        let (w, h) = fit_shown((32767, 32767), 16384);
        assert!(w as u64 * h as u64 <= MAX_SHOWN_PIXELS && w == h, "{w}x{h}");
        // A thin window: the side bound, not the pixel bound.
        assert_eq!(fit_shown((32000, 100), 16000), (16000, 50));
        assert_eq!(samples_shown(16, (4072, 2036)), 2);
        assert_eq!(samples_shown(16, (794, 698)), 11);
        assert_eq!(samples_shown(2, (794, 698)), 2);
        assert_eq!(samples_shown(16, (16384, 16384)), 1);
    }
}
