//! Command-line knobs reach the renderer's settings (parsed in-process, no GPU).

use clap::Parser;
use solari_app::cli::{Cli, Command};
use solari_renderer::{
    Antialias, DI_REUSE_LIGHT_THRESHOLD, FrameView, GiMode, PATH_GI_SHADE_APART_TRIANGLES,
    RealtimeSettings,
};

fn settings(args: &[&str]) -> RealtimeSettings {
    let argv = [&["solari", "render", "--mode", "realtime"], args].concat();
    let cli = Cli::try_parse_from(argv).expect("parses");
    let Command::Render(r) = cli.command else {
        panic!("render");
    };
    r.realtime.settings(FrameView::Lit).expect("valid settings")
}

/// Why `solari render --mode realtime ARGS` (parsed) has no valid settings.
fn settings_error(args: &[&str]) -> String {
    let argv = [&["solari", "render", "--mode", "realtime"], args].concat();
    let cli = Cli::try_parse_from(argv).expect("parses");
    let Command::Render(r) = cli.command else {
        panic!("render");
    };
    r.realtime
        .settings(FrameView::Lit)
        .expect_err("settings refused")
}

/// `solari render ARGS`'s scene options, or clap's error.
fn scene_args(args: &[&str]) -> Result<solari_app::cli::SceneArgs, clap::Error> {
    let argv = [&["solari", "render"], args].concat();
    Cli::try_parse_from(argv).map(|cli| match cli.command {
        Command::Render(r) => r.scene,
        _ => panic!("render"),
    })
}

fn di(args: &[&str]) -> (bool, bool, u32) {
    let s = settings(args);
    (s.di.temporal, s.di.spatial, s.di.reuse_light_threshold)
}

#[test]
fn gi_defaults_are_the_measured_choice_and_match_the_library() {
    let s = settings(&[]);
    assert_eq!((s.gi, s.specular_gi), (GiMode::Path, true));
    let lib = RealtimeSettings::default();
    assert_eq!((lib.gi, lib.specular_gi), (s.gi, s.specular_gi));
    assert_eq!(
        GiMode::default(),
        s.gi,
        "the enum's default is the settings' default"
    );
    for (arg, on) in [
        ("on", true),
        ("off", false),
        ("true", true),
        ("false", false),
    ] {
        assert_eq!(settings(&["--specular-gi", arg]).specular_gi, on, "{arg}");
    }
    assert!(
        settings(&["--specular-gi"]).specular_gi,
        "the bare flag still means on"
    );
    assert!(settings(&["--specular-gi", "--gi", "cache"]).specular_gi);
    assert_eq!(settings(&["--gi", "off"]).gi, GiMode::Off);
    let direct = RealtimeSettings::direct_only();
    assert_eq!((direct.gi, direct.specular_gi), (GiMode::Off, false));
}

#[test]
fn di_reuse_chooses_the_reuse_steps() {
    let few = DI_REUSE_LIGHT_THRESHOLD;
    assert!(few > 0);
    assert_eq!(
        di(&[]),
        (true, true, few),
        "default: both reuse steps, skipped on scenes of few lights"
    );
    assert_eq!(di(&["--di-reuse", "auto"]), (true, true, few));
    assert_eq!(
        RealtimeSettings::default().di.reuse_light_threshold,
        few,
        "the library's default is the command's"
    );
    assert_eq!(
        di(&["--di-reuse", "all"]),
        (true, true, 0),
        "all means always"
    );
    assert_eq!(di(&["--di-reuse", "temporal"]), (true, false, 0));
    assert_eq!(di(&["--di-reuse", "spatial"]), (false, true, 0));
    assert_eq!(di(&["--di-reuse", "none"]), (false, false, 0));
    assert!(
        Cli::try_parse_from(["solari", "render", "--di-reuse", "some"]).is_err(),
        "unknown reuse names are refused"
    );
}

