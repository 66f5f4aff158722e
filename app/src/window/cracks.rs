//! The cracks of the frame shown, counted: with "show cracks" on, each frame the window shows
//! at full resolution is traced again, sample by sample at the renderer's own positions, and
//! every answer graded against the exact one (as the cracks view marks it). The counts show in
//! the panel beside the colour legend; the marked pixels, in reading order, are what the next
//! and previous crack keys (N, Shift+N) step the ray inspector through.
//!
//! Counting runs on a thread of its own after the frame is shown (about the frame's own cost
//! again) and is dropped when the view changes or a newer frame arrives.

use super::worker::Job;
use super::AppEvent;
use raylab::check::code::verdict;
use raylab::check::grade::{FALSE_HIT, WRONG};
use raylab::check::{LabCode, Verdict};
use raylab::geometry::{Hit, Method, Ray, Shape};
use raylab::render::{linear_to_srgb8, Stage, CRACK};
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use winit::event_loop::EventLoopProxy;

/// A direction to step through the marked pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    Next,
    Previous,
}

/// How many samples of a frame got each verdict that is not "right".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub leaks: u64,
    pub false_hits: u64,
    pub wrong: u64,
    pub ties: u64,
}

impl Counts {
    fn add(&mut self, v: Verdict) {
        match v {
            Verdict::Leak => self.leaks += 1,
            Verdict::FalseHit => self.false_hits += 1,
            Verdict::Wrong => self.wrong += 1,
            Verdict::Tie => self.ties += 1,
            Verdict::Right => {}
        }
    }

    fn merge(mut self, o: Counts) -> Counts {
        self.leaks += o.leaks;
        self.false_hits += o.false_hits;
        self.wrong += o.wrong;
        self.ties += o.ties;
        self
    }
}

/// A pixel the cracks view marks: its first marked sample and that sample's verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marked {
    pub pixel: (u32, u32),
    /// The sample (sx, sy) of the pixel's n×n.
    pub sample: (u32, u32),
    pub verdict: Verdict,
}

/// The cracks of one frame.
#[derive(Clone, Debug)]
pub struct Census {
    /// The frame's generation and refinement level (see [`super::viewer::Shown`]).
    pub generation: u64,
    pub level: u8,
    pub size: (u32, u32),
    /// The columns of the view left of the frame (the inspector's panel crops its sides):
    /// the counts and the marked pixels are the whole view's, in its columns, as F5 and
    /// `raylab render --cracks` of the view count them.
    pub offset: u32,
    /// Samples per pixel along each axis.
    pub spp: u32,
    /// Who answered: the method's name, or the linked code's.
    pub who: String,
    /// Linked code answered (its wrong primitives and false hits are marked too).
    pub code: bool,
    pub counts: Counts,
    /// The marked pixels, in reading order.
    pub marked: Vec<Marked>,
}

/// The verdict on `given` for `ray` against the exact `exact` (a tie decided exactly) in a
/// scene of `count` primitives: an index past them is a wrong primitive (a false hit where
/// nothing is met), never looked up.
pub fn classify(
    count: usize,
    shape_of: impl Fn(u32) -> Shape,
    ray: &Ray,
    exact: Option<Hit>,
    given: Option<Hit>,
) -> Verdict {
    if given.is_some_and(|g| g.prim as usize >= count) {
        return match exact {
            Some(_) => Verdict::Wrong,
            None => Verdict::FalseHit,
        };
    }
    match (exact, given) {
        (Some(e), Some(g)) if e.prim != g.prim => {
            // Graded as the cracks view grades it, with the two primitives alone (renumbered
            // 1 and 0: the answer's first, as the exact search breaks ties to the lower index).
            let pair = [shape_of(g.prim), shape_of(e.prim)];
            let exact = Some(Hit { prim: 1, ..e });
            verdict(&pair, ray, exact, Some(Hit { prim: 0, ..g }))
        }
        // Hit or miss alone: nothing to look up.
        (Some(_), Some(_)) | (None, None) => Verdict::Right,
        (Some(_), None) => Verdict::Leak,
        (None, Some(_)) => Verdict::FalseHit,
    }
}

/// Whether the cracks view marks a sample with this verdict: linked code's every wrong answer
/// (leaks magenta, false hits yellow, wrong primitives cyan); a method's leaks and false hits
/// (magenta: another primitive at the same surface is not a crack).
pub fn is_marked(v: Verdict, code: bool) -> bool {
    match code {
        true => v.mark().is_some(),
        false => matches!(v, Verdict::Leak | Verdict::FalseHit),
    }
}

