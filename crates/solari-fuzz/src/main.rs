//! `solari-fuzz`: runs cases in worker processes (each with a memory limit and a hang
//! watchdog), restarts a worker that dies, saves every finding for replay, and prints a JSON
//! summary. Exit status 1 when anything was found.

use clap::Parser;
use solari_fuzz::run::{Case, Harness, Progress, Target, run_range, watchdog};
use solari_fuzz::targets::Outcome;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(Parser, Debug, Clone)]
#[command(
    name = "solari-fuzz",
    about = "Mutation fuzzing of the Solari importer and command line"
)]
struct Args {
    /// Cases to run.
    #[arg(long, default_value_t = 10_000)]
    cases: u64,
    /// Stop after this many seconds even if cases remain (0: no limit).
    #[arg(long, default_value_t = 0)]
    seconds: u64,
    /// Worker processes (default: the machine's cores).
    #[arg(long)]
    jobs: Option<usize>,
    /// The run's seed: case i of a run is a function of (seed, i).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seed folders (repeatable; default: the repository's test scenes and reproducers).
    #[arg(long = "seeds")]
    seed_dirs: Vec<PathBuf>,
    /// import, cli or all.
    #[arg(long, default_value = "all")]
    target: String,
    /// Where findings, the work folders and summary.json go.
    #[arg(long, default_value = "fuzz-findings")]
    out: PathBuf,
    /// A case running longer than this is a hang.
    #[arg(long, default_value_t = 5)]
    hang_seconds: u64,
    /// Address-space limit of each worker, MiB (exhausting it aborts the worker: a finding).
    #[arg(long, default_value_t = 4096)]
    memory_mib: u64,
    /// Cases per worker process before it is replaced.
    #[arg(long, default_value_t = 20_000)]
    chunk: u64,
    /// Run one case in this process and print what it did.
    #[arg(long)]
    replay: Option<u64>,
    /// Internal: run cases [from, to) as a worker.
    #[arg(long, hide = true)]
    worker: bool,
    #[arg(long, hide = true, default_value_t = 0)]
    from: u64,
    #[arg(long, hide = true, default_value_t = 0)]
    to: u64,
}

fn targets(s: &str) -> Result<Vec<Target>, String> {
    match s {
        "import" => Ok(vec![Target::Import]),
        "cli" => Ok(vec![Target::Cli]),
        "all" => Ok(vec![
            Target::Import,
            Target::Import,
            Target::Import,
            Target::Cli,
        ]),
        other => Err(format!("--target {other}: expected import, cli or all")),
    }
}

fn harness(a: &Args, work: &std::path::Path) -> Result<Harness, String> {
    let dirs = if a.seed_dirs.is_empty() {
        solari_fuzz::seeds::default_dirs()
    } else {
        a.seed_dirs.clone()
    };
    let seeds = solari_fuzz::seeds::load(&dirs);
    if seeds.is_empty() {
        return Err(format!("no .gltf or .glb seeds under {dirs:?}"));
    }
    Ok(Harness::new(a.seed, targets(&a.target)?, seeds, work))
}

/// Limits this process's address space (Linux); a failed allocation then aborts.
fn limit_memory(mib: u64) {
    let bytes = mib.saturating_mul(1 << 20);
    let lim = libc::rlimit {
        rlim_cur: bytes,
        rlim_max: bytes,
    };
    // SAFETY: setrlimit reads a valid rlimit value; failure leaves the limit unchanged.
    unsafe {
        libc::setrlimit(libc::RLIMIT_AS, &lim);
    }
}

