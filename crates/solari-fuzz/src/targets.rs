//! What a case runs: the importer on mutated bytes (then what the command line does with a
//! scene before the GPU: validation, statistics, camera choice, the light list and, for small
//! scenes, the software BVH), or the command line's parsing and up-front checks on generated
//! arguments and files.

use rand::Rng;
use solari_app::cli::{Cli, Command};
use solari_scene::{ImportLimits, ImportOptions, Scene};
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// How a case ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Accepted.
    Ok,
    /// Refused with an error (the expected result for most mutated inputs).
    Refused(String),
    /// A panic: a finding.
    Panic(String),
}

/// Import limits for fuzzing: tight enough that every case stays fast and small (the default
/// limits' own enforcement is what the harness checks, at a smaller scale).
pub fn fuzz_limits() -> ImportLimits {
    ImportLimits {
        max_file_bytes: 64 << 20,
        max_image_pixels: 1 << 22,
        max_image_side: 4096,
        max_total_image_bytes: 256 << 20,
    }
}

/// Scenes up to this many triangles also get their software BVH built.
const BVH_TRIANGLES: usize = 50_000;

/// What the command line does with a loaded scene before it opens a device.
fn exercise(scene: &Scene, camera: Option<&str>) {
    let _ = scene.validate();
    let _ = scene.stats();
    let _ = scene.warnings.lines();
    if let Some(c) = scene.camera(camera) {
        let _ = c.validate();
        let _ = solari_scene::gpu_types::GpuView::new(&c, 16, 9);
    }
    let _ = solari_lights::LightList::build(scene);
    if scene.stats().triangles <= BVH_TRIANGLES {
        let _ =
            solari_scene::bvh::SoftwareBvh::build(scene, solari_scene::bvh::BvhQuality::Fastest);
    }
}

/// Imports `bytes` as a file of `base` named `name`, then exercises the scene.
pub fn import(bytes: &[u8], base: &Path, name: &str) -> Outcome {
    let options = ImportOptions {
        limits: fuzz_limits(),
        ..Default::default()
    };
    match solari_scene::import_slice(bytes, base, Path::new(name), &options) {
        Ok(scene) => {
            exercise(&scene, None);
            Outcome::Ok
        }
        Err(solari_scene::SceneError::ImporterPanic { message, .. }) => Outcome::Panic(message),
        Err(e) => Outcome::Refused(e.to_string()),
    }
}

const SUBCOMMANDS: &[&str] = &[
    "render",
    "info",
    "bench-rays",
    "compare",
    "bench-di",
    "bench-cache",
    "bench-denoise",
    "soak",
    "bogus",
];

const SIZES: &[&str] = &[
    "64x64",
    "0x0",
    "100000x100000",
    "1x1",
    "16384x16384",
    "16385x1",
    "x",
    "",
    "-1x5",
    "64x",
    "1e3x5",
    " 7 x 9 ",
    "٣x٣",
    "4294967296x2",
];
const INTS: &[&str] = &[
    "0",
    "1",
    "8",
    "64",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "-1",
    "nan",
    "",
    "1e3",
    "0x10",
    "+5",
];
const FLOATS: &[&str] = &[
    "0", "-1", "1e39", "nan", "NaN", "inf", "-inf", "0.25", "1e-45", "", "x", "-0", "65",
];
const LISTS: &[&str] = &["1,8,32", "", ",", "1,,2", "x", "0.1,nan", "99999", "1;2"];