/// The position of sample (sx, sy) of pixel (i, j) at n×n samples, as the renderer takes it.
pub fn sample_position((i, j): (u32, u32), (sx, sy): (u32, u32), n: u32) -> (f32, f32) {
    let inv_n = 1.0 / n as f32;
    let x = i as f32 + (sx as f32 + 0.5) * inv_n;
    let y = j as f32 + (sy as f32 + 0.5) * inv_n;
    (x, y)
}

/// One sample's ray, the answer given for it and the exact one, as the frame of `job` traced
/// them (`shapes`: every primitive, for linked code).
pub fn answers(
    job: (&Stage, &raylab::Camera, Method, Option<&dyn LabCode>),
    shapes: &[Shape],
    size: (u32, u32),
    (x, y): (f32, f32),
) -> (Ray, Option<Hit>, Option<Hit>) {
    let (stage, camera, method, code) = job;
    let accel = stage.accel();
    let (ray, given) = match code {
        Some(code) => {
            let ray = code.camera_ray(camera, size.0, size.1, x, y);
            (ray, code.closest_hit(shapes, &ray, 0.0, f32::INFINITY))
        }
        None => {
            let ray = camera.ray_generator(size.0, size.1).ray_through(x, y);
            (ray, accel.closest_hit(&ray, method, 0.0, f32::INFINITY))
        }
    };
    let exact = accel.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
    (ray, given, exact)
}

/// Every primitive one by one, as linked code is given them (instanced meshes placed).
pub fn all_shapes(stage: &Stage) -> Cow<'_, [Shape]> {
    let scene = stage.scene();
    match scene.instances().is_empty() {
        true => Cow::Borrowed(&scene.shapes),
        false => Cow::Owned(scene.all_shapes().collect()),
    }
}

/// Counts the cracks of the frame `job` rendered; `None` if `cancelled()` turned true.
pub fn count(job: &Job, cancelled: &(dyn Fn() -> bool + Sync)) -> Option<Census> {
    let s = job.settings;
    let (w, h, n) = (s.width + 2 * job.view_offset, s.height, s.spp);
    let code = job.code.as_deref();
    let mut census = Census {
        generation: job.generation,
        level: job.level,
        size: (s.width, h),
        offset: job.view_offset,
        spp: n,
        who: code.map_or(s.method.name().to_string(), |c| c.name().to_string()),
        code: code.is_some(),
        counts: Counts::default(),
        marked: Vec::new(),
    };
    if code.is_none() && s.method == Method::Adaptive {
        return Some(census); // the exact method against itself
    }
    let scene = job.stage.scene();
    let shapes = match code {
        Some(_) => all_shapes(&job.stage),
        None => Cow::Borrowed(&[][..]),
    };
    let shape_of = |p: u32| match code {
        Some(_) => shapes[p as usize],
        None => scene.shape(p),
    };
    let trace = (&job.stage, &job.camera, s.method, code);
    let rows: Vec<(Counts, Vec<Marked>)> = (0..h)
        .into_par_iter()
        .map(|j| {
            let (mut counts, mut marked) = (Counts::default(), Vec::new());
            if cancelled() {
                return (counts, marked);
            }
            for i in 0..w {
                let mut first = None;
                for sy in 0..n {
                    for sx in 0..n {
                        let at = sample_position((i, j), (sx, sy), n);
                        let (ray, given, exact) = answers(trace, &shapes, (w, h), at);
                        let v = classify(scene.len(), shape_of, &ray, exact, given);
                        counts.add(v);
                        if first.is_none() && is_marked(v, census.code) {
                            first = Some(((sx, sy), v));
                        }
                    }
                }
                if let Some((sample, verdict)) = first {
                    marked.push(Marked {
                        pixel: (i, j),
                        sample,
                        verdict,
                    });
                }
            }
            (counts, marked)
        })
        .collect();
    if cancelled() {
        return None;
    }
    for (counts, marked) in rows {
        census.counts = census.counts.merge(counts);
        census.marked.extend(marked);
    }
    Some(census)
}

/// `n` with a comma between each group of three digits.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

impl Census {
    /// The counts as the panel shows them: `leaks 3 · false hits 0 · wrong 1 · ties 12 (of
    /// 307,200 px)` (samples where there are several a pixel).
    pub fn summary(&self) -> String {
        let c = &self.counts;
        let pixels = (self.size.0 + 2 * self.offset) as u64 * self.size.1 as u64;
        let of = match self.spp {
            1 => format!("of {} px", grouped(pixels)),
            n => format!(
                "of {} samples, {n}×{n} a pixel",
                grouped(pixels * (n * n) as u64)
            ),
        };
        format!(
            "leaks {} · false hits {} · wrong {} · ties {} ({of})",
            grouped(c.leaks),
            grouped(c.false_hits),
            grouped(c.wrong),
            grouped(c.ties)
        )
    }