/// The worker: one line per event on stdout ("C i o|r|p" when case i ends accepted, refused
/// or panicking, "P i msg" with the panic, "H i" for a hang, "D" at the end), so the parent
/// can tell which case killed it.
fn worker(a: &Args) -> Result<(), String> {
    limit_memory(a.memory_mib);
    let work = a.out.join(format!("work-{}", std::process::id()));
    let h = harness(a, &work)?;
    let progress = Arc::new(Progress::default());
    progress
        .started_ms
        .store(u64::MAX, std::sync::atomic::Ordering::Release);
    let begin = Instant::now();
    watchdog(
        progress.clone(),
        begin,
        Duration::from_secs(a.hang_seconds),
        |i| {
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "H {i}");
            let _ = out.flush();
        },
    );
    let stdout = std::io::stdout();
    run_range(&h, a.from..a.to, &progress, begin, |i, _, outcome, _| {
        let mut out = stdout.lock();
        let kind = match outcome {
            Outcome::Ok => 'o',
            Outcome::Refused(_) => 'r',
            Outcome::Panic(m) => {
                let _ = writeln!(out, "P {i} {}", m.replace('\n', " "));
                'p'
            }
        };
        let _ = writeln!(out, "C {i} {kind}");
        let _ = out.flush();
    });
    let _ = std::fs::remove_dir_all(&work);
    println!("D");
    Ok(())
}

#[derive(Default, Debug)]
struct Findings {
    cases: u64,
    ok: u64,
    refused: u64,
    panics: Vec<(u64, String, String)>,
    crashes: Vec<(u64, String, String)>,
    hangs: Vec<(u64, String)>,
}

fn spawn(a: &Args, from: u64, to: u64) -> Result<Child, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut cmd = Command::new(exe);
    cmd.args([
        "--worker",
        "--from",
        &from.to_string(),
        "--to",
        &to.to_string(),
    ])
    .args(["--seed", &a.seed.to_string(), "--target", &a.target])
    .args(["--hang-seconds", &a.hang_seconds.to_string()])
    .args(["--memory-mib", &a.memory_mib.to_string()])
    .arg("--out")
    .arg(&a.out);
    for d in &a.seed_dirs {
        cmd.arg("--seeds").arg(d);
    }
    cmd.stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start a worker: {e}"))
}

/// Runs one worker over [from, to) to the end, restarting after a crash; returns what it found.
fn drive(a: &Args, h: &Harness, from: u64, to: u64, f: &mut Findings) -> Result<(), String> {
    let mut start = from;
    while start < to {
        let mut child = spawn(a, start, to)?;
        let stdout = child.stdout.take().expect("piped");
        // The case running now: the one after the last that ended.
        let mut current = start;
        let mut done = false;
        let mut hang = None;
        for line in std::io::BufReader::new(stdout).lines() {
            let line = line.map_err(|e| e.to_string())?;
            let mut parts = line.splitn(3, ' ');
            match (
                parts.next(),
                parts.next().and_then(|x| x.parse::<u64>().ok()),
            ) {
                (Some("C"), Some(i)) => {
                    current = i + 1;
                    f.cases += 1;
                    match parts.next() {
                        Some("o") => f.ok += 1,
                        Some("r") => f.refused += 1,
                        _ => {}
                    }
                }
                (Some("P"), Some(i)) => {
                    let file = save(a, h, i);
                    f.panics
                        .push((i, parts.next().unwrap_or("").to_string(), file));
                }
                (Some("H"), Some(i)) => hang = Some(i),
                (Some("D"), _) => done = true,
                _ => {}
            }
        }
        let status = child.wait().map_err(|e| e.to_string())?;
        let mut stderr = String::new();
        if let Some(mut e) = child.stderr.take() {
            let _ = std::io::Read::read_to_string(&mut e, &mut stderr);
        }
        if done && status.success() {
            return Ok(());
        }
        // Died before the end: the case it was running is a finding; go on after it.
        let file = save(a, h, current);
        if let Some(i) = hang {
            f.hangs.push((i, file));
        } else {
            let why = format!("{status}; {}", stderr.lines().last().unwrap_or(""));
            f.crashes.push((current, why, file));
        }
        f.cases += 1;
        start = current + 1;
    }
    Ok(())
}

fn save(a: &Args, h: &Harness, i: u64) -> String {
    h.save(&h.case(i), i, &a.out)
        .map(|p| p.display().to_string())
        .unwrap_or_else(|e| format!("(not saved: {e})"))
}