#[test]
fn psr_and_gi_candidates_reach_the_settings() {
    let s = settings(&[]);
    assert!(s.psr, "primary surface replacement is on by default");
    assert_eq!(s.restir_gi.initial_samples, 1);
    assert!(!settings(&["--psr", "off"]).psr);
    assert!(settings(&["--psr"]).psr, "the bare flag means on");
    let four = settings(&["--gi-samples", "4"]);
    assert_eq!(
        four.gi_settings().initial_samples,
        4,
        "plain path GI keeps the candidates"
    );
    let err = settings_error(&["--gi-samples", "0"]);
    assert!(err.contains("initial_samples"), "{err}");
}

/// `--gi-spatial-visibility` reaches ReSTIR GI's settings (default: one ray, for the chosen
/// sample), and a bad name is refused with the choices named.
#[test]
fn gi_spatial_visibility_reaches_the_settings() {
    use solari_restir::SpatialVisibility;
    let vis = |args: &[&str]| settings(args).restir_gi.spatial_visibility;
    assert_eq!(vis(&[]), SpatialVisibility::Chosen);
    assert_eq!(vis(&[]), SpatialVisibility::default());
    for v in [
        SpatialVisibility::Both,
        SpatialVisibility::Chosen,
        SpatialVisibility::Neighbour,
    ] {
        assert_eq!(vis(&["--gi-spatial-visibility", v.name()]), v);
        assert_eq!(SpatialVisibility::parse(v.name()), Some(v));
    }
    let err = Cli::try_parse_from(["solari", "render", "--gi-spatial-visibility", "half"])
        .expect_err("unknown names are refused")
        .to_string();
    assert!(err.contains("both, chosen or neighbour"), "{err}");
    // Both samples of a two-ray merge are shaded unless switched off (the library's default).
    let both = |args: &[&str]| settings(args).restir_gi.shade_both_samples;
    assert!(both(&[]));
    assert_eq!(
        both(&[]),
        solari_restir::RestirGiSettings::default().shade_both_samples
    );
    assert!(!both(&["--gi-shade-both", "off"]));
    assert!(both(&["--gi-shade-both"]), "the bare flag means on");
    // The own reservoir's share, the library's default unless given; out of range refused.
    let share = |args: &[&str]| settings(args).restir_gi.own_sample_share;
    assert_eq!(
        share(&[]),
        solari_restir::RestirGiSettings::default().own_sample_share
    );
    assert_eq!(share(&["--gi-own-share", "0"]), 0.0);
    let err = settings_error(&["--gi-own-share", "2"]);
    assert!(err.contains("own_sample_share"), "{err}");
    // `--gi-reuse`: both steps unless one is named (the library's default is both).
    let reuse = |args: &[&str]| {
        let s = settings(args).restir_gi;
        (s.temporal, s.spatial)
    };
    let defaults = solari_restir::RestirGiSettings::default();
    assert_eq!(reuse(&[]), (defaults.temporal, defaults.spatial));
    assert_eq!(reuse(&[]), (true, true));
    assert_eq!(reuse(&["--gi-reuse", "all"]), (true, true));
    assert_eq!(reuse(&["--gi-reuse", "temporal"]), (true, false));
    assert_eq!(reuse(&["--gi-reuse", "spatial"]), (false, true));
    // The history is the spatial merge's unless switched off; the confidence cap is the
    // library's unless given, and one under 1 is refused by name.
    let history = |args: &[&str]| settings(args).restir_gi.spatial_history;
    assert_eq!(history(&[]), defaults.spatial_history);
    assert!(history(&[]));
    assert!(!history(&["--gi-spatial-history", "off"]));
    assert!(history(&["--gi-spatial-history"]), "the bare flag means on");
    let cap = |args: &[&str]| settings(args).restir_gi.confidence_cap;
    assert_eq!(cap(&[]), defaults.confidence_cap);
    assert_eq!(cap(&["--gi-confidence-cap", "4"]), 4.0);
    let err = settings_error(&["--gi-confidence-cap", "0.5"]);
    assert!(err.contains("confidence_cap"), "{err}");
}