    /// The marked pixel at `pixel`, if it is one.
    pub fn find(&self, (i, j): (u32, u32)) -> Option<(usize, &Marked)> {
        let k = (self.marked)
            .binary_search_by_key(&(j, i), |m| (m.pixel.1, m.pixel.0))
            .ok()?;
        Some((k, &self.marked[k]))
    }

    /// The marked pixel after (or before) `from` in reading order, wrapping around; from no
    /// pixel, the first (or the last).
    pub fn step(&self, from: Option<(u32, u32)>, step: Step) -> Option<(usize, &Marked)> {
        let key = |m: &Marked| (m.pixel.1, m.pixel.0);
        let n = self.marked.len();
        if n == 0 {
            return None;
        }
        let k = match (from, step) {
            (None, Step::Next) => 0,
            (None, Step::Previous) => n - 1,
            (Some((i, j)), Step::Next) => {
                let after = self.marked.partition_point(|m| key(m) <= (j, i));
                after % n
            }
            (Some((i, j)), Step::Previous) => {
                let before = self.marked.partition_point(|m| key(m) < (j, i));
                (before + n - 1) % n
            }
        };
        Some((k, &self.marked[k]))
    }
}

/// What a mark looks like and says, for the legend and the inspector.
pub fn mark_name(v: Verdict, code: bool) -> &'static str {
    match (v, code) {
        (Verdict::Leak, _) | (Verdict::FalseHit, false) => "magenta",
        (Verdict::FalseHit, true) => "yellow",
        (Verdict::Wrong, true) => "cyan",
        _ => "not marked",
    }
}

/// The census of the frames shown: the counting thread, its newest result, and a step asked
/// for before the frame it needs was counted.
pub struct Counter {
    /// Bumped by each new count and by each change: a count whose ticket is not the newest
    /// stops at its next row and is dropped.
    ticket: Arc<AtomicU64>,
    /// The ticket of the count under way, if one is, and the view it is of.
    running: Option<(u64, CountedView)>,
    tx: Sender<(u64, Census)>,
    rx: Receiver<(u64, Census)>,
    proxy: EventLoopProxy<AppEvent>,
    /// The view `census` is of.
    census_view: Option<CountedView>,
    /// The newest count that finished.
    pub census: Option<Census>,
    /// A next or previous crack asked for while the frame it needs was not yet counted.
    pub pending: Option<Step>,
}

impl Counter {
    pub fn new(proxy: EventLoopProxy<AppEvent>) -> Self {
        let (tx, rx) = channel();
        Self {
            ticket: Arc::new(AtomicU64::new(0)),
            running: None,
            tx,
            rx,
            proxy,
            census_view: None,
            census: None,
            pending: None,
        }
    }

    /// Counts the frame `job` rendered (`last`: the view's last refinement), on a thread of
    /// its own ([`AppEvent::CracksCounted`] when done).
    pub fn submit(&mut self, job: Job, last: bool) {
        let ticket = self.ticket.fetch_add(1, Ordering::Relaxed) + 1;
        let view = CountedView::of(&job);
        // (The same view framed again, as opening the inspector's panel crops it: counted
        // already. Counted again, a step to the next crack waited seconds for it; and the
        // coarser frame before the last, counted too, slowed the last one's render.)
        let counted = self.census_view.as_ref();
        let same = counted.is_some_and(|v| v.is(&view));
        if !last && !same && counted.is_some_and(|v| v.is_finer(&view)) {
            log::debug!(
                "frame {}.{} not counted: its view's count with more samples stands",
                job.generation,
                job.level
            );
            self.running = None;
            return;
        }
        self.running = Some((ticket, view));
        if let Some(census) = self.census.as_ref().filter(|_| same) {
            let census = Census {
                generation: job.generation,
                level: job.level,
                size: (job.settings.width, job.settings.height),
                offset: job.view_offset,
                ..census.clone()
            };
            log::debug!(
                "the cracks of frame {}.{} are those counted of the same view",
                job.generation,
                job.level
            );
            if self.tx.send((ticket, census)).is_ok() {
                let _ = self.proxy.send_event(AppEvent::CracksCounted);
            }
            return;
        }
        let (newest, tx, proxy) = (self.ticket.clone(), self.tx.clone(), self.proxy.clone());
        std::thread::spawn(move || {
            let stale = || newest.load(Ordering::Relaxed) != ticket;
            let start = std::time::Instant::now();
            if let Some(census) = count(&job, &stale) {
                log::debug!(
                    "counted the cracks of frame {}.{} ({}x{}, {}x{} samples a pixel) in {:.0} ms",
                    census.generation,
                    census.level,
                    census.size.0,
                    census.size.1,
                    census.spp,
                    census.spp,
                    start.elapsed().as_secs_f64() * 1e3
                );
                if tx.send((ticket, census)).is_ok() {
                    let _ = proxy.send_event(AppEvent::CracksCounted);
                }
            }
        });
    }

