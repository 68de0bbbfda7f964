//! `solari soak`: the whole real-time pipeline for many frames with the non-finite detector
//! on every pass of every frame, optionally switching lights on and off, ending with a JSON
//! summary: non-finite, negative and over-bound counts per pass (with the first frame of
//! each), world-cache overflows, GPU and process memory at the start and the end, and
//! wall frame-time percentiles over every frame and GPU ones over the frames `--time-every`
//! times (one in 8 by default; the summary's `gpu_frame_ms.frames` says how many), and the
//! eight slowest frames by wall time with their index and the frames since the last light
//! toggle. Exits with status 1 when anything was found.

use solari_app::cli::{Prepared, SoakArgs};
use solari_app::output::write_atomic;
use solari_renderer::{FINITE_SLOTS, FrameReport, RealtimeRenderer};
use solari_scene::{Material, Scene};
use std::time::Instant;

/// The slowest frames of a run by wall time, with where they fell: a hitch's frame index and
/// its distance from the last light toggle say more than a percentile does.
struct Slowest {
    /// (wall ms, frame, frames since the last toggle), slowest first.
    frames: Vec<(f64, u64, Option<u64>)>,
}

/// How many of the slowest frames the summary lists.
const SLOWEST_FRAMES: usize = 8;

impl Slowest {
    fn add(&mut self, ms: f64, frame: u64, since_toggle: Option<u64>) {
        if !ms.is_finite()
            || (self.frames.len() == SLOWEST_FRAMES && ms <= self.frames[SLOWEST_FRAMES - 1].0)
        {
            return;
        }
        let at = self.frames.partition_point(|f| f.0 >= ms);
        self.frames.insert(at, (ms, frame, since_toggle));
        self.frames.truncate(SLOWEST_FRAMES);
    }

    fn json(&self) -> serde_json::Value {
        self.frames
            .iter()
            .map(|&(ms, frame, since)| {
                serde_json::json!({"frame": frame, "wall_ms": ms, "frames_since_toggle": since})
            })
            .collect()
    }
}

/// Per pass over the run.
#[derive(Clone, Default, serde::Serialize)]
struct PassFindings {
    non_finite: u64,
    negative: u64,
    over: u64,
    frames_with_findings: u64,
    first_frame: Option<u64>,
}

/// A histogram of frame times on log-spaced buckets (0.01 ms to 10 s, 0.7% wide), so a run of
/// any length keeps constant memory and percentiles within a bucket's width.
struct Times {
    buckets: Vec<u64>,
    count: u64,
    max: f64,
}

const TIME_BUCKETS: usize = 2000;
const TIME_MIN_MS: f64 = 0.01;
const TIME_DECADES: f64 = 6.0;

impl Times {
    fn new() -> Self {
        Self {
            buckets: vec![0; TIME_BUCKETS],
            count: 0,
            max: 0.0,
        }
    }

    fn add(&mut self, ms: f64) {
        if !ms.is_finite() {
            return;
        }
        let t = ((ms.max(TIME_MIN_MS) / TIME_MIN_MS).log10() / TIME_DECADES * TIME_BUCKETS as f64)
            as usize;
        self.buckets[t.min(TIME_BUCKETS - 1)] += 1;
        self.count += 1;
        self.max = self.max.max(ms);
    }

    /// The `q` quantile (bucket upper edge), or None without samples.
    fn quantile(&self, q: f64) -> Option<f64> {
        if self.count == 0 {
            return None;
        }
        let target = (q * self.count as f64).ceil().max(1.0) as u64;
        let mut seen = 0;
        for (i, n) in self.buckets.iter().enumerate() {
            seen += n;
            if seen >= target {
                let edge =
                    TIME_MIN_MS * 10f64.powf((i + 1) as f64 / TIME_BUCKETS as f64 * TIME_DECADES);
                return Some(edge.min(self.max));
            }
        }
        Some(self.max)
    }

    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "frames": self.count,
            "p50": self.quantile(0.5), "p90": self.quantile(0.9),
            "p99": self.quantile(0.99), "p999": self.quantile(0.999),
            "max": (self.count > 0).then_some(self.max),
        })
    }
}

/// The lights `--toggle-lights` switches: every other entry of (emissive instances, then
/// directional lights), or the only one.
struct Toggle {
    // Emissive instance index → its material's dark twin (appended to the scene).
    instances: Vec<(usize, u32, u32)>,
    directional: Vec<(usize, glam::Vec3)>,
    off: bool,
}