/// `--denoise-kernel` reaches the fallback denoiser's settings (default: the 13-tap diamond,
/// the library's default), and a bad name is refused with the choices named.
#[test]
fn denoise_kernel_reaches_the_settings() {
    use solari_denoise::AtrousKernel;
    let kernel = |args: &[&str]| settings(args).denoise.atrous_kernel;
    assert_eq!(kernel(&[]), AtrousKernel::Diamond);
    assert_eq!(kernel(&[]), AtrousKernel::default());
    for k in [AtrousKernel::Diamond, AtrousKernel::Full] {
        assert_eq!(kernel(&["--denoise-kernel", k.name()]), k);
        assert_eq!(AtrousKernel::parse(k.name()), Some(k));
    }
    let err = Cli::try_parse_from(["solari", "render", "--denoise-kernel", "wide"])
        .expect_err("unknown names are refused")
        .to_string();
    assert!(err.contains("diamond or full"), "{err}");
}

/// `--brdf` reaches the scene's upload options, the library's default when absent, and a bad
/// name is refused with the choices named.
#[test]
fn brdf_model_reaches_the_scene_options() {
    use solari_scene::brdf::BrdfModel;
    let parse = |args: &[&str]| scene_args(args).map(|s| s.brdf);
    assert_eq!(parse(&[]).expect("parses"), BrdfModel::default());
    assert_eq!(BrdfModel::default(), BrdfModel::Layered);
    assert_eq!(
        parse(&["--brdf", "gltf-spec"]).expect("parses"),
        BrdfModel::GltfSpec
    );
    let err = parse(&["--brdf", "phong"])
        .expect_err("unknown model")
        .to_string();
    assert!(err.contains("layered or gltf-spec"), "{err}");
}

/// `--light-radius` gives point and spot lights a radius (0, delta lights, by default), and
/// refuses negative or non-finite lengths.
#[test]
fn light_radius_is_checked() {
    let parse = |args: &[&str]| scene_args(args).map(|s| s.light_radius);
    assert_eq!(parse(&[]).expect("parses"), 0.0);
    assert_eq!(parse(&["--light-radius", "0.05"]).expect("parses"), 0.05);
    for bad in ["-1", "nan", "inf", "ten"] {
        let err = parse(&["--light-radius", bad]).expect_err(bad).to_string();
        assert!(err.contains(bad), "{err}");
    }
}

