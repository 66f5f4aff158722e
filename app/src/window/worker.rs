//! Renders off the event-loop thread: one worker thread takes the newest job (older pending
//! jobs are dropped unrendered), renders it on the rayon pool and hands the image back.

use raylab::camera::Camera;
use raylab::check::LabCode;
use raylab::render::{self, RenderSettings, RenderStats, Stage};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

/// What to render.
#[derive(Clone)]
pub struct Job {
    /// The scene and its structure.
    pub stage: Stage,
    /// The camera (focal length for this job's width).
    pub camera: Camera,
    /// Size, step, sampling, method.
    pub settings: RenderSettings,
    /// Linked code that answers the rays instead of raylab's structure ("your code").
    pub code: Option<Arc<dyn LabCode>>,
    /// The app's change counter when the job was made.
    pub generation: u64,
    /// Refinement level: 0 preview, 1 full resolution, 2 full supersampling.
    pub level: u8,
    /// The columns of the view left of the image, which the inspector's panel crops at its
    /// sides (0 uncropped): the cracks are counted over the whole view.
    pub view_offset: u32,
}

/// A finished image.
pub struct Done {
    /// The job, as submitted.
    pub job: Job,
    /// RGBA8 pixels, or why the render failed; `Ok(None)` if a newer generation cancelled it.
    pub image: Result<Option<(Vec<u8>, RenderStats)>, String>,
}

/// A refinement being rendered: the status line tells how far it has come, so a long one
/// (16x16 samples with cracks counted takes a minute) does not look like a hang.
struct Underway {
    level: u8,
    spp: u32,
    since: Instant,
    /// The image's tiles, and how many have started (the renderer asks whether to stop
    /// before each tile, and once at the end).
    tiles: u64,
    started: AtomicU64,
}

/// How far the refinement being rendered has come.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Its refinement level (1 full resolution, 2 full supersampling) and supersampling.
    pub level: u8,
    pub spp: u32,
    /// When it started rendering.
    pub since: Instant,
    /// The share of its tiles begun, 0 to 1.
    pub begun: f64,
}

#[derive(Default)]
struct Slot {
    job: Option<Job>,
    quit: bool,
}

/// The worker thread and its mailbox.
pub struct Worker {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    /// The app's newest generation: a refinement job of an older one stops at its next tile.
    latest: Arc<AtomicU64>,
    underway: Arc<Mutex<Option<Arc<Underway>>>>,
    done: Receiver<Done>,
    outstanding: usize,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the thread; `wake` is called after each finished job (to wake the event loop).
    pub fn new(wake: impl Fn() + Send + 'static) -> Self {
        let slot = Arc::new((Mutex::new(Slot::default()), Condvar::new()));
        let (tx, rx): (Sender<Done>, Receiver<Done>) = channel();
        let shared = slot.clone();
        let latest = Arc::new(AtomicU64::new(0));
        let newest = latest.clone();
        let underway = Arc::new(Mutex::new(None));
        let now_underway = underway.clone();
        let thread = std::thread::Builder::new()
            .name("raylab-render".into())
            .spawn(move || loop {
                let job = {
                    let (lock, cvar) = &*shared;
                    let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
                    while s.job.is_none() && !s.quit {
                        s = cvar.wait(s).unwrap_or_else(|e| e.into_inner());
                    }
                    if s.quit {
                        return;
                    }
                    s.job.take().expect("checked above")
                };
                let mut rgba = vec![0u8; job.settings.buffer_len()];
                // Only refinement is cancelled: a preview is short, and a slightly stale preview
                // beats none (cancelling previews too would show nothing while the camera moves,
                // since every frame of motion is a new generation).
                let refining = (job.level > 0).then(|| {
                    Arc::new(Underway {
                        level: job.level,
                        spp: job.settings.spp,
                        since: Instant::now(),
                        tiles: render::tiles(job.settings.width, job.settings.height),
                        started: AtomicU64::new(0),
                    })
                });
                *now_underway.lock().unwrap_or_else(|e| e.into_inner()) = refining.clone();
                let stale = || {
                    if let Some(r) = &refining {
                        r.started.fetch_add(1, Ordering::Relaxed);
                    }
                    job.level > 0 && newest.load(Ordering::Relaxed) != job.generation
                };
                let (stage, camera, settings) = (&job.stage, &job.camera, &job.settings);
                let image = match &job.code {
                    Some(code) => raylab::check::code::render_into_cancellable(
                        code.as_ref(),
                        stage,
                        camera,
                        settings,
                        &mut rgba,
                        &stale,
                    ),
                    None => {
                        render::render_into_cancellable(stage, camera, settings, &mut rgba, &stale)
                    }
                }
                .map(|stats| stats.map(|s| (rgba, s)))
                .map_err(|e| e.to_string());
                *now_underway.lock().unwrap_or_else(|e| e.into_inner()) = None;
                if tx.send(Done { job, image }).is_err() {
                    return;
                }
                wake();
            })
            .expect("spawn the render thread");
        Self {
            slot,
            latest,
            underway,
            done: rx,
            outstanding: 0,
            thread: Some(thread),
        }
    }