impl Toggle {
    fn new(scene: &mut Scene) -> Self {
        let emissive: Vec<usize> = scene
            .instances
            .iter()
            .enumerate()
            .filter(|(_, i)| scene.materials[i.material as usize].is_emissive())
            .map(|(k, _)| k)
            .collect();
        let total = emissive.len() + scene.directional_lights.len();
        let chosen = |k: usize| total == 1 || k.is_multiple_of(2);
        let mut instances = Vec::new();
        let mut twins = std::collections::HashMap::new();
        for (k, &i) in emissive.iter().enumerate() {
            if !chosen(k) {
                continue;
            }
            let lit = scene.instances[i].material;
            let dark = *twins.entry(lit).or_insert_with(|| {
                let mut m: Material = scene.materials[lit as usize].clone();
                m.emissive = glam::Vec3::ZERO;
                m.name.push_str(" (off)");
                scene.materials.push(m);
                (scene.materials.len() - 1) as u32
            });
            instances.push((i, lit, dark));
        }
        let directional = (0..scene.directional_lights.len())
            .filter(|d| chosen(emissive.len() + d))
            .map(|d| (d, scene.directional_lights[d].irradiance))
            .collect();
        Self {
            instances,
            directional,
            off: false,
        }
    }

    fn switched(&self) -> usize {
        self.instances.len() + self.directional.len()
    }

    /// Flips the chosen lights in `scene`.
    fn flip(&mut self, scene: &mut Scene) {
        self.off = !self.off;
        for &(i, lit, dark) in &self.instances {
            scene.instances[i].material = if self.off { dark } else { lit };
        }
        for &(d, irradiance) in &self.directional {
            scene.directional_lights[d].irradiance = if self.off {
                glam::Vec3::ZERO
            } else {
                irradiance
            };
        }
    }
}

/// Resident memory of this process in bytes (Linux), for the CPU side of "memory flat".
fn process_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn allocated(gpu: &solari_scene::gpu::Gpu) -> Option<u64> {
    gpu.device
        .generate_allocator_report()
        .map(|r| r.total_allocated_bytes)
}

fn gpu_memory(gpu: &solari_scene::gpu::Gpu) -> serde_json::Value {
    match gpu.device.generate_allocator_report() {
        Some(r) => serde_json::json!({
            "allocated_bytes": r.total_allocated_bytes,
            "reserved_bytes": r.total_reserved_bytes,
        }),
        None => serde_json::Value::Null,
    }
}

/// What the reports of a run add up to (they arrive late and in order; see `run`).
struct Tally {
    findings: Vec<PassFindings>,
    gpu_ms: Times,
    overflow_total: u64,
    overflow_frames: u64,
    overflow_max: u32,
}

impl Tally {
    fn new() -> Self {
        Self {
            findings: vec![PassFindings::default(); FINITE_SLOTS.len()],
            gpu_ms: Times::new(),
            overflow_total: 0,
            overflow_frames: 0,
            overflow_max: 0,
        }
    }

    fn add(&mut self, report: &FrameReport) {
        let timed: Vec<f64> = report.passes.iter().filter_map(|p| p.gpu_ms).collect();
        if !timed.is_empty() {
            self.gpu_ms.add(timed.iter().sum());
        }
        for (f, c) in self.findings.iter_mut().zip(&report.finite) {
            f.non_finite += c.non_finite;
            f.negative += c.negative;
            f.over += c.over;
            if c.non_finite + c.negative + c.over > 0 {
                f.frames_with_findings += 1;
                f.first_frame.get_or_insert(report.frame as u64);
            }
        }
        if let Some(stats) = report.cache {
            self.overflow_total += stats.overflows as u64;
            self.overflow_frames += (stats.overflows > 0) as u64;
            self.overflow_max = self.overflow_max.max(stats.overflows);
        }
    }
}