/// (option, kind): kinds pick values from the tables above or the enum's own names.
const OPTIONS: &[(&str, &str)] = &[
    ("--size", "size"),
    ("--tiles", "size"),
    ("--frames", "int"),
    ("--spp", "int"),
    ("--max-bounces", "int"),
    ("--candidates", "int"),
    ("--cache-budget", "int"),
    ("--cache-capacity", "int"),
    ("--denoise-iterations", "int"),
    ("--warmup", "int"),
    ("--timed-frames", "int"),
    ("--toggle-lights", "int"),
    ("--heightfield", "int"),
    ("--progress-every", "int"),
    ("--capacity", "int"),
    ("--exposure", "float"),
    ("--cache-cell-size", "float"),
    ("--denoise-max-history", "float"),
    ("--firefly-clamp", "float"),
    ("--max-history", "float"),
    ("--phi-lobe", "float"),
    ("--mode", "debug|reference|realtime|x"),
    ("--view", "albedo|normal|depth|instance|lit|world-cache|x"),
    ("--gi", "off|cache|x"),
    ("--denoiser", "none|fallback|dlss-rr|x"),
    ("--selection", "power|uniform|x"),
    ("--camera-path", "fixed|orbit|x"),
    ("--tracer", "auto|software|ray-query|x"),
    ("--bvh-quality", "fastest|medium|very-slow|x"),
    ("--camera", "camera|0|9|render_setup|"),
    ("--candidates", "list"),
    ("--cell-sizes", "list"),
    ("--budgets", "list"),
    ("--iterations", "list"),
    ("--presets", "list"),
    ("--out", "out"),
    ("--exr", "out"),
    ("--report", "out"),
    ("--csv", "out"),
    ("--summary", "out"),
    ("--heatmap", "out"),
    ("--reference", "in"),
    ("--mask-emitters", "in"),
    ("--asset-root", "in"),
    ("--json", "flag"),
    ("--pixel-centre", "flag"),
    ("--check-finite", "flag"),
    ("--compare-checks", "flag"),
];

fn pick<'a>(rng: &mut impl Rng, xs: &[&'a str]) -> &'a str {
    xs[rng.random_range(0..xs.len())]
}