    /// The view changed: a count under way is of a frame no longer wanted.
    pub fn cancel(&mut self) {
        self.ticket.fetch_add(1, Ordering::Relaxed);
        self.running = None;
    }

    /// Takes a finished count (the newest wanted one); true if there was one.
    pub fn take(&mut self) -> bool {
        let mut got = false;
        while let Ok((ticket, census)) = self.rx.try_recv() {
            if let Some((_, view)) = self.running.take_if(|(running, _)| *running == ticket) {
                (self.census, self.census_view) = (Some(census), Some(view));
                got = true;
            }
        }
        got
    }

    /// Whether a count is under way.
    pub fn is_counting(&self) -> bool {
        self.running.is_some()
    }
}

/// What a frame's cracks depend on: the structure (not the colours), the camera, the whole
/// view's size (the inspector's panel crops its sides), the samples and who answers.
struct CountedView {
    structure: std::sync::Weak<raylab::accel::Accel>,
    camera: raylab::Camera,
    view: (u32, u32),
    spp: u32,
    method: Method,
    code: Option<Arc<dyn LabCode>>,
}

impl CountedView {
    fn of(job: &Job) -> Self {
        let s = job.settings;
        Self {
            structure: job.stage.structure_handle(),
            camera: job.camera,
            view: (s.width + 2 * job.view_offset, s.height),
            spp: s.spp,
            method: s.method,
            code: job.code.clone(),
        }
    }

    /// Whether the cracks of `other` are this view's.
    fn is(&self, other: &Self) -> bool {
        self.spp == other.spp && self.is_finer(other)
    }

    /// Whether this is `other`'s view, counted with as many samples a pixel or more.
    fn is_finer(&self, other: &Self) -> bool {
        let code = match (&self.code, &other.code) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (a, b) => a.is_none() && b.is_none(),
        };
        std::sync::Weak::ptr_eq(&self.structure, &other.structure)
            && (self.camera, self.view, self.method) == (other.camera, other.view, other.method)
            && self.spp >= other.spp
            && code
    }
}

/// What the panel shows beside the "show cracks" box.
pub struct Legend {
    /// Linked code answers (three marks), or a method (one).
    pub code: bool,
    /// The counts of the frame shown, or what they wait for.
    pub line: Result<String, &'static str>,
    /// Marked pixels in that frame.
    pub marked: Option<usize>,
}

/// What the counts are, under the pointer (the legend names the painted marks only, and
/// "ties" was said nowhere in the window).
const COUNTS_HELP: &str = "Each sample's ray as the method (or your code) answers it, graded \
    against the exact answer as `raylab check` grades: a leak misses what the ray meets first; \
    a false hit meets something where the ray meets nothing; wrong: another primitive met \
    first; ties: another primitive met at the same t, or at one rounding cannot tell apart \
    from it (either answer is right: not marked).";

