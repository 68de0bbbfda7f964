//! Running cases: case `i` of a run is fully determined by the run's seed and `i` (so any
//! finding replays with `--replay i`), panics are caught and counted (the panic hook is
//! silenced while the harness runs), and a watchdog thread ends the process when one case
//! runs longer than the hang limit.

use crate::mutate::mutate;
use crate::seeds::Seed;
use crate::targets::{Outcome, cli, cli_args, import};
use rand::{Rng, SeedableRng};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Once};
use std::time::{Duration, Instant};

/// Which target a case exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The glTF/GLB importer on a mutated seed.
    Import,
    /// The command line's parsing, checks and scene loading.
    Cli,
}

/// A generated case.
#[derive(Clone, Debug)]
pub enum Case {
    /// Mutated bytes of seed `seed` (index into the run's seeds).
    Import {
        /// Which seed.
        seed: usize,
        /// The mutated file.
        bytes: Vec<u8>,
    },
    /// A command line.
    Cli {
        /// Its arguments, program name first.
        args: Vec<OsString>,
    },
}

/// Everything a run needs to generate and run its cases.
pub struct Harness {
    /// The run's seed.
    pub seed: u64,
    /// Targets to pick from (uniformly).
    pub targets: Vec<Target>,
    /// Seed inputs, with their selection weights.
    pub seeds: Vec<Seed>,
    weights: Vec<f64>,
    /// The work folder for the command-line target's files.
    pub work: PathBuf,
    files: Vec<PathBuf>,
}

impl Harness {
    /// A harness over `seeds`, writing the command line's files under `work` (created).
    ///
    /// Seeds are weighted by the inverse of the time one import of them takes (measured
    /// here, at least 0.1 ms), so each gets about the same share of the run's time: the
    /// million-triangle spheres cost thousands of Cornell boxes per case.
    pub fn new(seed: u64, targets: Vec<Target>, seeds: Vec<Seed>, work: &Path) -> Self {
        let weights = seeds
            .iter()
            .map(|s| {
                let t = Instant::now();
                let _ = import(&s.bytes, &s.base, &s.name);
                1.0 / t.elapsed().as_secs_f64().max(1e-4)
            })
            .collect();
        let _ = std::fs::create_dir_all(work);
        // The command line's inputs: a few seeds copied into the folder, one mutated copy of
        // each (rewritten per case would be slow and racy between workers), an image.
        let mut files = Vec::new();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed ^ 0xC11);
        for (i, s) in seeds
            .iter()
            .enumerate()
            .filter(|(_, s)| s.bytes.len() < 64 << 10)
            .take(6)
        {
            let ext = if s.bytes.starts_with(b"glTF") {
                "glb"
            } else {
                "gltf"
            };
            let p = work.join(format!("seed{i}.{ext}"));
            if std::fs::write(&p, &s.bytes).is_ok() {
                files.push(p);
            }
            let m = work.join(format!("mutant{i}.{ext}"));
            if std::fs::write(&m, mutate(&s.bytes, &mut rng)).is_ok() {
                files.push(m);
            }
        }
        let png = work.join("image.png");
        if write_png(&png).is_ok() {
            files.push(png);
        }
        let dir = work.join("folder");
        let _ = std::fs::create_dir_all(&dir);
        files.push(dir);
        Self {
            seed,
            targets,
            seeds,
            weights,
            work: work.to_path_buf(),
            files,
        }
    }

    /// Case `index` of this run.
    pub fn case(&self, index: u64) -> Case {
        let mut rng =
            rand_pcg::Pcg64::seed_from_u64(self.seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let target = self.targets[rng.random_range(0..self.targets.len())];
        match target {
            Target::Import => {
                let total: f64 = self.weights.iter().sum();
                let mut x = rng.random_range(0.0..total);
                let mut seed = self.seeds.len() - 1;
                for (i, w) in self.weights.iter().enumerate() {
                    if x < *w {
                        seed = i;
                        break;
                    }
                    x -= w;
                }
                let bytes = mutate(&self.seeds[seed].bytes, &mut rng);
                Case::Import { seed, bytes }
            }
            Target::Cli => Case::Cli {
                args: cli_args(&mut rng, &self.work, &self.files),
            },
        }
    }

    /// Runs `case`, turning a panic anywhere into [`Outcome::Panic`].
    pub fn run(&self, case: &Case) -> Outcome {
        install_quiet_hook();
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match case {
            Case::Import { seed, bytes } => {
                let s = &self.seeds[*seed];
                import(bytes, &s.base, &s.name)
            }
            Case::Cli { args } => cli(args),
        }));
        result.unwrap_or_else(|_| {
            Outcome::Panic(LAST_PANIC.with(|p| p.borrow().clone()).unwrap_or_default())
        })
    }

    /// Writes `case` to `folder` for replay outside the harness; returns the file.
    pub fn save(&self, case: &Case, index: u64, folder: &Path) -> std::io::Result<PathBuf> {
        std::fs::create_dir_all(folder)?;
        match case {
            Case::Import { seed, bytes } => {
                let ext = if bytes.starts_with(b"glTF") {
                    "glb"
                } else {
                    "gltf"
                };
                let p = folder.join(format!("case-{index}-{}.{ext}", self.seeds[*seed].name));
                std::fs::write(&p, bytes)?;
                Ok(p)
            }
            Case::Cli { args } => {
                let p = folder.join(format!("case-{index}-cli.txt"));
                let text: Vec<String> = args.iter().map(|a| format!("{a:?}")).collect();
                std::fs::write(&p, text.join(" "))?;
                Ok(p)
            }
        }
    }
}