/// A valid value most of the time (so cases reach past parsing), else a hostile one.
fn value<'a>(rng: &mut impl Rng, valid: &[&'a str], hostile: &[&'a str]) -> &'a str {
    if rng.random_bool(0.7) {
        pick(rng, valid)
    } else {
        pick(rng, hostile)
    }
}

/// Input paths: the work folder's files (scenes, mutated scenes, images), the folder itself,
/// missing files, a non-UTF-8 name, device files.
fn input_path(rng: &mut impl Rng, dir: &Path, files: &[PathBuf]) -> OsString {
    use std::os::unix::ffi::OsStringExt;
    match rng.random_range(0..10) {
        0..=5 if !files.is_empty() => files[rng.random_range(0..files.len())].clone().into(),
        4 => dir.as_os_str().to_owned(),
        5 => dir.join("missing.gltf").into(),
        6 => {
            let mut b = dir.as_os_str().to_owned().into_vec();
            b.extend(b"/n\xffo.gltf");
            OsString::from_vec(b)
        }
        _ => pick(rng, &["/dev/null", "/dev/zero", "", "builtin"]).into(),
    }
}

/// Output paths, all inside the work folder (checks create and remove a probe file there).
fn output_path(rng: &mut impl Rng, dir: &Path) -> OsString {
    use std::os::unix::ffi::OsStringExt;
    match rng.random_range(0..8) {
        0 | 5 | 6 => dir
            .join(pick(rng, &["o.png", "o.exr", "o.PNG", "o.csv", "o.jsonl"]))
            .into(),
        1 => dir
            .join(pick(rng, &["o.jpg", "o", "o.", ".png", "o.png.exr"]))
            .into(),
        2 => dir.join("missing/o.png").into(),
        3 => dir.as_os_str().to_owned(),
        4 => {
            let mut b = dir.as_os_str().to_owned().into_vec();
            b.extend(b"/o\xfe.png");
            OsString::from_vec(b)
        }
        _ => dir.join("").into(),
    }
}

/// A random command line (program name first), inside `dir` for every path it names.
pub fn cli_args(rng: &mut impl Rng, dir: &Path, files: &[PathBuf]) -> Vec<OsString> {
    let sub = value(rng, &SUBCOMMANDS[..SUBCOMMANDS.len() - 1], SUBCOMMANDS);
    let mut args: Vec<OsString> = vec!["solari".into(), sub.into()];
    let positional = match args[1].to_str() {
        Some("compare") => 2,
        _ => rng.random_range(0..2),
    };
    for _ in 0..positional {
        if rng.random_bool(0.9) {
            args.push(input_path(rng, dir, files));
        }
    }
    // The subcommand's own options most of the time, so cases get past argument parsing.
    let own: Vec<String> = <Cli as clap::CommandFactory>::command()
        .find_subcommand(sub)
        .map(|c| {
            c.get_arguments()
                .filter_map(|a| a.get_long().map(|l| format!("--{l}")))
                .collect()
        })
        .unwrap_or_default();
    for _ in 0..rng.random_range(0..7) {
        let name = if !own.is_empty() && rng.random_bool(0.85) {
            own[rng.random_range(0..own.len())].clone()
        } else {
            OPTIONS[rng.random_range(0..OPTIONS.len())].0.to_string()
        };
        let (opt, kind) = OPTIONS
            .iter()
            .find(|(o, _)| *o == name)
            .copied()
            .unwrap_or(("", "int"));
        let _ = opt;
        args.push(name.into());
        let value: Option<OsString> = match kind {
            "flag" => None,
            "size" => Some(value(rng, &["16x9", "64x64", "8x8", "32x16"], SIZES).into()),
            "int" => Some(value(rng, &["1", "2", "8", "16"], INTS).into()),
            "float" => Some(value(rng, &["0", "0.25", "1", "8"], FLOATS).into()),
            "list" => Some(value(rng, &["1", "1,8", "0.25", "40000", "medium"], LISTS).into()),
            "out" => Some(output_path(rng, dir)),
            "in" => Some(input_path(rng, dir, files)),
            names => {
                let all: Vec<&str> = names.split('|').collect();
                Some(value(rng, &all[..all.len() - 1], &all).into())
            }
        };
        if let Some(v) = value {
            args.push(v);
        }
    }
    if rng.random_bool(0.05) {
        // Stray tokens.
        let at = rng.random_range(1..=args.len());
        args.insert(
            at,
            pick(rng, &["--", "-x", "--size=", "--out=", "-", "--help"]).into(),
        );
    }
    args
}

/// Parses `args` as the `solari` binary would, runs the up-front checks and, when they pass,
/// loads the scene the command names (with the importer's default limits, as the tool does).
pub fn cli(args: &[OsString]) -> Outcome {
    let parsed = match <Cli as clap::Parser>::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => return Outcome::Refused(format!("arguments: {}", e.kind())),
    };
    if let Err(e) = parsed.check() {
        return Outcome::Refused(e);
    }
    let scene_args = match &parsed.command {
        Command::Render(a) => Some(&a.scene),
        Command::Info(a) => Some(&a.scene),
        Command::BenchRays(a) => Some(&a.scene),
        Command::BenchDi(a) => Some(&a.scene),
        Command::BenchCache(a) => Some(&a.scene),
        Command::BenchDenoise(a) => Some(&a.scene),
        Command::Soak(a) => Some(&a.scene),
        Command::View(a) => Some(&a.scene),
        Command::Compare(a) => {
            for p in [&a.test, &a.reference] {
                if let Err(e) = solari_reference::image_io::read_linear(p) {
                    return Outcome::Refused(e);
                }
            }
            None
        }
    };
    if let Some(s) = scene_args
        && s.scene.is_some()
    {
        match s.load() {
            Ok((name, scene)) => {
                let _ = s.pick_camera(&name, &scene);
                exercise(&scene, s.camera.as_deref());
            }
            Err(e) if e.contains("the glTF reader failed") => return Outcome::Panic(e),
            Err(e) => return Outcome::Refused(e),
        }
    }
    Outcome::Ok
}