/// The legend, the counts and the next / previous crack buttons; the step clicked, if any.
pub fn legend(ui: &mut egui::Ui, legend: &Legend) -> Option<Step> {
    let swatch = |ui: &mut egui::Ui, rgb: [f32; 3], what: &str| {
        let [r, g, b] = rgb.map(linear_to_srgb8);
        ui.colored_label(egui::Color32::from_rgb(r, g, b), "■");
        ui.small(what);
    };
    ui.horizontal_wrapped(|ui| match legend.code {
        true => {
            swatch(ui, CRACK, "leak");
            swatch(ui, FALSE_HIT, "false hit");
            swatch(ui, WRONG, "wrong primitive");
        }
        false => swatch(
            ui,
            CRACK,
            "leak or false hit (wrong primitives not painted)",
        ),
    });
    // (Two lines whether counted or not: the counts, then what they are of or what they wait
    // for. One line while counting, then the counts wrapped to two, moved every control
    // below them as a click was on its way.)
    let (counts, of) = match &legend.line {
        Ok(line) => match line.split_once(" (") {
            Some((counts, of)) => (counts, of.strip_suffix(')').unwrap_or(of)),
            None => (line.as_str(), ""),
        },
        Err(why) => ("leaks – · false hits – · wrong – · ties –", *why),
    };
    ui.label(egui::RichText::new(counts).strong())
        .on_hover_text(COUNTS_HELP);
    // (The marked pixels' count here, not before the buttons: that row, wider once counted,
    // widened the panel, and the view with it, as the count arrived.)
    match legend.marked {
        Some(n) => ui.small(format!("{of}; {} px marked", grouped(n as u64))),
        None => ui.small(of),
    };
    let mut step = None;
    ui.horizontal(|ui| {
        if ui
            .small_button("◀ previous (Shift+N)")
            .on_hover_text("the previous marked pixel in the ray inspector")
            .clicked()
        {
            step = Some(Step::Previous);
        }
        if ui
            .small_button("next crack (N) ▶")
            .on_hover_text("the next marked pixel, in reading order, in the ray inspector")
            .clicked()
        {
            step = Some(Step::Next);
        }
    });
    step
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hit on the exact primitive, a miss where nothing is met, a leak and a false hit are
    /// decided without looking a primitive up (a window scene's list may be empty); an index
    /// past the scene is a wrong primitive, or a false hit where nothing is met.
    #[test]
    fn classify_looks_up_only_the_two_primitives_of_a_disagreement() {
        let ray = Ray::new([0.0; 3], [0.0, 0.0, 1.0]);
        let hit = |prim| Hit {
            t: 1.0,
            prim,
            b1: 0.0,
            b2: 0.0,
        };
        let nothing = |p: u32| -> Shape { panic!("primitive {p} looked up") };
        assert_eq!(
            classify(1, nothing, &ray, Some(hit(0)), Some(hit(0))),
            Verdict::Right
        );
        assert_eq!(classify(1, nothing, &ray, None, None), Verdict::Right);
        assert_eq!(
            classify(1, nothing, &ray, Some(hit(0)), None),
            Verdict::Leak
        );
        assert_eq!(
            classify(1, nothing, &ray, None, Some(hit(0))),
            Verdict::FalseHit
        );
        assert_eq!(
            classify(1, nothing, &ray, Some(hit(0)), Some(hit(1))),
            Verdict::Wrong
        );
        assert_eq!(
            classify(1, nothing, &ray, None, Some(hit(1))),
            Verdict::FalseHit
        );
    }

    fn census(pixels: &[(u32, u32)]) -> Census {
        Census {
            generation: 1,
            level: 1,
            size: (640, 480),
            offset: 0,
            spp: 1,
            who: "moller".into(),
            code: false,
            counts: Counts {
                leaks: 3,
                false_hits: 0,
                wrong: 1,
                ties: 12,
            },
            marked: pixels
                .iter()
                .map(|&pixel| Marked {
                    pixel,
                    sample: (0, 0),
                    verdict: Verdict::Leak,
                })
                .collect(),
        }
    }

    #[test]
    fn steps_go_in_reading_order_and_wrap_around() {
        let c = census(&[(5, 1), (2, 3), (9, 3)]);
        let at = |from, step| c.step(from, step).map(|(k, m)| (k, m.pixel));
        assert_eq!(at(None, Step::Next), Some((0, (5, 1))));
        assert_eq!(at(None, Step::Previous), Some((2, (9, 3))));
        assert_eq!(at(Some((5, 1)), Step::Next), Some((1, (2, 3))));
        assert_eq!(at(Some((6, 1)), Step::Next), Some((1, (2, 3))));
        assert_eq!(at(Some((9, 3)), Step::Next), Some((0, (5, 1))));
        assert_eq!(at(Some((5, 1)), Step::Previous), Some((2, (9, 3))));
        assert_eq!(at(Some((3, 3)), Step::Previous), Some((1, (2, 3))));
        assert_eq!(c.find((2, 3)).map(|(k, _)| k), Some(1));
        assert_eq!(c.find((3, 3)), None);
        assert!(census(&[]).step(None, Step::Next).is_none());
    }

    #[test]
    fn the_summary_groups_digits_and_names_samples() {
        let mut c = census(&[]);
        assert_eq!(
            c.summary(),
            "leaks 3 · false hits 0 · wrong 1 · ties 12 (of 307,200 px)"
        );
        c.spp = 2;
        assert!(c.summary().ends_with("(of 1,228,800 samples, 2×2 a pixel)"));
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1,000");
        assert_eq!(grouped(12345678), "12,345,678");
    }
}