    /// Tells a running job of an older generation to stop.
    pub fn set_generation(&self, generation: u64) {
        self.latest.store(generation, Ordering::Relaxed);
    }

    /// How far the refinement being rendered has come, if one is.
    pub fn progress(&self) -> Option<Progress> {
        let underway = self.underway.lock().unwrap_or_else(|e| e.into_inner());
        underway.as_ref().map(|u| Progress {
            level: u.level,
            spp: u.spp,
            since: u.since,
            begun: u.started.load(Ordering::Relaxed).min(u.tiles) as f64 / u.tiles.max(1) as f64,
        })
    }

    /// Whether no job is queued or rendering.
    pub fn is_idle(&self) -> bool {
        self.outstanding == 0
    }

    /// Queues `job`, replacing a queued job that has not started.
    pub fn submit(&mut self, job: Job) {
        let (lock, cvar) = &*self.slot;
        let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
        if s.job.replace(job).is_none() {
            self.outstanding += 1;
        }
        cvar.notify_one();
    }

    /// The newest finished image, if any finished since the last call.
    pub fn take_latest(&mut self) -> Option<Done> {
        let mut latest = None;
        while let Ok(done) = self.done.try_recv() {
            self.outstanding = self.outstanding.saturating_sub(1);
            latest = Some(done);
        }
        latest
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // A refinement in progress stops at its next tile (no generation is this new), so
        // quitting never waits for a long render.
        self.latest.store(u64::MAX, Ordering::Relaxed);
        {
            let (lock, cvar) = &*self.slot;
            lock.lock().unwrap_or_else(|e| e.into_inner()).quit = true;
            cvar.notify_one();
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab::accel::AccelChoice;
    use raylab::Scene;
    use std::time::Duration;

    #[test]
    fn a_refinement_says_how_far_it_has_come_and_a_preview_does_not() {
        let mut worker = Worker::new(|| {});
        let job = |level: u8, spp: u32| {
            let settings = RenderSettings {
                width: 320,
                height: 16 * 40,
                spp,
                ..RenderSettings::default()
            };
            Job {
                stage: render::Stage::new(Scene::cornell(), AccelChoice::Bvh),
                camera: Camera::cornell(settings.width),
                settings,
                code: None,
                generation: 0,
                level,
                view_offset: 0,
            }
        };
        let finish = |worker: &mut Worker| loop {
            if let Some(done) = worker.take_latest() {
                assert!(matches!(done.image, Ok(Some(_))));
                return;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        worker.submit(job(0, 1));
        finish(&mut worker);
        assert!(worker.progress().is_none(), "a preview is not said");
        // 20 by 40 tiles: some begun, not all, while it renders.
        worker.submit(job(2, 6));
        let seen = loop {
            match worker.progress() {
                Some(p) if p.begun > 0.0 => break p,
                // (Never a wait without end: a render done before it was seen fails.)
                _ => match worker.take_latest() {
                    Some(_) => panic!("the refinement ended before its progress was seen"),
                    None => std::thread::sleep(Duration::from_millis(1)),
                },
            }
        };
        assert_eq!((seen.level, seen.spp), (2, 6));
        assert!(seen.begun < 1.0, "{seen:?}");
        finish(&mut worker);
        assert!(
            worker.progress().is_none(),
            "nothing is under way once it is done"
        );
    }
}