pub fn run(args: &SoakArgs) -> Result<(), String> {
    let start = Instant::now();
    let settings = args.check()?;
    let (w, h) = args.size;
    let Prepared {
        name,
        mut scene,
        camera,
        gpu,
        backend,
        mut gpu_scene,
        dlss,
        ..
    } = args.scene.prepare()?;
    let mut toggle = args.toggle_lights.map(|_| Toggle::new(&mut scene));
    if toggle.is_some() {
        // The dark twins are new materials: upload them once, before the first frame.
        gpu_scene = solari_scene::gpu_scene::GpuScene::new(
            &gpu,
            &scene,
            backend,
            &args.scene.gpu_scene_options(),
        )
        .map_err(|e| e.to_string())?;
    }
    let mut renderer =
        RealtimeRenderer::with_dlss(&gpu, backend, &scene, &gpu_scene, w, h, settings, &dlss)
            .map_err(|e| e.to_string())?;
    let memory_start = gpu_memory(&gpu);
    let rss_start = process_rss();
    // Resources made on first use (profiler queries, the detector's bind groups) are in
    // place after a few frames: memory growth is measured from there.
    let warm_frame = args.frames.min(100);
    let (mut memory_warm, mut rss_warm) = (serde_json::Value::Null, None);
    let (mut memory_max, mut rss_max) = (0u64, 0u64);
    let mut tally = Tally::new();
    let mut wall = Times::new();
    let mut slowest = Slowest { frames: Vec::new() };
    let mut toggles = 0u64;
    let mut last_toggle = None;
    let (mut last_progress, mut last_frames) = (Instant::now(), 0u64);
    let progress = |tally: &Tally, done: u64, since: Instant, since_frames: u64| {
        let bad: u64 = tally
            .findings
            .iter()
            .map(|f| f.non_finite + f.negative)
            .sum();
        eprintln!(
            "soak {name}: frame {done}/{} ({:.0} frames/s), {bad} non-finite/negative, {} cache overflows",
            args.frames,
            (done - since_frames) as f64 / since.elapsed().as_secs_f64().max(1e-9),
            tally.overflow_total
        );
    };
    // The path's pivot comes from the scene as loaded; toggling lights moves no geometry.
    let rig = args.realtime.camera_path.rig(&camera, &scene);
    let loop_start = Instant::now();
    for frame in 0..args.frames {
        if let (Some(k), Some(t)) = (args.toggle_lights, toggle.as_mut())
            && frame > 0
            && frame % k as u64 == 0
        {
            t.flip(&mut scene);
            gpu_scene
                .set_instances(&gpu, &scene)
                .map_err(|e| e.to_string())?;
            renderer
                .set_lights(&gpu, &scene)
                .map_err(|e| e.to_string())?;
            toggles += 1;
            last_toggle = Some(frame);
        }
        let cam = rig.at(frame as u32);
        // Frames go to the GPU without waiting for it (`submit`); each report (GPU times,
        // detector counts, cache counters) arrives `--frames-in-flight` - 1 frames late. Wall
        // time per frame is the time `submit` takes: recording, plus waiting for the oldest
        // frame once the queue is full.
        let t0 = Instant::now();
        let report = renderer
            .submit(&gpu, &scene, &gpu_scene, &cam)
            .map_err(|e| format!("frame {frame}: {e}"))?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        wall.add(ms);
        slowest.add(ms, frame, last_toggle.map(|t| frame - t));
        if let Some(r) = report {
            tally.add(&r);
        }
        let done = frame + 1;
        if done == warm_frame {
            memory_warm = gpu_memory(&gpu);
            rss_warm = process_rss();
        }
        if done >= warm_frame && (done % 1000 == 0 || done == args.frames) {
            memory_max = memory_max.max(allocated(&gpu).unwrap_or(0));
            rss_max = rss_max.max(process_rss().unwrap_or(0));
        }
        if args.progress_every > 0 && done % args.progress_every == 0 && done < args.frames {
            progress(&tally, done, last_progress, last_frames);
            (last_progress, last_frames) = (Instant::now(), done);
        }
    }
    for r in renderer.finish(&gpu).map_err(|e| e.to_string())? {
        tally.add(&r);
    }
    // Everything the loop did per frame (toggles, camera, reports, memory probes), the GPU's
    // last frames included: the rate a user would see, beside `submit`'s own time.
    let loop_ms = loop_start.elapsed().as_secs_f64() * 1e3 / args.frames.max(1) as f64;
    // The last line counts every frame, the ones still in flight when the loop ended too.
    if args.progress_every > 0 {
        progress(&tally, args.frames, last_progress, last_frames);
    }
    let Tally {
        findings,
        gpu_ms,
        overflow_total,
        overflow_frames,
        overflow_max,
    } = tally;
    let clean = findings.iter().all(|f| f.non_finite + f.negative == 0);
    let per_pass: serde_json::Map<String, serde_json::Value> = FINITE_SLOTS
        .iter()
        .zip(&findings)
        .map(|(n, f)| (n.to_string(), serde_json::json!(f)))
        .collect();
    let summary = serde_json::json!({
        "scene": name, "frames": args.frames, "width": w, "height": h,
        "camera_path": format!("{:?}", args.realtime.camera_path).to_lowercase(),
        "gi": format!("{:?}", settings.gi), "specular_gi": settings.specular_gi, "denoiser": renderer.denoiser_kind().name(),
        "tracer": backend.name(), "adapter": gpu.info.name,
        "toggle_lights_every": args.toggle_lights,
        "lights_switched": toggle.as_ref().map(Toggle::switched), "toggles": toggles,
        "clean": clean, "passes": per_pass,
        "cache_overflows": {"total": overflow_total, "frames": overflow_frames, "max_in_a_frame": overflow_max},
        "gpu_memory": {"start": memory_start, "after_warmup": memory_warm,
            "end": gpu_memory(&gpu), "max_allocated_after_warmup": memory_max,
            "warmup_frames": warm_frame},
        "process_rss_bytes": {"start": rss_start, "after_warmup": rss_warm, "end": process_rss(),
            "max_after_warmup": rss_max},
        "wall_frame_ms": wall.json(), "slowest_wall_frames": slowest.json(), "loop_ms_per_frame": loop_ms, "gpu_frame_ms": gpu_ms.json(),
        "seconds": start.elapsed().as_secs_f64(),
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    println!("{text}");
    if let Some(p) = &args.summary {
        write_atomic(p, text.as_bytes())?;
    }
    if clean {
        Ok(())
    } else {
        Err("the soak found non-finite or negative values (see \"passes\")".into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_come_within_a_bucket() {
        let mut t = Times::new();
        for i in 1..=1000 {
            t.add(i as f64 * 0.01);
        }
        let p50 = t.quantile(0.5).unwrap();
        assert!((p50 - 5.0).abs() / 5.0 < 0.01, "{p50}");
        assert_eq!(t.quantile(1.0), Some(10.0));
        assert_eq!(Times::new().quantile(0.5), None);
    }

    #[test]
    fn the_slowest_frames_are_kept_slowest_first() {
        let mut s = Slowest { frames: Vec::new() };
        for frame in 0..100u64 {
            // Frame 37 the slowest, then every tenth; a NaN never enters.
            let ms = if frame == 37 {
                500.0
            } else if frame % 10 == 0 {
                10.0 + frame as f64
            } else {
                4.0
            };
            s.add(ms, frame, Some(frame % 7));
        }
        s.add(f64::NAN, 100, None);
        let frames: Vec<u64> = s.frames.iter().map(|f| f.1).collect();
        assert_eq!(frames, [37, 90, 80, 70, 60, 50, 40, 30]);
        assert_eq!(s.frames[0].2, Some(2));
        assert!(s.frames.windows(2).all(|w| w[0].0 >= w[1].0));
    }

    #[test]
    fn toggling_switches_every_other_light_or_the_only_one() {
        let mut one = solari_scene::default_scene::cornell_box();
        let before = one.materials.len();
        let mut t = Toggle::new(&mut one);
        assert_eq!(t.switched(), 1);
        assert_eq!(one.materials.len(), before + 1);
        t.flip(&mut one);
        assert_eq!(one.stats().emissive_triangles, 0);
        t.flip(&mut one);
        assert_eq!(one.stats().emissive_triangles, 2);
        let mut many = one.clone();
        for k in 0..5 {
            let mut i = many.instances[5].clone();
            i.transform = glam::Mat4::from_translation(glam::Vec3::X * k as f32);
            many.instances.push(i);
        }
        many.directional_lights
            .push(solari_scene::DirectionalLight {
                name: "sun".into(),
                direction: -glam::Vec3::Y,
                irradiance: glam::Vec3::ONE,
                angular_diameter: 0.01,
            });
        let mut t = Toggle::new(&mut many);
        // Six emitters and a sun: entries 0, 2, 4 and 6 (the sun).
        assert_eq!(t.switched(), 4);
        t.flip(&mut many);
        assert_eq!(many.stats().emissive_triangles, 2 * 3);
        assert_eq!(many.directional_lights[0].irradiance, glam::Vec3::ZERO);
    }
}