fn parent(a: &Args) -> Result<bool, String> {
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let h = harness(a, &a.out.join("work-parent"))?;
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let begin = Instant::now();
    let deadline = (a.seconds > 0).then(|| begin + Duration::from_secs(a.seconds));
    let next = std::sync::Mutex::new(0u64);
    let findings = std::sync::Mutex::new(Findings::default());
    let chunk = a.chunk.max(1);
    eprintln!(
        "solari-fuzz: {} cases, {} seeds, {jobs} workers, seed {}",
        a.cases,
        h.seeds.len(),
        a.seed
    );
    std::thread::scope(|s| -> Result<(), String> {
        let mut handles = Vec::new();
        for _ in 0..jobs {
            handles.push(s.spawn(|| -> Result<(), String> {
                loop {
                    if deadline.is_some_and(|d| Instant::now() >= d) {
                        return Ok(());
                    }
                    let (from, to) = {
                        let mut n = next.lock().map_err(|e| e.to_string())?;
                        if *n >= a.cases {
                            return Ok(());
                        }
                        let r = (*n, (*n + chunk).min(a.cases));
                        *n = r.1;
                        r
                    };
                    let mut local = Findings::default();
                    drive(a, &h, from, to, &mut local)?;
                    let mut f = findings.lock().map_err(|e| e.to_string())?;
                    f.cases += local.cases;
                    f.ok += local.ok;
                    f.refused += local.refused;
                    f.panics.extend(local.panics);
                    f.crashes.extend(local.crashes);
                    f.hangs.extend(local.hangs);
                    let elapsed = begin.elapsed().as_secs_f64();
                    eprintln!(
                        "solari-fuzz: {} cases in {elapsed:.0} s ({:.0}/s), {} panics, {} crashes, {} hangs",
                        f.cases,
                        f.cases as f64 / elapsed.max(1e-9),
                        f.panics.len(),
                        f.crashes.len(),
                        f.hangs.len()
                    );
                }
            }));
        }
        for h in handles {
            h.join()
                .map_err(|_| "a driver thread panicked".to_string())??;
        }
        Ok(())
    })?;
    let f = findings.into_inner().map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(a.out.join("work-parent"));
    let clean = f.panics.is_empty() && f.crashes.is_empty() && f.hangs.is_empty();
    let summary = serde_json::json!({
        "cases": f.cases, "accepted": f.ok, "refused": f.refused,
        "panics": f.panics.iter().map(|(i, m, p)| serde_json::json!({"case": i, "message": m, "input": p})).collect::<Vec<_>>(),
        "crashes": f.crashes.iter().map(|(i, m, p)| serde_json::json!({"case": i, "status": m, "input": p})).collect::<Vec<_>>(),
        "hangs": f.hangs.iter().map(|(i, p)| serde_json::json!({"case": i, "input": p})).collect::<Vec<_>>(),
        "seed": a.seed, "target": a.target, "jobs": jobs, "hang_seconds": a.hang_seconds,
        "memory_mib": a.memory_mib, "seconds": begin.elapsed().as_secs_f64(),
        "seeds": h.seeds.len(), "clean": clean,
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    println!("{text}");
    std::fs::write(a.out.join("summary.json"), &text).map_err(|e| e.to_string())?;
    Ok(clean)
}

fn replay(a: &Args, i: u64) -> Result<bool, String> {
    let h = harness(a, &a.out.join("work-replay"))?;
    let case = h.case(i);
    match &case {
        Case::Import { seed, bytes } => {
            eprintln!(
                "case {i}: import of {} bytes mutated from {}",
                bytes.len(),
                h.seeds[*seed].name
            )
        }
        Case::Cli { args } => eprintln!("case {i}: {args:?}"),
    }
    let file = h.save(&case, i, &a.out).map_err(|e| e.to_string())?;
    let t = Instant::now();
    let outcome = h.run(&case);
    eprintln!(
        "saved as {}; {outcome:?} in {:.3} s",
        file.display(),
        t.elapsed().as_secs_f64()
    );
    Ok(!matches!(outcome, Outcome::Panic(_)))
}

fn main() {
    let a = Args::parse();
    let result = if a.worker {
        worker(&a).map(|()| true)
    } else if let Some(i) = a.replay {
        replay(&a, i)
    } else {
        parent(&a)
    };
    match result {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
