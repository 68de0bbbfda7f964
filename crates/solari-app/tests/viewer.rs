//! `solari view` in a real window: under a virtual X server (Xvfb) on whatever Vulkan adapter
//! there is (lavapipe in CI), the viewer opens, renders frames, takes a screenshot and closes,
//! and its picture is the headless renderer's picture of the same view. Without Xvfb these
//! tests skip, unless `SOLARI_REQUIRE_GPU=1` (CI), where they fail.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

/// A virtual X server on a free display, stopped when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    /// Starts Xvfb; `None` (or a panic with `SOLARI_REQUIRE_GPU=1`) where it is not installed.
    fn start() -> Option<Self> {
        // -displayfd picks a free display and writes its number once the server is ready.
        let spawned = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(c) => c,
            Err(e) if std::env::var("SOLARI_REQUIRE_GPU").as_deref() == Ok("1") => {
                panic!("SOLARI_REQUIRE_GPU=1 but Xvfb cannot start ({e}): .ci/run installs it")
            }
            Err(e) => {
                eprintln!("skipping: no Xvfb ({e})");
                return None;
            }
        };
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut line)
            .expect("Xvfb's display number");
        let number = line.trim();
        assert!(!number.is_empty(), "Xvfb printed no display number");
        Some(Self {
            child,
            display: format!(":{number}"),
        })
    }

    /// Runs `solari args` in `dir` on this display.
    fn solari(&self, dir: &Path, args: &[&str]) -> Output {
        let out = Command::new(env!("CARGO_BIN_EXE_solari"))
            .args(args)
            .current_dir(dir)
            .env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY")
            .env("RUST_LOG", "error")
            .output()
            .expect("run solari");
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn folder(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("solari-viewer-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn rgb8(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

fn linear(path: &Path) -> image::Rgb32FImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb32f()
}

/// Mean absolute difference per channel (0–255) over the block `x0..x1 × y0..y1`.
fn block_difference(a: &image::RgbImage, b: &image::RgbImage, x: (u32, u32), y: (u32, u32)) -> f64 {
    let mut sum = 0.0;
    for j in y.0..y.1 {
        for i in x.0..x.1 {
            for c in 0..3 {
                sum += (a.get_pixel(i, j)[c] as f64 - b.get_pixel(i, j)[c] as f64).abs();
            }
        }
    }
    sum / ((x.1 - x.0) * (y.1 - y.0) * 3) as f64
}

// Both sides render the same frames of the same fixed view with the same settings (the
// raster G-buffer, so that auto's start-up timing cannot choose differently).
const SAME_VIEW: [&str; 8] = [
    "--size",
    "96x64",
    "--frames",
    "6",
    "--gbuffer",
    "raster",
    "--denoiser",
    "fallback",
];

#[test]
fn the_viewer_shows_what_the_headless_renderer_renders() {
    let Some(x) = Xvfb::start() else { return };
    let d = folder("same");
    let dir = d.as_path();
    let mut args = vec!["view"];
    args.extend(SAME_VIEW);
    x.solari(
        dir,
        &[&args[..], &["--no-ui", "--screenshot", "view.png"]].concat(),
    );
    x.solari(
        dir,
        &[&args[..], &["--no-ui", "--screenshot", "view.exr"]].concat(),
    );
    let mut render = vec!["render", "--mode", "realtime"];
    render.extend(SAME_VIEW);
    x.solari(
        dir,
        &[&render[..], &["--out", "head.png", "--out", "head.exr"]].concat(),
    );

    // Linear output: the same picture up to the renderer's run-to-run noise (lavapipe's
    // threads reorder the world cache's atomics; two headless runs differ by ~0.001 RMSE).
    let (v, h) = (linear(&d.join("view.exr")), linear(&d.join("head.exr")));
    assert_eq!(v.dimensions(), (96, 64));
    assert_eq!(v.dimensions(), h.dimensions());
    let (mut sv, mut sh, mut se) = (0.0f64, 0.0f64, 0.0f64);
    for (a, b) in v.pixels().zip(h.pixels()) {
        for c in 0..3 {
            sv += a[c] as f64;
            sh += b[c] as f64;
            se += (a[c] as f64 - b[c] as f64).powi(2);
        }
    }
    let n = (96 * 64 * 3) as f64;
    let rmse = (se / n).sqrt();
    assert!(
        sh / n > 0.02,
        "the headless image is black: mean {}",
        sh / n
    );
    assert!(
        (sv / sh - 1.0).abs() < 0.02 && rmse < 0.05 * sh / n,
        "viewer against headless: mean ratio {}, RMSE {rmse} (mean {})",
        sv / sh,
        sh / n
    );

    // The window's own picture (the presenter's tone curve on the GPU, read back from the
    // surface format) against the CPU tone curve of the headless PNG.
    let (v, h) = (rgb8(&d.join("view.png")), rgb8(&d.join("head.png")));
    assert_eq!(v.dimensions(), h.dimensions());
    let diff = block_difference(&v, &h, (0, 96), (0, 64));
    assert!(diff < 2.0, "window PNG against headless PNG: {diff} levels");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_overlay_is_drawn_over_the_frame() {
    let Some(x) = Xvfb::start() else { return };
    let d = folder("overlay");
    let dir = d.as_path();
    let common = [
        "view",
        "--size",
        "200x150",
        "--frames",
        "3",
        "--gbuffer",
        "raster",
    ];
    x.solari(dir, &[&common[..], &["--screenshot", "ui.png"]].concat());
    x.solari(
        dir,
        &[&common[..], &["--no-ui", "--screenshot", "bare.png"]].concat(),
    );
    let (ui, bare) = (rgb8(&d.join("ui.png")), rgb8(&d.join("bare.png")));
    assert_eq!(ui.dimensions(), (200, 150));
    // The panel sits at the top left.
    let diff = block_difference(&ui, &bare, (8, 72), (8, 40));
    assert!(diff > 10.0, "no overlay at the top left: {diff} levels");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_viewer_refuses_bad_input_without_a_window() {
    let d = folder("refuse");
    let run = |args: &[&str], display: bool| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_solari"));
        cmd.args(args).current_dir(&d).env("RUST_LOG", "error");
        if !display {
            cmd.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
        }
        let out = cmd.output().expect("run solari");
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
        err
    };
    let err = run(&["view", "--frames", "1"], false);
    assert!(err.contains("cannot open a window"), "{err}");
    assert!(err.contains("solari render --mode realtime"), "{err}");
    for (args, needle) in [
        (&["view", "--denoiser", "dlss-rr"][..], "DLSS-RR"),
        (
            &["view", "--screenshot", "shot.bmp"][..],
            "unknown image extension",
        ),
        (&["view", "missing.glb"][..], "missing.glb"),
        (&["view", "--frames", "0"][..], "--frames"),
        (&["view", "--size", "0x10"][..], "each side"),
    ] {
        let err = run(args, true);
        assert!(
            err.contains(needle),
            "{args:?}: expected {needle:?} in {err}"
        );
    }
    assert!(
        std::fs::read_dir(&d).unwrap().next().is_none(),
        "files left behind"
    );
    let _ = std::fs::remove_dir_all(&d);
}
