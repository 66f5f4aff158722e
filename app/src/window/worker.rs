//! Renders off the event-loop thread: one worker thread takes the newest job (older pending
//! jobs are dropped unrendered), renders it on the rayon pool and hands the image back.

use raylab::camera::Camera;
use raylab::check::LabCode;
use raylab::render::{self, RenderSettings, RenderStats, Stage};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

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
}

/// A finished image.
pub struct Done {
    /// The job, as submitted.
    pub job: Job,
    /// RGBA8 pixels, or why the render failed; `Ok(None)` if a newer generation cancelled it.
    pub image: Result<Option<(Vec<u8>, RenderStats)>, String>,
}

#[derive(Default)]
struct Slot {
    job: Option<Job>,
    quit: bool,
}

/// The worker thread and its mailbox.
pub struct Worker {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    /// The app's newest generation: a refinement job of an older one stops at its next band.
    latest: Arc<AtomicU64>,
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
                let stale = || job.level > 0 && newest.load(Ordering::Relaxed) != job.generation;
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
                if tx.send(Done { job, image }).is_err() {
                    return;
                }
                wake();
            })
            .expect("spawn the render thread");
        Self {
            slot,
            latest,
            done: rx,
            outstanding: 0,
            thread: Some(thread),
        }
    }

    /// Tells a running job of an older generation to stop.
    pub fn set_generation(&self, generation: u64) {
        self.latest.store(generation, Ordering::Relaxed);
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
        // A refinement in progress stops at its next band (no generation is this new), so
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