fn write_png(path: &Path) -> Result<(), String> {
    let png = solari_reference::image_io::encode_png_rgb8(8, 8, &[200u8; 8 * 8 * 3])?;
    std::fs::write(path, png).map_err(|e| e.to_string())
}

thread_local! {
    static LAST_PANIC: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Replaces the panic hook with one that records the message (with its location) for
/// [`Harness::run`] instead of printing it: most cases end in expected errors, and a panic is
/// reported once, as a finding.
fn install_quiet_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            let msg = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_default();
            let at = info
                .location()
                .map(|l| format!("{}:{}", l.file(), l.line()))
                .unwrap_or_default();
            LAST_PANIC.with(|p| *p.borrow_mut() = Some(format!("{msg} at {at}")));
        }));
    });
}

/// Tallies of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Cases run.
    pub cases: u64,
    /// Accepted inputs.
    pub ok: u64,
    /// Refused inputs.
    pub refused: u64,
    /// Panics: (case index, message).
    pub panics: Vec<(u64, String)>,
    /// The slowest case: (index, seconds).
    pub slowest: (u64, f64),
}

/// The case running now and when it started, for the watchdog.
#[derive(Default)]
pub struct Progress {
    /// Index of the running case.
    pub case: AtomicU64,
    /// Its start, in milliseconds since the run began (u64::MAX when idle).
    pub started_ms: AtomicU64,
}

/// Ends the process (exit status 3, after `report`) when a case runs past `limit`; `begin` is
/// the instant [`run_range`] measures start times from.
pub fn watchdog(
    progress: Arc<Progress>,
    begin: Instant,
    limit: Duration,
    report: impl Fn(u64) + Send + 'static,
) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_millis(100));
            let started = progress.started_ms.load(Ordering::Acquire);
            if started == u64::MAX {
                continue;
            }
            let now = begin.elapsed().as_millis() as u64;
            if now.saturating_sub(started) > limit.as_millis() as u64 {
                report(progress.case.load(Ordering::Acquire));
                std::process::exit(3);
            }
        }
    });
}

/// Runs cases `range` in this process, telling `progress` which case runs (for a watchdog)
/// and calling `each` after every case.
pub fn run_range(
    h: &Harness,
    range: std::ops::Range<u64>,
    progress: &Progress,
    begin: Instant,
    mut each: impl FnMut(u64, &Case, &Outcome, f64),
) -> Tally {
    let mut t = Tally::default();
    for i in range {
        let case = h.case(i);
        progress.case.store(i, Ordering::Release);
        progress
            .started_ms
            .store(begin.elapsed().as_millis() as u64, Ordering::Release);
        let t0 = Instant::now();
        let outcome = h.run(&case);
        let secs = t0.elapsed().as_secs_f64();
        progress.started_ms.store(u64::MAX, Ordering::Release);
        t.cases += 1;
        match &outcome {
            Outcome::Ok => t.ok += 1,
            Outcome::Refused(_) => t.refused += 1,
            Outcome::Panic(m) => t.panics.push((i, m.clone())),
        }
        if secs > t.slowest.1 {
            t.slowest = (i, secs);
        }
        each(i, &case, &outcome, secs);
    }
    t
}
