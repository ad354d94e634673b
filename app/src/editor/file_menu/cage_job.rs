//! File ▸ Make cage from mesh…, the work behind it: reading a dense mesh and fitting a Loop cage
//! to it ([`taut_core::cage_fit::fit_cage`], the QEM simplification and limit-position solve of
//! seed 002) on a background thread, so the window keeps drawing while it runs.
//!
//! The thread reports through a channel: the step and the fraction of it done (forwarded from
//! the fit's [`Progress`](taut_core::cage_fit::Progress), throttled to changes a progress bar
//! shows), then the result. Cancelling sets a flag that the fit reads at its next progress
//! report (after a step or a chunk of parallel work), so a cancel takes effect within a fraction
//! of a second on any input; the thread then ends without a result and nothing of the editor
//! changed. Besides the cage, the thread prepares what the editor shows afterwards: the
//! original as a mesh for the ghost, and a bounding-volume hierarchy of it for the "distance to
//! original" colour view, so the window never builds them itself.
//!
//! Weak spots: reading the file (import, weld) is not cancellable; only the fit's steps are. The
//! ghost is the whole original: a software renderer draws a million translucent triangles at a
//! frame or two a second. Simplifying it for display to 250,000 triangles was tried and made the
//! ghost step take 10 s instead of 2.7 s on a 1 M-triangle sphere while drawing no faster (the
//! simplifier's retries for a manifold result are the likely cause), so it was taken out.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;
use taut_core::PolyMesh;
use taut_core::cage_fit::surface_index::SurfaceIndex;
use taut_core::cage_fit::{CageFitParams, DenseMesh, FitReport, fit_cage};
use taut_core::io::{self, ImportOptions, UpAxis};

/// What to fit: the mesh file, the size and rounds, and how OBJ files are read.
#[derive(Clone, Debug, PartialEq)]
pub struct CageRequest {
    pub path: PathBuf,
    pub params: CageFitParams,
    pub obj_up: UpAxis,
}

/// A finished fit with what the editor shows beside it.
#[derive(Debug)]
pub struct CageResult {
    pub request: CageRequest,
    /// The kept cage (fitted, or the QEM cage when fitting did not improve on it).
    pub cage: PolyMesh,
    /// The prepared original (manifold, oriented), for the ghost.
    pub original: PolyMesh,
    /// Closest points on the original, for the distance view.
    pub index: SurfaceIndex,
    pub report: FitReport,
    /// Reading the file, preparing it, and building the ghost and its index, in seconds.
    pub import_seconds: f64,
    pub prepare_seconds: f64,
    pub ghost_seconds: f64,
    /// What reading and preparing the file repaired, for the designer's log (empty when clean).
    pub notes: Vec<String>,
}

/// What the thread sends.
enum Message {
    Progress(String, f64),
    Done(Result<Option<Box<CageResult>>, String>),
}

/// Where a running job stands, as last reported.
#[derive(Clone, Debug, PartialEq)]
pub struct JobProgress {
    pub step: String,
    pub fraction: f64,
    pub started: Instant,
}

/// How a job ended, when it has.
#[derive(Debug)]
pub enum JobEnd {
    Finished(Box<CageResult>),
    Cancelled,
    Failed(String),
}

/// Holds a job at its first progress report until released (tests use it to look at a running
/// job deterministically).
pub(crate) type Gate = Arc<(Mutex<bool>, Condvar)>;

/// A fit running on its own thread.
#[derive(Debug)]
pub struct CageJob {
    receiver: Receiver<Message>,
    cancel: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
    pub progress: JobProgress,
    pub request: CageRequest,
}

impl CageJob {
    /// Starts fitting on a new thread; with a `gate`, held at the first progress report while
    /// the gate holds `false` (or until cancelled).
    pub(crate) fn start(request: CageRequest, gate: Option<Gate>) -> Self {
        let (sender, receiver) = mpsc::channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let flag = cancel.clone();
        let job_request = request.clone();
        let handle = std::thread::Builder::new()
            .name("taut cage fit".into())
            .spawn(move || {
                let result = run(&job_request, &flag, gate, &sender);
                let _ = sender.send(Message::Done(result));
            })
            .ok();
        let progress = JobProgress { step: "read the mesh".into(), fraction: 0.0, started: Instant::now() };
        let mut job = CageJob { receiver, cancel, handle, progress, request };
        if job.handle.is_none() {
            // No thread could be started: report it as the job's end on the first poll.
            let (sender, receiver) = mpsc::channel();
            let _ = sender.send(Message::Done(Err("could not start a thread for the fit".into())));
            job.receiver = receiver;
        }
        job
    }