#[test]
fn environment_options_are_checked_and_applied() {
    let parse = |args: &[&str]| scene_args(args).map(|s| s.environment_intensity);
    assert_eq!(parse(&[]).expect("parses"), None);
    assert_eq!(
        parse(&["--environment-intensity", "2.5"]).expect("parses"),
        Some(2.5)
    );
    for bad in ["-1", "nan", "inf", "1e12", "bright"] {
        let err = parse(&["--environment-intensity", bad])
            .expect_err(bad)
            .to_string();
        assert!(err.contains(bad), "{err}");
    }
    // No map: the built-in scene's uniform environment (black) becomes the intensity.
    let args = scene_args(&["--environment-intensity", "0.25"]).expect("parses");
    let (_, scene) = args.load().expect("loads");
    assert_eq!(scene.environment_radiance, glam::Vec3::splat(0.25));
    assert!(scene.environment_map.is_none());
    // A map: read, and scaled by the intensity.
    let dir = std::env::temp_dir().join(format!("solari-cli-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sky.exr");
    image::Rgb32FImage::from_pixel(8, 4, image::Rgb([1.0, 2.0, 3.0]))
        .save_with_format(&path, image::ImageFormat::OpenExr)
        .unwrap();
    let env = path.to_str().unwrap();
    let args = scene_args(&["--environment", env, "--environment-intensity", "2"]).unwrap();
    args.check().expect("the file exists");
    let (_, scene) = args.load().expect("loads");
    assert_eq!(
        scene.environment(glam::Vec3::X),
        glam::Vec3::new(2.0, 4.0, 6.0)
    );
    // A missing or corrupt map is an error that names the file.
    let missing = dir.join("missing.hdr");
    let args = scene_args(&["--environment", missing.to_str().unwrap()]).unwrap();
    assert!(args.check().unwrap_err().contains("missing.hdr"));
    let corrupt = dir.join("corrupt.exr");
    std::fs::write(&corrupt, b"not an exr").unwrap();
    let args = scene_args(&["--environment", corrupt.to_str().unwrap()]).unwrap();
    let err = args.load().unwrap_err();
    assert!(
        err.contains("corrupt.exr") && err.contains("environment map"),
        "{err}"
    );
}

#[test]
fn a_quality_tier_sets_its_knobs_over_the_flags() {
    use solari_renderer::QualityTier;
    for tier in QualityTier::ALL {
        let s = settings(&["--quality", tier.name()]);
        assert_eq!(QualityTier::of(&s), Some(tier), "{}", tier.name());
        // The tier wins over a flag it sets; flags it does not set stay.
        let s = settings(&[
            "--quality",
            tier.name(),
            "--candidates",
            "3",
            "--tiles",
            "4x64",
        ]);
        assert_eq!(QualityTier::of(&s), Some(tier));
        assert_eq!(s.tiles.sample_count(), 256);
    }
    // No tier: the flags' defaults are the ultra tier (antialiased).
    assert_eq!(QualityTier::of(&settings(&[])), Some(QualityTier::Ultra));
    let refused = solari_app::cli::Cli::try_parse_from([
        "solari",
        "render",
        "--mode",
        "realtime",
        "--quality",
        "max",
    ]);
    assert!(refused.is_err());
}

#[test]
fn the_light_change_frames_reach_the_cache_settings() {
    let library = RealtimeSettings::default().cache.light_change_frames;
    assert_eq!(settings(&[]).cache.light_change_frames, library);
    assert_eq!(
        settings(&["--cache-light-change-frames", "0"])
            .cache
            .light_change_frames,
        0
    );
    assert_eq!(
        settings(&["--cache-light-change-frames", "3"])
            .cache
            .light_change_frames,
        3
    );
}

#[test]
fn the_shade_apart_rule_reaches_the_renderer_settings() {
    let library = RealtimeSettings::default().path_gi_shade_apart_triangles;
    assert_eq!(library, PATH_GI_SHADE_APART_TRIANGLES);
    let threshold = |args: &[&str]| settings(args).path_gi_shade_apart_triangles;
    assert_eq!(threshold(&[]), library);
    assert_eq!(threshold(&["--gi-shade-apart", "auto"]), library);
    assert_eq!(threshold(&["--gi-shade-apart", "on"]), 0);
    assert_eq!(threshold(&["--gi-shade-apart", "off"]), u64::MAX);
    // As the renderer applies it: on in any scene, off in a large one.
    assert!(
        settings(&["--gi-shade-apart", "on"])
            .gi_settings_for(32)
            .shade_apart
    );
    assert!(
        !settings(&["--gi-shade-apart", "off"])
            .gi_settings_for(294_000)
            .shade_apart
    );
}

#[test]
fn the_warm_up_exponent_reaches_the_cache_settings() {
    let library = RealtimeSettings::default().cache.warm_up_exponent;
    assert_eq!(library, 2.0);
    let exponent = |args: &[&str]| settings(args).cache.warm_up_exponent;
    assert_eq!(exponent(&[]), library);
    assert_eq!(exponent(&["--cache-warm-up", "0"]), 0.0);
    assert_eq!(exponent(&["--cache-warm-up", "3.5"]), 3.5);
    // Out of range: refused before anything is built, the knob named.
    let err = settings_error(&["--cache-warm-up", "17"]);
    assert!(err.contains("warm_up_exponent"), "{err}");
}

#[test]
fn the_warm_up_rounds_reach_the_cache_settings() {
    let library = RealtimeSettings::default().cache;
    assert_eq!((library.warm_up_rounds, library.warm_up_frames), (4, 8));
    let rounds = |args: &[&str]| {
        let c = settings(args).cache;
        (c.warm_up_rounds, c.warm_up_frames)
    };
    assert_eq!(rounds(&[]), (4, 8));
    assert_eq!(rounds(&["--cache-warm-up-rounds", "1"]), (1, 8));
    assert_eq!(
        rounds(&[
            "--cache-warm-up-rounds",
            "2",
            "--cache-warm-up-frames",
            "30"
        ]),
        (2, 30)
    );
    // Out of range: refused before anything is built, the knob named.
    for bad in ["0", "17"] {
        let err = settings_error(&["--cache-warm-up-rounds", bad]);
        assert!(err.contains("warm_up_rounds"), "{bad}: {err}");
    }
}

/// `--antialias` defaults to auto, as the library does; the flag alone means on; a bad value
/// is refused by clap with the accepted ones named; and on with DLSS-RR is refused by name.
#[test]
fn antialias_reaches_the_settings() {
    assert_eq!(settings(&[]).antialias, Antialias::Auto);
    assert_eq!(RealtimeSettings::default().antialias, Antialias::Auto);
    assert_eq!(settings(&["--antialias"]).antialias, Antialias::On);
    for (arg, want) in [
        ("auto", Antialias::Auto),
        ("on", Antialias::On),
        ("off", Antialias::Off),
    ] {
        assert_eq!(settings(&["--antialias", arg]).antialias, want);
    }
    let argv = [
        "solari",
        "render",
        "--mode",
        "realtime",
        "--antialias",
        "2x",
    ];
    let e = Cli::try_parse_from(argv).expect_err("refused").to_string();
    assert!(e.contains("auto, on or off"), "{e}");
    let e = settings_error(&["--antialias", "on", "--denoiser", "dlss"]);
    assert!(e.contains("DLSS-RR"), "{e}");
    assert_eq!(
        settings(&["--denoiser", "dlss"]).antialias,
        Antialias::Auto,
        "auto stands aside for DLSS-RR"
    );
}

/// `--gi-half-rate-spatial` reaches ReSTIR GI's settings: on by default (as in the library),
/// `off` turns it off, and it acts only with `--gi-half-rate`.
#[test]
fn gi_half_rate_spatial_reaches_the_settings() {
    use solari_restir::RestirGiSettings;
    let get = |args: &[&str]| {
        let s = settings(args).restir_gi;
        (s.rate == solari_restir::GiRate::Half, s.half_rate_spatial)
    };
    assert_eq!(get(&[]), (false, true));
    assert!(RestirGiSettings::default().half_rate_spatial);
    assert_eq!(get(&["--gi", "restir", "--gi-half-rate"]), (true, true));
    assert_eq!(
        get(&[
            "--gi",
            "restir",
            "--gi-half-rate",
            "--gi-half-rate-spatial",
            "off"
        ]),
        (true, false)
    );
    assert_eq!(
        get(&["--gi-half-rate-spatial"]),
        (false, true),
        "the bare flag means on"
    );
    assert!(
        Cli::try_parse_from(["solari", "render", "--gi-half-rate-spatial", "maybe"]).is_err(),
        "not a yes or no"
    );
}

/// `--gi-quarter-rate` reaches ReSTIR GI's settings (a pixel traces one frame in four) and
/// refuses `--gi-half-rate` beside it, naming both, rather than picking one; so does
/// `--gi-trace-fresh`.
#[test]
fn gi_quarter_rate_reaches_the_settings() {
    let s = settings(&["--gi", "restir", "--gi-quarter-rate"]).restir_gi;
    assert_eq!(s.rate, solari_restir::GiRate::Quarter);
    assert_eq!(s.rate_shift(), 2);
    assert_eq!(
        settings(&["--gi", "restir", "--gi-half-rate"])
            .restir_gi
            .rate_shift(),
        1
    );
    assert_eq!(settings(&[]).restir_gi.rate_shift(), 0);
    // Pixels without history trace whatever their phase: on by default, `off` turns it off.
    assert!(settings(&[]).restir_gi.trace_fresh_pixels);
    let off = settings(&[
        "--gi",
        "restir",
        "--gi-quarter-rate",
        "--gi-trace-fresh",
        "off",
    ]);
    assert!(!off.restir_gi.trace_fresh_pixels);
    let e = Cli::try_parse_from(["solari", "render", "--gi-quarter-rate", "--gi-half-rate"])
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("--gi-quarter-rate") && e.contains("--gi-half-rate"),
        "{e}"
    );
}