    /// Asks the job to stop at its next progress report.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::SeqCst);
    }

    /// True once [`cancel`](Self::cancel) was called.
    pub fn cancelling(&self) -> bool {
        self.cancel.load(Ordering::SeqCst)
    }

    /// Takes what the thread reported since the last poll; `Some` once it has ended.
    pub fn poll(&mut self) -> Option<JobEnd> {
        loop {
            match self.receiver.try_recv() {
                Ok(Message::Progress(step, fraction)) => {
                    self.progress.step = step;
                    self.progress.fraction = fraction;
                }
                Ok(Message::Done(result)) => {
                    if let Some(handle) = self.handle.take() {
                        let _ = handle.join();
                    }
                    return Some(match result {
                        Ok(Some(result)) => JobEnd::Finished(result),
                        Ok(None) => JobEnd::Cancelled,
                        Err(e) => JobEnd::Failed(e),
                    });
                }
                Err(TryRecvError::Empty) => return None,
                Err(TryRecvError::Disconnected) => {
                    // The thread ended without a word: it panicked.
                    self.handle = None;
                    return Some(JobEnd::Failed("the fit stopped unexpectedly".into()));
                }
            }
        }
    }
}

impl Drop for CageJob {
    /// A job dropped while running (the editor closing) is cancelled, not waited for.
    fn drop(&mut self) {
        self.cancel();
    }
}

/// The job's body: read, prepare, fit, then the ghost and its index. `Ok(None)` when cancelled.
fn run(
    request: &CageRequest,
    cancel: &AtomicBool,
    gate: Option<Gate>,
    sender: &mpsc::Sender<Message>,
) -> Result<Option<Box<CageResult>>, String> {
    let name = |e: &dyn std::fmt::Display| format!("{}: {e}", display_name(&request.path));
    let send = |step: &str, fraction: f64| {
        let _ = sender.send(Message::Progress(step.to_string(), fraction));
    };
    let mut held = gate;
    let mut go_on = |step: &str, fraction: f64| -> bool {
        if let Some(gate) = held.take() {
            let (lock, released) = &*gate;
            let mut open = lock.lock().unwrap_or_else(|e| e.into_inner());
            while !*open && !cancel.load(Ordering::SeqCst) {
                let timeout = std::time::Duration::from_millis(20);
                open = released.wait_timeout(open, timeout).map_or_else(|e| e.into_inner().0, |(g, _)| g);
            }
        }
        send(step, fraction);
        !cancel.load(Ordering::SeqCst)
    };
    if !go_on("read the mesh", 0.0) {
        return Ok(None);
    }
    let started = Instant::now();
    let options = ImportOptions { obj_up: request.obj_up };
    let (positions, triangles, import_report) =
        io::import_triangles(&request.path, &options).map_err(|e| e.to_string())?;
    let import_seconds = started.elapsed().as_secs_f64();
    let mut notes = Vec::new();
    if !import_report.is_clean() {
        notes.push(import_report.to_string());
    }
    if !go_on("prepare the mesh", 0.0) {
        return Ok(None);
    }
    let started = Instant::now();
    let dense = DenseMesh::from_triangles(positions, &triangles).map_err(|e| name(&e))?;
    drop(triangles);
    let prepare_seconds = started.elapsed().as_secs_f64();
    notes.extend(dense.report().notes());

    // Forward the fit's progress when the step changes or the bar would move by a pixel or so.
    let mut last: Option<(String, f64)> = None;
    let mut progress = |step: &str, fraction: f64| {
        let moved = last.as_ref().is_none_or(|(s, f)| s != step || (fraction - f).abs() >= 0.005);
        if moved {
            last = Some((step.to_string(), fraction));
            send(step, fraction);
        }
        !cancel.load(Ordering::SeqCst)
    };
    let Some(fit) = fit_cage(&dense, &request.params, &mut progress).map_err(|e| name(&e))? else {
        return Ok(None);
    };
    if !go_on("prepare the ghost", 0.0) {
        return Ok(None);
    }
    let started = Instant::now();
    let original = PolyMesh::from_polygons(dense.positions().to_vec(), dense.triangles()).map_err(|e| name(&e))?;
    let index = SurfaceIndex::new(dense.positions(), dense.triangles()).map_err(|e| name(&e))?;
    let ghost_seconds = started.elapsed().as_secs_f64();
    if cancel.load(Ordering::SeqCst) {
        return Ok(None);
    }
    Ok(Some(Box::new(CageResult {
        request: request.clone(),
        cage: fit.cage,
        original,
        index,
        report: fit.report,
        import_seconds,
        prepare_seconds,
        ghost_seconds,
        notes,
    })))
}

/// The file's name for messages.
pub fn display_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}
