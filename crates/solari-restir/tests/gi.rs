//! ReSTIR GI on lavapipe, composed as the renderer does (G-buffer → light tiles → ReSTIR DI →
//! world cache upkeep → ReSTIR GI adding to DI's image; the DI frame is this crate's test
//! harness): against the full-bounce reference path tracer on the Cornell box, plain path GI
//! against reuse, the non-finite detector on every frame, and bad settings. Figures are
//! printed for the issue notes
//! (`cargo test --release -p solari-restir --test gi -- --nocapture`).

mod common;

use common::{
    DirectLight, di_settings, frame_mean, reference, rmse, tile_settings, total_light_bias,
};
use solari_restir::{
    GiRate, GlossyHits, RestirGi, RestirGiSettings, SpatialVisibility, gi_reservoir_check,
};
use solari_scene::finite_check::{FiniteChecker, RecordLayout, first_offender};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::{Scene, default_scene};
use solari_worldcache::{WorldCache, WorldCacheSettings};

/// Which indirect light the frame adds to DI.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// The cache at the pixel itself (cache-only GI).
    Cache,
    /// ReSTIR GI with the given settings.
    Gi(RestirGiSettings),
}

struct Setup {
    direct: DirectLight,
    cache: WorldCache,
    cache_target: wgpu::BindGroup,
    gi: RestirGi,
    gi_target: wgpu::BindGroup,
    mode: Mode,
    checker: FiniteChecker,
    frames: u64,
}

fn setup(gpu: &Gpu, scene: &Scene, size: u32, mode: Mode) -> Setup {
    setup_with_capacity(gpu, scene, size, mode, 1 << 14)
}

/// As [`setup`], with a world cache of `capacity` slots.
fn setup_with_capacity(gpu: &Gpu, scene: &Scene, size: u32, mode: Mode, capacity: u32) -> Setup {
    let backend = gpu.backend(Default::default()).expect("backend");
    let direct = DirectLight::new(gpu, backend, scene, size, di_settings(), tile_settings());
    let variant = TraceVariant::for_scene(&direct.gpu_scene);
    let settings = WorldCacheSettings {
        capacity,
        ..Default::default()
    };
    let cache = WorldCache::new(gpu, backend, variant, settings, tile_settings()).expect("cache");
    let gi_settings = match mode {
        Mode::Gi(s) => s,
        Mode::Cache => RestirGiSettings::default(),
    };
    let gi = RestirGi::new(
        gpu,
        backend,
        variant,
        size,
        size,
        gi_settings,
        &cache,
        tile_settings(),
    )
    .expect("GI");
    Setup {
        cache_target: cache.target_group(gpu, direct.di.output()),
        gi_target: gi
            .target_group(gpu, direct.di.output(), &direct.tiles, &direct.lights)
            .expect("GI's target group"),
        direct,
        cache,
        gi,
        mode,
        checker: FiniteChecker::new(gpu, &["gi_reservoirs", "image"]).expect("detector"),
        frames: 0,
    }
}

/// As [`setup`] with `settings`, the initial pass's reservoirs in a scratch buffer of their
/// own, returned: after a frame it holds the temporal merge's output, before spatial reuse
/// ([`initial_reservoirs`]).
fn setup_reading_initial(
    gpu: &Gpu,
    scene: &Scene,
    size: u32,
    settings: RestirGiSettings,
) -> (Setup, wgpu::Buffer) {
    let mut s = setup(gpu, scene, size, Mode::Gi(settings));
    let scratch = solari_scene::scratch::allocate(gpu, s.gi.scratch_bytes()).unwrap();
    s.gi.use_scratch(gpu, &scratch, &s.cache).expect("scratch");
    (s, scratch)
}

/// The reservoirs in a [`setup_reading_initial`] scratch buffer, one per pixel.
fn initial_reservoirs(
    gpu: &Gpu,
    s: &Setup,
    scratch: &wgpu::Buffer,
) -> Vec<solari_restir::GpuGiReservoir> {
    reservoirs_in(gpu, s, scratch)
}

/// The per-pixel reservoirs `buffer` holds (the scratch's or [`RestirGi::reservoirs`]).
fn reservoirs_in(
    gpu: &Gpu,
    s: &Setup,
    buffer: &wgpu::Buffer,
) -> Vec<solari_restir::GpuGiReservoir> {
    gpu.read_buffer(buffer, s.gi.scratch_bytes())
        .unwrap()
        .chunks_exact(size_of::<solari_restir::GpuGiReservoir>())
        .map(bytemuck::pod_read_unaligned)
        .collect()
}

impl Setup {
    /// One frame of the scene's camera; panics if the GI reservoirs or the image hold a NaN,
    /// an infinity, a negative value or an over-confident reservoir.
    fn frame(&mut self, gpu: &Gpu, scene: &Scene) {
        self.frame_jittered(gpu, scene, [0.0; 2]);
    }

    /// As [`Setup::frame`], the G-buffer's samples `jitter` pixels off the pixel centres.
    fn frame_jittered(&mut self, gpu: &Gpu, scene: &Scene, jitter: [f32; 2]) {
        let camera = scene.camera(None).unwrap();
        self.frame_from(gpu, scene, &camera, jitter);
    }

    /// As [`Setup::frame_jittered`], seen from `camera`.
    fn frame_from(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        camera: &solari_scene::Camera,
        jitter: [f32; 2],
    ) {
        self.direct.prepare_jittered(gpu, scene, camera, jitter);
        let context = *self.direct.context();
        self.cache
            .prepare(gpu, &context, self.direct.lights.light_count);
        self.gi
            .prepare(gpu, &context, &self.direct.gbuffer)
            .expect("GI prepares");
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.checker.begin_frame(&mut encoder);
        self.direct.encode_inputs(&mut encoder);
        self.direct.encode_di(&mut encoder);
        let d = &self.direct;
        self.cache
            .encode(&mut encoder, &context, &d.gpu_scene, &d.lights_group)
            .expect("cache upkeep");
        match self.mode {
            Mode::Cache => {
                self.cache
                    .encode_gi(&mut encoder, &context, &d.gbuffer, &self.cache_target)
                    .expect("cache GI");
            }
            Mode::Gi(_) => {
                let ran = self
                    .gi
                    .encode(
                        &mut encoder,
                        &context,
                        &d.gpu_scene,
                        &d.gbuffer,
                        &self.gi_target,
                    )
                    .expect("GI");
                assert!(ran.contains("gi_initial_temporal"));
                // Plain path GI shades in its first pass and skips the second.
                assert_eq!(ran.contains("gi_spatial_shade"), self.gi.built_for_reuse());
            }
        }
        let (w, h) = d.di.size();
        let pixels = w as u64 * h as u64;
        let cap = self.gi.settings().confidence_cap;
        let c = &mut self.checker;
        c.check_buffer(
            gpu,
            &mut encoder,
            0,
            self.gi.reservoirs(),
            pixels,
            gi_reservoir_check(cap),
        )
        .expect("check reservoirs");
        c.check_buffer(
            gpu,
            &mut encoder,
            1,
            d.di.output(),
            pixels,
            RecordLayout::RGBA_NON_NEGATIVE,
        )
        .expect("check image");
        c.end_frame(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let counts = self.checker.read(gpu).expect("detector");
        if let Some(bad) = first_offender(&counts) {
            panic!("frame {}: {bad:?}", self.frames);
        }
        self.frames += 1;
    }

    /// The mean image over `frames` frames after `warmup`, and the last frame alone.
    fn mean(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        warmup: u32,
        frames: u32,
    ) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        self.mean_jittered(gpu, scene, warmup, frames, |_| [0.0; 2])
    }

    /// As [`Setup::mean`], frame `i`'s G-buffer samples `jitter(i)` pixels off the pixel
    /// centres (`i` counted from the setup's first frame).
    fn mean_jittered(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        warmup: u32,
        frames: u32,
        jitter: impl Fn(u32) -> [f32; 2],
    ) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        for _ in 0..warmup {
            self.frame_jittered(gpu, scene, jitter(self.frames as u32));
        }
        frame_mean(frames, || {
            self.frame_jittered(gpu, scene, jitter(self.frames as u32));
            self.direct.read_output(gpu)
        })
    }
}

#[test]
fn gi_is_unbiased_against_the_full_reference_and_reuse_lowers_noise() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let scene = default_scene::cornell_box();
    let backend = gpu.backend(Default::default()).unwrap();
    let truth = reference(&gpu, backend, &scene, size, 512, u32::MAX);
    let mut results = Vec::new();
    let modes = [
        ("cache", Mode::Cache),
        ("plain", Mode::Gi(RestirGiSettings::plain())),
        (
            "restir, two spatial rays",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_visibility: SpatialVisibility::Both,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "restir, biased spatial",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_visibility: SpatialVisibility::Neighbour,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "restir, permuted",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                permutation_sampling: true,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "plain, 4 candidates",
            Mode::Gi(RestirGiSettings {
                initial_samples: 4,
                ..RestirGiSettings::plain()
            }),
        ),
        (
            "restir, chosen sample's ray",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_visibility: SpatialVisibility::Chosen,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "plain, half rate",
            Mode::Gi(RestirGiSettings {
                rate: GiRate::Half,
                ..RestirGiSettings::plain()
            }),
        ),
        (
            "restir, half rate, spatial at every pixel",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                rate: GiRate::Half,
                half_rate_spatial: false,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "restir, half rate, spatial at half rate",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                rate: GiRate::Half,
                half_rate_spatial: true,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "plain, quarter rate",
            Mode::Gi(RestirGiSettings {
                rate: GiRate::Quarter,
                ..RestirGiSettings::plain()
            }),
        ),
        (
            "restir, quarter rate, spatial at a quarter",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                rate: GiRate::Quarter,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "restir, defaults (adaptive cap)",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                ..Default::default()
            }),
        ),
        (
            "restir, own history",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_history: false,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
        (
            "restir, temporal reuse only",
            Mode::Gi(RestirGiSettings {
                spatial: false,
                adaptive_cap: false,
                ..Default::default()
            }),
        ),
    ];
    for (name, mode) in modes {
        let mut s = setup(&gpu, &scene, size, mode);
        let (mean, last) = s.mean(&gpu, &scene, 100, 256);
        let (e_mean, e_last) = (rmse(&mean, &truth), rmse(&last, &truth));
        let bias = total_light_bias(&mean, &truth);
        eprintln!(
            "cornell {size}x{size} {name}: RMSE vs full reference, one frame {e_last:.4}, \
             mean of 256 frames {e_mean:.4}; total light {:+.2}%",
            bias * 100.0
        );
        results.push((name, e_last, e_mean, bias));
    }
    // Measured (lavapipe, 100 + 256 frames, five runs; cache updates race, so runs differ):
    // total light cache -0.5 to -0.6%, plain -0.15 to +0.05%, ReSTIR -0.33 to +0.02%; without
    // the spatial pass's second visibility ray -0.74%; with temporal permutation -0.9 to -1.0%.
    // One-frame RMSE plain 0.044, ReSTIR 0.023. Since emissive hits' reflected light counts
    // (the light's own albedo), one run: plain +0.07%, ReSTIR +0.11%.
    // (The figures below predate `shade_both_samples` and `own_sample_share`, 2026-11-29,
    // which lower one frame's error: see the last assertion's note.)
    // The default one spatial ray (`SpatialVisibility::Chosen`), four runs: total light
    // -0.28 to -0.17%, one-frame RMSE 0.0233-0.0249, 256-frame mean 0.0054-0.0056 (two rays,
    // three runs: -0.26 to -0.22%, 0.0235-0.0250, 0.0053-0.0054). Where it chooses the
    // neighbour's sample and finds it hidden, the pixel keeps an empty reservoir that its
    // next frames inherit, so its frames are more alike and their mean converges a little
    // more slowly.
    // Half rate (each pixel traced every other frame at twice the weight): unbiased, with
    // twice the variance per traced frame, so its 256-frame mean is noisier than plain's.
    // ReSTIR GI at half rate, two runs (2026-11-27): total light -0.10% and -0.06%, one-frame
    // RMSE 0.0249 and 0.0246, 256-frame mean 0.0057 and 0.0056 (every pixel: -0.26%/-0.20%,
    // 0.0230/0.0240, 0.0054/0.0056): reuse carries each traced sample into the other frame.
    // Spatial reuse at half rate as well (2026-11-28, one run): total light +0.05%, one-frame
    // RMSE 0.0232, 256-frame mean 0.0058 (spatial reuse at every pixel, the same run: -0.01%,
    // 0.0218, 0.0058). Reusing from neighbours of both checkerboard phases read +2.78%: the
    // total-light check fails it.
    // A quarter of the pixels (each traced one frame in four at four times the weight),
    // 2026-11-29, two runs: plain -0.31% and -0.34%, one frame 0.1185 and 0.1208, 256-frame
    // mean 0.0073 (1.49x cache GI's).
    // ReSTIR GI with spatial reuse at phase 1 (the frame after a pixel traced), three runs:
    // total light -0.32% twice and -0.41% (cache GI -0.39% in that run), one frame
    // 0.0258-0.0265, mean 0.0064-0.0066;
    // reusing at phase 2 read -0.41% to -0.52% in four runs, at phase 3 -0.33% and -0.36%,
    // at every pixel -0.19% to -0.32% (`restir_gi_spatial.wesl`).
    // The modes above test the estimator, so their caps are fixed: the adaptive cap (on by
    // default) makes a history's weight depend on the sample it holds, which is not
    // unbiased. With it (2026-11-27, one run): total light +0.16% with the chosen sample's
    // ray and +0.42% at half rate (fixed cap, earlier runs: -0.28% to -0.06%); it is bounded
    // at 1% below, as measured, not as proven.
    // The 256-frame means' RMSE against cache GI's, over the runs logged (2026-11-26/27, six
    // local, one CI): cache 0.0047-0.0049; ReSTIR with two spatial rays 0.0050-0.0055 (CI:
    // 0.00548 against 0.00471, a ratio of 1.16). Reuse correlates a pixel's frames, so its
    // mean keeps more of the estimator's variance than cache GI's nearly noise-free frames do;
    // plain path GI read 0.0051 (1.04-1.08 of cache GI's, 1.08 against CI's cache figure) and
    // the one-ray default 0.0051-0.0056 (up to 1.19 against CI's). Each bound leaves CI's
    // spread room: plain 1.25, both ReSTIR variants 1.35 (the biased spatial mode reads
    // 0.0052-0.0059 here too; bias is the total-light check's to catch, not this one's).
    // The pixel's own reservoir as history (`spatial_history` off), 2026-11-29, one run: total
    // light -0.11% (cache -0.32%), one-frame RMSE 0.0184 (the adaptive-cap defaults 0.0201),
    // 256-frame mean 0.0057 (1.19 of cache GI's 0.0048; its frames are more alike).
    // Temporal reuse only (`spatial` off, `--gi-reuse temporal`), 2026-12-07, one run: total
    // light -0.11% (cache -0.43%), one frame 0.0207, 256-frame mean 0.0063 (1.31 of cache
    // GI's: a pixel's chain alone carries its samples, so its frames are alike); bound 1.6
    // for CI's spread.
    let (cache, plain, restir, plain4, chosen, half, restir_half, half_spatial) = (
        results[0], results[1], results[2], results[5], results[6], results[7], results[8],
        results[9],
    );
    let (quarter, restir_quarter, adaptive, own_history, temporal_only) = (
        results[10],
        results[11],
        results[12],
        results[13],
        results[14],
    );
    assert!(
        adaptive.3.abs() < 0.01,
        "{}: total light off by {:+.2}%",
        adaptive.0,
        adaptive.3 * 100.0
    );
    // (mode, bound on the 256-frame mean's RMSE as a multiple of cache GI's, bound on its
    // total light's distance from the reference's). A quarter of the pixels gets 0.65%: its
    // mean is the noisiest (one traced frame in four), and it read -0.31% to -0.41% in runs
    // where cache-only GI, every mode's expectation, read -0.32% to -0.39%.
    for (gi, mean_bound, light_bound) in [
        (plain, 1.25, 0.005),
        (restir, 1.35, 0.005),
        (plain4, 1.25, 0.005),
        (chosen, 1.35, 0.005),
        (half, 1.5, 0.005),
        (restir_half, 1.5, 0.005),
        (half_spatial, 1.5, 0.005),
        (quarter, 1.75, 0.0065),
        (restir_quarter, 1.75, 0.0065),
        (own_history, 1.35, 0.005),
        (temporal_only, 1.6, 0.005),
    ] {
        // All estimate the cache-terminated bounce without bias.
        assert!(
            gi.3.abs() < light_bound,
            "{}: total light off by {:+.2}%",
            gi.0,
            gi.3 * 100.0
        );
        // And their means are about as close to the full reference as cache GI's (the
        // remaining error is mostly the reference's own noise at 512 paths).
        assert!(
            gi.2 < mean_bound * cache.2,
            "{}: 256-frame mean RMSE {} against cache GI's {}",
            gi.0,
            gi.2,
            cache.2
        );
    }
    // Reuse is what ReSTIR is for: a single frame is less noisy than plain sampling, with
    // either unbiased choice of spatial rays.
    for gi in [
        restir,
        chosen,
        restir_half,
        half_spatial,
        restir_quarter,
        adaptive,
        own_history,
        temporal_only,
    ] {
        assert!(
            gi.1 < 0.7 * plain.1,
            "one frame: {} {} vs plain {}",
            gi.0,
            gi.1,
            plain.1
        );
    }
    // Four candidates, averaged: less noise than one, still unbiased (above). (One run,
    // 2026-11-29: one-frame RMSE 0.0240 against 0.0447; two spatial rays with both samples
    // shaded, `shade_both_samples`, 0.0192 against the one-ray default's 0.0233-0.0249.)
    assert!(
        plain4.1 < 0.8 * plain.1,
        "one frame: plain GI with 4 candidates {} vs 1 {}",
        plain4.1,
        plain.1
    );
}

/// furnace_sphere (`solari-testdata`, README there): a white Lambertian sphere (albedo 0.8,
/// r = 1.5) inside an emitting Lambertian enclosure (E = 1, albedo 0.5, R = 5). Closed form
/// with every bounce: walls 1.96464, sphere 1.57171 (tessellation ~0.1%). Plain path GI and
/// ReSTIR GI trace one bounce and end in the world cache, whose furnace irradiance
/// converges within 2% (`solari-worldcache`'s furnace test): the mean over frames must
/// land within 1.5% of the closed form, and the bias left is printed. Measured (lavapipe,
/// 32², 400 + 256 frames; the test runs 300 + 128): plain sphere −0.22%, walls −0.46%; ReSTIR −0.18%, −0.46%.
/// The test itself, 2026-11-26: plain −0.65%, −0.49%; ReSTIR with two spatial rays −0.39%,
/// −0.51%; with the default one ray −0.37%, −0.53%. 2026-11-27, three runs, ReSTIR GI at half
/// rate: sphere −0.76% to −0.84%, walls −0.47% to −0.48% (every pixel, the same runs: sphere
/// −0.39% to −0.44%, walls −0.50% to −0.52%; the sphere's 0.4% is not explained). With the
/// adaptive cap (`RestirGiSettings::adaptive_cap`, on in these modes), one run: the chosen
/// sample's ray sphere −0.41%, walls −0.26%; half rate −0.58%, −0.27%. 2026-11-28, half
/// rate with spatial reuse at half rate (now the default with half rate): sphere −0.52%, walls
/// −0.43%; with neighbours of both checkerboard phases the sphere read +8.3%. Before
/// emissive hits' reflected light counted, the sphere read 0.80 (−49%).
#[test]
fn gi_converges_to_the_sphere_furnace_closed_form() {
    let Some(gpu) = test_gpu() else { return };
    let size = 32;
    let scene = solari_scene::load_gltf(solari_testdata::scene("furnace_sphere")).expect("scene");
    // The inner sphere subtends asin(1.5 / 4.5) = 19.47° about the view axis; the camera's
    // half field is 30°. Pixels by the tangent of their angle off the axis, clear of the rim.
    let rim = (1.5f32 / 4.5).asin().tan();
    let half = 30f32.to_radians().tan();
    let tangent = |i: usize| {
        let (x, y) = ((i as u32 % size) as f32, (i as u32 / size) as f32);
        let ndc = |p: f32| (p + 0.5) / size as f32 * 2.0 - 1.0;
        half * (ndc(x).powi(2) + ndc(y).powi(2)).sqrt()
    };
    let modes = [
        ("plain", Mode::Gi(RestirGiSettings::plain())),
        (
            "plain, half rate",
            Mode::Gi(RestirGiSettings {
                rate: GiRate::Half,
                ..RestirGiSettings::plain()
            }),
        ),
        (
            "restir, two spatial rays",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_visibility: SpatialVisibility::Both,
                ..Default::default()
            }),
        ),
        (
            "restir, chosen sample's ray",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                spatial_visibility: SpatialVisibility::Chosen,
                ..Default::default()
            }),
        ),
        (
            "restir, half rate (spatial reuse at half rate, the default with it)",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                rate: GiRate::Half,
                ..Default::default()
            }),
        ),
        (
            "restir, quarter rate",
            Mode::Gi(RestirGiSettings {
                spatial_radius: 3.0,
                rate: GiRate::Quarter,
                ..Default::default()
            }),
        ),
    ];
    for (name, mode) in modes {
        let mut s = setup_with_capacity(&gpu, &scene, size, mode, 1 << 17);
        // The cache settles in about 300 frames here (solari-worldcache's furnace test).
        let (mean, _) = s.mean(&gpu, &scene, 300, 128);
        for (region, pick, expected) in [
            (
                "sphere",
                (|t: f32, rim: f32| t < 0.9 * rim) as fn(f32, f32) -> bool,
                1.57171,
            ),
            ("walls", |t, rim| t > 1.1 * rim, 1.96464),
        ] {
            let values: Vec<f64> = (0..mean.len())
                .filter(|&i| pick(tangent(i), rim))
                .map(|i| mean[i].iter().map(|&c| c as f64).sum::<f64>() / 3.0)
                .collect();
            let n = values.len() as f64;
            let m = values.iter().sum::<f64>() / n;
            let sd = (values.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n).sqrt();
            eprintln!(
                "furnace_sphere {size}x{size} {name} {region}: mean of 128 frames {m:.4} \
                 (closed form {expected}, {:+.2}%), pixel spread {sd:.4} over {n} pixels",
                (m / expected - 1.0) * 100.0
            );
            assert!(n > 100.0, "{name} {region}: only {n} pixels");
            assert!(
                (m / expected - 1.0).abs() < 0.015,
                "{name} {region}: mean {m}, closed form {expected}"
            );
        }
    }
}

#[test]
fn bad_gi_settings_are_refused_with_the_knob_named() {
    let cases = [
        RestirGiSettings {
            jacobian_bound: f32::NAN,
            ..Default::default()
        },
        RestirGiSettings {
            jacobian_bound: 0.5,
            ..Default::default()
        },
        RestirGiSettings {
            confidence_cap: 0.0,
            ..Default::default()
        },
        RestirGiSettings {
            spatial_tries: 17,
            ..Default::default()
        },
        RestirGiSettings {
            max_ray_distance: -1.0,
            ..Default::default()
        },
        RestirGiSettings {
            spatial_radius: f32::INFINITY,
            ..Default::default()
        },
    ];
    for s in cases {
        let e = s.validate().expect_err("refused").to_string();
        assert!(e.contains("ReSTIR GI settings"), "{e}");
    }
    // A share of the pixel's own estimate outside 0..1 (or NaN) is named.
    for own_sample_share in [f32::NAN, -0.1, 1.5, f32::INFINITY] {
        let s = RestirGiSettings {
            own_sample_share,
            ..Default::default()
        };
        let e = s.validate().expect_err("refused").to_string();
        assert!(e.contains("own_sample_share"), "{e}");
    }
    // So is a glossy-hit roughness outside (0, 1].
    for glossy_hit_roughness in [f32::NAN, 0.0, -0.5, 1.5, f32::INFINITY] {
        let s = RestirGiSettings {
            glossy_hit_roughness,
            glossy_hits: GlossyHits::Lights,
            ..Default::default()
        };
        let e = s.validate().expect_err("refused").to_string();
        assert!(e.contains("glossy_hit_roughness"), "{e}");
    }
    for own_sample_share in [0.0, 0.5, 1.0] {
        let s = RestirGiSettings {
            own_sample_share,
            ..Default::default()
        };
        s.validate().unwrap();
    }
    RestirGiSettings::default().validate().unwrap();
    RestirGiSettings::plain().validate().unwrap();
    // Half or quarter rate, with reuse or without, and with spatial reuse at that rate.
    for s in [RestirGiSettings::plain(), RestirGiSettings::default()] {
        for half_rate_spatial in [false, true] {
            for rate in [GiRate::Half, GiRate::Quarter] {
                RestirGiSettings {
                    rate,
                    half_rate_spatial,
                    ..s
                }
                .validate()
                .unwrap();
            }
        }
    }
}

/// Both passes are built specialised for their settings: the initial pass without the
/// resampling loop unless `initial_samples` is above 1, the spatial pass for the default
/// `SpatialVisibility::Chosen` (the merge settled before its one ray) or in general form for
/// the other two, and for spatial reuse at half rate only with half rate and
/// `half_rate_spatial`. A settings change across any of these lines builds that pass again at
/// the next frame (encode refuses until `prepare` has), and frames before and after render
/// (finite and non-negative: `Setup::frame` checks the reservoirs and the image). Each form's
/// results are checked by the convergence tests
/// above (4 candidates built from the start: less noise than 1, so the loop is there); on
/// lavapipe with one thread (`LP_NUM_THREADS=1`, which makes the world cache deterministic)
/// the specialised passes gave the general ones' images bit for bit (`benches/RESULTS.md`,
/// "GI's initial pass without its resampling loop").
#[test]
fn the_passes_are_built_for_their_settings() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let with = |v, n| RestirGiSettings {
        spatial_visibility: v,
        initial_samples: n,
        ..Default::default()
    };
    let mut s = setup(&gpu, &scene, 32, Mode::Gi(with(SpatialVisibility::Both, 1)));
    assert!(!s.gi.spatial_chosen_only());
    assert!(!s.gi.initial_multi_candidate());
    s.frame(&gpu, &scene);
    for (v, n) in [
        (SpatialVisibility::Chosen, 1),
        (SpatialVisibility::Neighbour, 4),
        (SpatialVisibility::Chosen, 4),
        (SpatialVisibility::Both, 1),
    ] {
        let (chosen, multi) = (s.gi.spatial_chosen_only(), s.gi.initial_multi_candidate());
        s.gi.set_settings(with(v, n)).expect("valid settings");
        assert_eq!(
            (s.gi.spatial_chosen_only(), s.gi.initial_multi_candidate()),
            (chosen, multi),
            "{v:?}, {n}: built at the next frame"
        );
        // Until `prepare` rebuilds, the passes do not fit the settings: encode refuses.
        if (chosen, multi) != (v == SpatialVisibility::Chosen, n > 1) {
            assert_stale_pipelines_refused(&gpu, &mut s);
        }
        s.frame(&gpu, &scene);
        assert_eq!(
            s.gi.spatial_chosen_only(),
            v == SpatialVisibility::Chosen,
            "{v:?}"
        );
        assert_eq!(s.gi.initial_multi_candidate(), n > 1, "{n} candidates");
    }
    let mut plain = setup(&gpu, &scene, 32, Mode::Gi(RestirGiSettings::plain()));
    assert!(
        !plain.gi.spatial_chosen_only(),
        "no spatial pass without reuse"
    );
    assert!(!plain.gi.initial_multi_candidate());
    let four = RestirGiSettings {
        initial_samples: 4,
        ..RestirGiSettings::plain()
    };
    plain.gi.set_settings(four).expect("valid settings");
    plain.mode = Mode::Gi(four);
    plain.frame(&gpu, &scene);
    assert!(plain.gi.initial_multi_candidate());
    // The glossy-hit lighting is built into the initial pass: each change rebuilds it.
    assert_eq!(plain.gi.glossy_hits(), GlossyHits::Cache);
    for glossy_hits in [GlossyHits::Lights, GlossyHits::Path, GlossyHits::Cache] {
        let settings = RestirGiSettings {
            glossy_hits,
            ..four
        };
        plain.gi.set_settings(settings).expect("valid settings");
        plain.mode = Mode::Gi(settings);
        assert_stale_pipelines_refused(&gpu, &mut plain);
        plain.frame(&gpu, &scene);
        assert_eq!(plain.gi.glossy_hits(), glossy_hits);
    }
    // Tiles built with other settings than GI's (sample count, light kinds) are refused.
    let other = solari_lights::LightTiles::new(
        &gpu,
        solari_lights::LightTileSettings {
            tiles: 4,
            ..tile_settings()
        },
    )
    .expect("tiles");
    let d = &plain.direct;
    let e = plain
        .gi
        .target_group(&gpu, d.di.output(), &other, &d.lights)
        .expect_err("other tiles refused")
        .to_string();
    assert!(e.contains("light tiles"), "{e}");
    let mut default = setup(&gpu, &scene, 32, Mode::Gi(RestirGiSettings::default()));
    assert!(default.gi.spatial_chosen_only());
    assert!(!default.gi.initial_multi_candidate());
    // Spatial reuse at a reduced rate: on by default, built only with half or quarter rate.
    assert!(!default.gi.spatial_half_rate());
    default.frame(&gpu, &scene);
    for (rate, half_rate_spatial) in [
        (GiRate::Half, true),
        (GiRate::Half, false),
        (GiRate::Full, true),
        (GiRate::Quarter, true),
        (GiRate::Half, true),
        (GiRate::Quarter, false),
    ] {
        let before = default.gi.spatial_half_rate();
        let settings = RestirGiSettings {
            rate,
            half_rate_spatial,
            ..Default::default()
        };
        let wanted = rate.reduced() && half_rate_spatial;
        default.gi.set_settings(settings).expect("valid settings");
        default.mode = Mode::Gi(settings);
        if before != wanted {
            assert_stale_pipelines_refused(&gpu, &mut default);
        }
        default.frame(&gpu, &scene);
        assert_eq!(
            default.gi.spatial_half_rate(),
            wanted,
            "rate {rate:?}, reduced-rate spatial {half_rate_spatial}"
        );
    }
}

/// Encoding after a settings change that needs other pipelines, before `prepare` has built
/// them, is refused with the way out named.
fn assert_stale_pipelines_refused(gpu: &Gpu, s: &mut Setup) {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let d = &s.direct;
    let e =
        s.gi.encode(
            &mut encoder,
            d.context(),
            &d.gpu_scene,
            &d.gbuffer,
            &s.gi_target,
        )
        .expect_err("stale pipelines refused");
    assert!(e.to_string().contains("RestirGi::prepare"), "{e}");
}

/// Plain path GI keeps one reservoir buffer (the shade stores each pixel's reservoir back
/// where its initial pass put it), and holds 32 bytes per pixel less than a `RestirGi` built
/// with reuse and switched to plain, which writes a separate history. Their runs must match
/// (`assert_runs_match`). Turning reuse on is refused, with the way out named.
#[test]
fn plain_path_gi_on_one_buffer_matches_two_buffers() {
    use solari_restir::gi_reservoir::GpuGiReservoir;
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 32;
    let plain = RestirGiSettings::plain();
    let mut one = setup(&gpu, &scene, size, Mode::Gi(plain));
    let mut two = setup(&gpu, &scene, size, Mode::Gi(RestirGiSettings::default()));
    two.gi
        .set_settings(plain)
        .expect("reuse off is always allowed");
    two.mode = Mode::Gi(plain);
    let record = size_of::<GpuGiReservoir>() as u64;
    let bytes = (size * size) as u64 * record;
    assert_eq!(
        two.gi.memory_bytes() - one.gi.memory_bytes(),
        bytes - record,
        "one reservoir buffer (and a one-reservoir placeholder) instead of two"
    );
    assert_runs_match(&gpu, &scene, size, &mut one, &mut two);
    let e = one
        .gi
        .set_settings(RestirGiSettings::default())
        .expect_err("reuse needs a history buffer")
        .to_string();
    assert!(e.contains("built without reuse"), "{e}");
    assert_eq!(one.gi.settings(), plain, "a refused change changes nothing");
}

/// Plain path GI shaded in a second dispatch (`RestirGiSettings::shade_apart`) traces the
/// same samples and adds the same light as shaded in the pass that traces them
/// (`assert_runs_match`), whether built so or switched to it, which builds the pass again at
/// the next frame (encode refuses until `prepare` has) and back.
#[test]
fn plain_path_gi_shaded_apart_matches_shaded_where_traced() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 32;
    let plain = RestirGiSettings::plain();
    let apart = RestirGiSettings {
        shade_apart: true,
        ..plain
    };
    let mut one = setup(&gpu, &scene, size, Mode::Gi(plain));
    let mut two = setup(&gpu, &scene, size, Mode::Gi(apart));
    assert!(!one.gi.shades_apart() && two.gi.shades_apart());
    assert_runs_match(&gpu, &scene, size, &mut one, &mut two);
    let mut switched = setup(&gpu, &scene, size, Mode::Gi(plain));
    switched.frame(&gpu, &scene);
    for (settings, apart) in [(apart, true), (plain, false)] {
        switched.gi.set_settings(settings).expect("valid settings");
        switched.mode = Mode::Gi(settings);
        assert_eq!(
            switched.gi.shades_apart(),
            !apart,
            "built at the next frame"
        );
        assert_stale_pipelines_refused(&gpu, &mut switched);
        switched.frame(&gpu, &scene);
        assert_eq!(switched.gi.shades_apart(), apart);
    }
    // With reuse the setting changes nothing: the second dispatch is the temporal merge.
    let reuse = setup(
        &gpu,
        &scene,
        size,
        Mode::Gi(RestirGiSettings {
            shade_apart: true,
            ..Default::default()
        }),
    );
    assert!(!reuse.gi.shades_apart());
    // Nor with several candidates: their average exists only in the tracing dispatch, so the
    // pass shades there, and a switch to one candidate builds the pass apart again.
    let several = RestirGiSettings {
        initial_samples: 4,
        ..apart
    };
    let mut multi = setup(&gpu, &scene, size, Mode::Gi(several));
    multi.frame(&gpu, &scene);
    assert!(!multi.gi.shades_apart() && multi.gi.initial_multi_candidate());
    multi.gi.set_settings(apart).expect("valid settings");
    multi.mode = Mode::Gi(apart);
    multi.frame(&gpu, &scene);
    assert!(multi.gi.shades_apart() && !multi.gi.initial_multi_candidate());
}

/// Two runs of plain path GI that must trace the same samples and add the same light. Their
/// first frames agree bit for bit (reservoirs and image). Later frames differ where the world
/// cache does (its cells are claimed by atomics, in whatever order lavapipe's threads arrive):
/// a sample whose cell reads no light yet is dropped in one run and kept in the other. So from
/// frame 1 every sample both runs kept must be the same point with the same normal, W and
/// confidence (73–80% of those either kept in frame 3, while the cache fills; at least half
/// are required, so the check cannot pass empty), and their means over 16 more frames must
/// add up to within 1% (0.07–0.12% apart in three runs of the one-buffer test; GI is a fifth
/// of the box's light: with the shade's GI dropped it read 282 against 348).
fn assert_runs_match(gpu: &Gpu, scene: &Scene, size: u32, one: &mut Setup, two: &mut Setup) {
    use solari_restir::gi_reservoir::GpuGiReservoir;
    let bytes = (size * size) as u64 * size_of::<GpuGiReservoir>() as u64;
    for frame in 0..6 {
        one.frame(gpu, scene);
        two.frame(gpu, scene);
        let read = |gi: &RestirGi| -> Vec<GpuGiReservoir> {
            let raw = gpu.read_buffer(gi.reservoirs(), bytes).expect("read");
            bytemuck::cast_slice(&raw).to_vec()
        };
        let (ra, rb) = (read(&one.gi), read(&two.gi));
        assert!(
            frame == 0 || ra.iter().any(|r| r.weight > 0.0),
            "frame {frame}: no reservoir holds a sample"
        );
        if frame == 0 {
            assert!(ra == rb, "frame 0: the final reservoirs differ");
            let (a, b) = (one.direct.read_output(gpu), two.direct.read_output(gpu));
            assert!(a == b, "frame 0: the images differ");
        } else {
            // A sample whose cell reads zero radiance in one run is dropped there (W = 0);
            // every sample both runs kept is the same point with the same W.
            let geometry = |r: &GpuGiReservoir| (r.position, r.normal, r.weight, r.confidence);
            let both: Vec<_> = ra
                .iter()
                .zip(&rb)
                .filter(|(a, b)| a.weight > 0.0 && b.weight > 0.0)
                .collect();
            let either = ra
                .iter()
                .zip(&rb)
                .filter(|(a, b)| a.weight > 0.0 || b.weight > 0.0)
                .count();
            assert!(
                both.iter().all(|(a, b)| geometry(a) == geometry(b)),
                "frame {frame}: the reservoirs' samples differ"
            );
            assert!(
                both.len() * 2 >= either,
                "frame {frame}: only {} of {either} samples kept by both runs",
                both.len()
            );
        }
    }
    let total = |s: &mut Setup| -> f64 {
        let (mean, _) = s.mean(gpu, scene, 0, 16);
        mean.iter().flatten().map(|&v| v as f64).sum()
    };
    let (a, b) = (total(one), total(two));
    eprintln!("16-frame totals: {a:.3} and {b:.3}");
    assert!(
        (a / b - 1.0).abs() < 0.01,
        "one run {a} against the other {b}"
    );
}

/// What another pass sharing `scratch` might leave there: `plausible` (real records of
/// another pixel, `record` bytes each, moved along by 7 of them, which a pass reading what it
/// did not write would take for its own) and random bytes after it.
fn scribble(gpu: &Gpu, scratch: &wgpu::Buffer, plausible: &[u8], record: usize, seed: u64) {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg32::seed_from_u64(seed);
    let mut bytes: Vec<u8> = (0..scratch.size()).map(|_| rng.random()).collect();
    let n = plausible.len();
    for (i, b) in plausible.iter().enumerate() {
        bytes[(i + 7 * record) % n] = *b;
    }
    gpu.queue.write_buffer(scratch, 0, &bytes);
}

/// The renderer keeps DI's and GI's initial reservoirs in one scratch buffer that the
/// denoiser overwrites later in the frame, so each pass may read only what its own
/// dispatches of the frame wrote there. Filled before every frame with other pixels' real
/// reservoirs and random bytes, the scratch changes nothing: DI alone, whose frames are
/// deterministic, gives the same images bit for bit over 6 frames of temporal and spatial
/// reuse; with GI, frame 0 (before the world cache's later, racing updates) gives the same
/// image and reservoirs bit for bit, with reuse and without, from every pixel and at half
/// rate, path GI shaded where traced and apart. (Real reservoirs pass the
/// passes' validity checks, which random bytes may not; a DI initial pass made to skip every
/// fifth column fails the test either way.) Each pass counts only its own buffers, and a
/// scratch too small is refused with both sizes named.
#[test]
fn a_shared_scratch_full_of_garbage_changes_nothing() {
    use solari_restir::GpuReservoir;
    use solari_restir::gi_reservoir::GpuGiReservoir;
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 32;
    let backend = gpu.backend(Default::default()).expect("backend");
    let camera = scene.camera(None).unwrap();
    let new_di = || DirectLight::new(&gpu, backend, &scene, size, di_settings(), tile_settings());
    let (mut own, mut shared) = (new_di(), new_di());
    let scratch = solari_scene::scratch::allocate(&gpu, shared.di.scratch_bytes()).unwrap();
    shared.di.use_scratch(&gpu, &scratch).expect("scratch");
    assert_eq!(
        own.di.memory_bytes() - shared.di.memory_bytes(),
        shared.di.scratch_bytes()
    );
    let record = size_of::<GpuReservoir>();
    let mut plausible = vec![0u8; shared.di.scratch_bytes() as usize];
    for frame in 0..6 {
        scribble(&gpu, &scratch, &plausible, record, frame);
        let (a, b) = (
            own.render(&gpu, &scene, &camera),
            shared.render(&gpu, &scene, &camera),
        );
        assert!(a == b, "DI frame {frame}: the images differ");
        plausible = gpu
            .read_buffer(
                own.di.reservoirs().expect("DI with reuse keeps reservoirs"),
                own.di.scratch_bytes(),
            )
            .unwrap();
    }
    let read = |gi: &RestirGi| {
        gpu.read_buffer(gi.reservoirs(), gi.scratch_bytes())
            .unwrap()
    };
    let plain = RestirGiSettings::plain();
    let apart = RestirGiSettings {
        shade_apart: true,
        ..plain
    };
    let half = |s: RestirGiSettings| RestirGiSettings {
        rate: GiRate::Half,
        ..s
    };
    // The second dispatches read what the first wrote: at half rate, with reuse, only the
    // pixels on this frame's checkerboard.
    for (what, settings) in [
        ("reuse", RestirGiSettings::default()),
        ("plain", plain),
        ("plain, shaded apart", apart),
        ("reuse, half rate", half(RestirGiSettings::default())),
        ("plain, shaded apart, half rate", half(apart)),
        (
            "reuse, quarter rate",
            RestirGiSettings {
                rate: GiRate::Quarter,
                ..RestirGiSettings::default()
            },
        ),
    ] {
        let mut donor = setup(&gpu, &scene, size, Mode::Gi(settings));
        donor.frame(&gpu, &scene);
        let plausible = read(&donor.gi);
        let mut own = setup(&gpu, &scene, size, Mode::Gi(settings));
        let mut shared = setup(&gpu, &scene, size, Mode::Gi(settings));
        let bytes = shared
            .direct
            .di
            .scratch_bytes()
            .max(shared.gi.scratch_bytes());
        let scratch = solari_scene::scratch::allocate(&gpu, bytes).unwrap();
        shared.direct.di.use_scratch(&gpu, &scratch).unwrap();
        let gi_own = shared.gi.memory_bytes();
        shared
            .gi
            .use_scratch(&gpu, &scratch, &shared.cache)
            .expect("scratch");
        assert_eq!(gi_own - shared.gi.memory_bytes(), shared.gi.scratch_bytes());
        scribble(&gpu, &scratch, &plausible, size_of::<GpuGiReservoir>(), 99);
        own.frame(&gpu, &scene);
        shared.frame(&gpu, &scene);
        let (a, b) = (
            own.direct.read_output(&gpu),
            shared.direct.read_output(&gpu),
        );
        assert!(a.iter().any(|p| p[0] > 0.0), "{what}: a black frame");
        assert!(a == b, "{what}: the images differ");
        assert!(
            read(&own.gi) == read(&shared.gi),
            "{what}: the reservoirs differ"
        );
    }
    let small = solari_scene::scratch::allocate(&gpu, 64).unwrap();
    let e = new_di()
        .di
        .use_scratch(&gpu, &small)
        .unwrap_err()
        .to_string();
    assert!(e.contains("holds 64 bytes") && e.contains("20480"), "{e}");
    // A failed copy into the scratch would leave it clean and the test toothless.
    gpu.check_errors().expect("no wgpu error");
}

/// Spatial reuse at a reduced rate (`RestirGiSettings::half_rate_spatial`) runs at the pixels
/// of one phase of the initial pass's cycle, and nowhere else: at half rate those that did not
/// trace this frame (x + y + frame odd), at a quarter those one frame past their traced one
/// ((x + 2y + frame) mod 4 = 1). Every other pixel ends the frame with the reservoir the
/// temporal merge left it, bit for bit, while most of the reusing ones take a neighbour's.
/// With the setting off, every pixel reuses. (A spatial pass on the wrong phase, or on
/// several, fails one of these.) The initial reservoirs are read from a scratch buffer GI
/// keeps them in.
#[test]
fn reduced_rate_spatial_reuse_runs_at_one_phase_only() {
    use solari_restir::gi_reservoir::GpuGiReservoir;
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 32;
    for (rate, half_rate_spatial) in [
        (GiRate::Half, false),
        (GiRate::Half, true),
        (GiRate::Quarter, true),
    ] {
        let settings = RestirGiSettings {
            spatial_radius: 3.0,
            rate,
            half_rate_spatial,
            ..Default::default()
        };
        let n = rate.interval();
        let (mut s, scratch) = setup_reading_initial(&gpu, &scene, size, settings);
        for _ in 0..6 {
            s.frame(&gpu, &scene);
        }
        let frame = s.direct.context().index;
        let record = size_of::<GpuGiReservoir>();
        let bytes = s.gi.scratch_bytes();
        let initial = gpu.read_buffer(&scratch, bytes).unwrap();
        let history = gpu.read_buffer(s.gi.reservoirs(), bytes).unwrap();
        // Pixels whose final reservoir is not the temporal merge's, by their phase.
        let mut changed = [0u32; 4];
        let mut pixels = [0u32; 4];
        for (i, (a, b)) in initial
            .chunks_exact(record)
            .zip(history.chunks_exact(record))
            .enumerate()
        {
            let (x, y) = (i as u32 % size, i as u32 / size);
            let phase = ((x + y * (n / 2) + frame) % n) as usize;
            pixels[phase] += 1;
            changed[phase] += u32::from(a != b);
        }
        let share = |k: usize| changed[k] as f64 / pixels[k] as f64;
        eprintln!(
            "rate 1/{n}, half_rate_spatial {half_rate_spatial}: reservoirs changed by spatial \
             reuse at {:?} of each phase's pixels",
            (0..n as usize).map(share).collect::<Vec<_>>()
        );
        for phase in 0..n as usize {
            if !half_rate_spatial || phase == 1 {
                assert!(
                    share(phase) > 0.5,
                    "rate 1/{n}: phase {phase} hardly reuses: {changed:?} of {pixels:?}"
                );
            } else {
                assert_eq!(
                    changed[phase], 0,
                    "rate 1/{n}: a pixel of phase {phase} reused: {changed:?} of {pixels:?}"
                );
            }
        }
    }
}

/// At a reduced rate, a pixel with nothing to carry from last frame traces at its full-rate
/// weight, off its phase or on it (`traces_without_history` in `restir_gi_initial.wesl`: the
/// merge traces the one off its phase with the tracing dispatch's seed, and divides the one
/// on it back by the interval). On the first frame after `RestirGi::reset` (no history
/// anywhere) half and quarter rate therefore hold, pixel for pixel, the very sample that
/// every-pixel GI draws: the same sample point and weight (the weight of one candidate is
/// π / cos θ, whatever the cache says there). With `trace_fresh_pixels` off only a half or a
/// quarter of the pixels hold one, at the rate's multiple of that weight. From the second
/// frame on, with a still camera, every pixel has its history and the rate's phases alone
/// decide (the phase test above).
#[test]
fn pixels_without_history_trace_at_a_reduced_rate() {
    use solari_restir::gi_reservoir::GpuGiReservoir;
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 32;
    // The merged reservoirs of the first frame after a reset.
    let first_frame = |rate: GiRate, trace_fresh_pixels: bool| -> Vec<GpuGiReservoir> {
        let settings = RestirGiSettings {
            spatial: false,
            rate,
            trace_fresh_pixels,
            ..Default::default()
        };
        let (mut s, scratch) = setup_reading_initial(&gpu, &scene, size, settings);
        // The world cache lit first (a cold cell gives no sample), then history dropped.
        for _ in 0..12 {
            s.frame(&gpu, &scene);
        }
        s.gi.reset();
        s.frame(&gpu, &scene);
        initial_reservoirs(&gpu, &s, &scratch)
    };
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1.0);
    let full = first_frame(GiRate::Full, true);
    let sampled = full.iter().filter(|r| r.weight > 0.0).count();
    assert!(
        sampled > (size * size / 2) as usize,
        "only {sampled} samples at every pixel"
    );
    for (name, rate) in [("half", GiRate::Half), ("quarter", GiRate::Quarter)] {
        let scale = rate.interval() as f32;
        for trace_fresh_pixels in [true, false] {
            let reduced = first_frame(rate, trace_fresh_pixels);
            // Pixels where both hold a sample (a cell that is cold in one run and not in the
            // other gives one of them none), and how many of those match.
            let (mut both, mut same, mut scaled) = (0, 0, 0);
            for (f, r) in full.iter().zip(&reduced) {
                if !(f.weight > 0.0 && r.weight > 0.0) {
                    continue;
                }
                both += 1;
                let at = (0..3).all(|k| close(f.position[k], r.position[k]));
                same += usize::from(at && close(f.weight, r.weight));
                scaled += usize::from(at && close(f.weight * scale, r.weight));
            }
            eprintln!(
                "first frame after a reset, {name} rate, fresh pixels {trace_fresh_pixels}: \
                 {both} pixels with a sample in both (every pixel: {sampled}), {same} the same \
                 sample, {scaled} at {scale}x its weight"
            );
            if trace_fresh_pixels {
                assert!(
                    both as f64 > 0.9 * sampled as f64,
                    "{name} rate: {both} samples against {sampled}"
                );
                assert_eq!(
                    same, both,
                    "{name} rate: another sample or weight somewhere"
                );
            } else {
                // Only the pixels on their phase trace, at the rate's scale.
                let share = both as f64 / sampled as f64;
                assert!(
                    (share - 1.0 / scale as f64).abs() < 0.1,
                    "{name} rate without the rule: {both} samples against {sampled}"
                );
                assert_eq!(
                    scaled, both,
                    "{name} rate without the rule: a weight off the scale"
                );
            }
        }
    }
}

/// Under a still camera jittered as the temporal upscaler jitters it, a pixel at a silhouette
/// lands on one side of it one frame and on the other the next. The temporal neighbour search
/// looks about the reprojected pixel for its own surface, so such a pixel carries its history
/// like the rest. The test counts the pixels whose merged reservoir holds one frame's
/// confidence at most: without the search 2.5–14.6% of the Cornell box's at 48² a frame (mean
/// 9.6%; 7% of `interior`'s at 320×180), each of which traces again at once at a reduced rate
/// (`trace_fresh_pixels`); with it 1.4–2.1%; unjittered, none.
#[test]
fn a_jittered_still_camera_keeps_history_at_silhouettes() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let size = 48;
    let settings = RestirGiSettings {
        spatial: false,
        rate: GiRate::Quarter,
        ..Default::default()
    };
    let (mut s, scratch) = setup_reading_initial(&gpu, &scene, size, settings);
    let mut shares = Vec::new();
    for frame in 0..24u32 {
        // The renderer's jitter.
        let jitter = solari_scene::gpu_types::halton_jitter(frame);
        s.frame_jittered(&gpu, &scene, jitter);
        if frame < 12 {
            continue;
        }
        let confidences: Vec<f32> = initial_reservoirs(&gpu, &s, &scratch)
            .iter()
            .map(|r| r.confidence)
            .filter(|&c| c > 0.0)
            .collect();
        let alone = confidences.iter().filter(|&&c| c <= 1.0).count();
        let share = alone as f64 / confidences.len().max(1) as f64;
        eprintln!(
            "frame {frame}: {alone} of {} pixels without history",
            confidences.len()
        );
        assert!(confidences.len() > (size * size * 9 / 10) as usize);
        shares.push(share);
    }
    let mean = shares.iter().sum::<f64>() / shares.len() as f64;
    assert!(
        mean < 0.04,
        "{:.2}% of the pixels lost their history each frame under a jittered still camera",
        mean * 100.0
    );
}

/// Under the renderer's jitter (where the temporal neighbour search finds a silhouette
/// pixel's history on a neighbour of its reprojected pixel, at reduced rates only) ReSTIR GI
/// at a quarter rate keeps the total light of a 256-frame mean within 1% of the reference's.
/// A mean of jittered frames averages each pixel's area, so the reference here samples the
/// pixels' areas too: against pixel centres the box's ceiling light, a few pixels tall, read
/// 8% darker in cache-only GI as well. Measured (lavapipe, 2026-11-29): +0.60%, +0.64%,
/// +0.66% (cache-only GI, every mode's expectation, +0.00% to +0.22% in the same runs), and
/// +0.71% twice with the search turned off in the shader: the jitter itself, not the search,
/// lifts reuse by about half a percent here. So the bound is 1%, as the unjittered test
/// gives the adaptive cap's measured bias, rather than its 0.65% for a quarter rate.
#[test]
fn reuse_at_a_quarter_rate_under_jitter_keeps_its_total_light() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let scene = default_scene::cornell_box();
    let backend = gpu.backend(Default::default()).unwrap();
    let settings = solari_reference::ReferenceSettings {
        spp: 512,
        max_bounces: u32::MAX,
        selection: solari_lights::Selection::Power,
        pixel_centre: false,
        min_bounces: 0,
    };
    let truth = solari_reference::reference_image(&gpu, backend, &scene, size, size, &settings)
        .expect("reference render")
        .pixels;
    let jitter = solari_scene::gpu_types::halton_jitter;
    let quarter = RestirGiSettings {
        spatial_radius: 3.0,
        rate: GiRate::Quarter,
        adaptive_cap: false,
        ..Default::default()
    };
    let mut biases = Vec::new();
    for (name, mode) in [
        ("cache", Mode::Cache),
        ("restir, quarter rate", Mode::Gi(quarter)),
    ] {
        let mut s = setup(&gpu, &scene, size, mode);
        let (mean, _) = s.mean_jittered(&gpu, &scene, 100, 256, jitter);
        let bias = total_light_bias(&mean, &truth);
        eprintln!(
            "cornell {size}x{size} jittered, {name}: total light {:+.2}%",
            bias * 100.0
        );
        biases.push(bias);
    }
    assert!(
        biases[1].abs() < 0.01,
        "ReSTIR GI at a quarter rate, jittered: total light off by {:+.2}% (cache GI {:+.2}%)",
        biases[1] * 100.0,
        biases[0] * 100.0
    );
}

/// On a device whose storage bindings stop at 64 KiB: ReSTIR DI at 60×60 fits its image
/// (57,600 bytes) but not its reservoirs (72,000), and says so instead of failing at bind
/// time; a scratch buffer over the limit is refused too (every pass binds it whole).
#[test]
fn buffers_over_the_binding_limit_are_refused_by_name() {
    use solari_restir::RestirDi;
    use solari_scene::GpuError;
    use solari_scene::shaders::Backend;
    let Some(small) = solari_scene::gpu::test_gpu_with_limits(|own| wgpu::Limits {
        max_storage_buffer_binding_size: 1 << 16,
        ..own
    }) else {
        return;
    };
    let di = RestirDi::new(
        &small,
        Backend::Software,
        TraceVariant::General,
        60,
        60,
        di_settings(),
        tile_settings(),
    );
    match di {
        Err(GpuError::OverLimit { what, needed, .. }) => {
            assert!(
                what.contains("reservoirs") && needed == 72_000,
                "{what}: {needed}"
            );
        }
        other => panic!("expected OverLimit, got {:?}", other.err()),
    }
    match solari_scene::scratch::allocate(&small, 1 << 17) {
        Err(GpuError::OverLimit { what, .. }) => assert!(what.contains("scratch"), "{what}"),
        other => panic!("expected OverLimit, got {:?}", other.err()),
    }
    small
        .check_errors()
        .expect("refused before wgpu saw anything");
}

/// ReSTIR GI's first frames follow the world cache as it fills (`RestirGiSettings::
/// ignore_cold_cells`, `adaptive_cap`): from a cold start its total light over frames 5-12
/// of the Cornell box matches plain path GI's, which asks the cache afresh every frame. With
/// both off it was dark: a hit in a cell not yet lit counted as a sample of no light, and
/// samples traced while the cache was dim were reused at the full confidence cap.
#[test]
fn young_frames_follow_the_cache() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let scene = default_scene::cornell_box();
    let young = |settings: RestirGiSettings| {
        let mut s = setup(&gpu, &scene, size, Mode::Gi(settings));
        let (mean, _) = s.mean(&gpu, &scene, 4, 8);
        mean.iter()
            .map(|p| (p[0] + p[1] + p[2]) as f64)
            .sum::<f64>()
    };
    let plain = young(RestirGiSettings::plain());
    let old = RestirGiSettings {
        ignore_cold_cells: false,
        adaptive_cap: false,
        ..Default::default()
    };
    let modes = [
        ("defaults", RestirGiSettings::default()),
        ("neither", old),
        (
            "cold cells ignored",
            RestirGiSettings {
                ignore_cold_cells: true,
                ..old
            },
        ),
        (
            "adaptive cap",
            RestirGiSettings {
                adaptive_cap: true,
                ..old
            },
        ),
    ];
    let ratios: Vec<f64> = modes.iter().map(|(_, m)| young(*m) / plain).collect();
    for ((name, _), r) in modes.iter().zip(&ratios) {
        eprintln!(
            "cornell {size}x{size}, frames 5-12 from a cold start: ReSTIR GI ({name}) / plain \
             path GI total light {r:.4}"
        );
    }
    // Measured (lavapipe, three runs): defaults 0.987, neither 0.923, cold cells ignored
    // alone 0.954, the adaptive cap alone 0.973. The ratio counts DI too, which both modes
    // share, so GI's own shortfall was larger.
    let (defaults, neither) = (ratios[0], ratios[1]);
    assert!(
        defaults > 0.97,
        "ReSTIR GI's young frames are dark: {defaults:.4} of path GI's light"
    );
    // The defect the settings mend is still there without them (else this test proves
    // nothing), and each setting mends part of it alone.
    assert!(neither < 0.95, "without either setting: {neither:.4}");
    for (i, r) in ratios.iter().enumerate().skip(2) {
        assert!(
            *r > neither + 0.015,
            "{} alone: {r:.4}, no better than neither ({neither:.4})",
            modes[i].0
        );
    }
}

/// A confidence cap beyond f16's range (valid: any finite cap of at least 1) is stored at the
/// limit in each sample and read back as no cap: every frame stays finite and non-negative,
/// with the adaptive cap (which stores a cap per sample as f16) on and off.
#[test]
fn a_confidence_cap_beyond_f16_stays_finite() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    for adaptive_cap in [true, false] {
        let settings = RestirGiSettings {
            confidence_cap: 1e9,
            adaptive_cap,
            ..Default::default()
        };
        let mut s = setup(&gpu, &scene, 32, Mode::Gi(settings));
        // `frame` panics on any NaN, infinity, negative value or over-confident reservoir.
        let (mean, _) = s.mean(&gpu, &scene, 8, 8);
        let light: f64 = mean.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum();
        assert!(light > 0.0, "adaptive cap {adaptive_cap}: no light at all");
    }
}

/// The adaptive cap runs while the view is unsettled: from the first frame until the camera
/// has held still for `adaptive_cap_settle_frames` frames, and again after the camera moves,
/// the scene changes (`unsettle`), the lights change (`follow_light_change`, for its frames
/// and the settling after) or history is dropped.
#[test]
fn the_adaptive_cap_runs_until_the_view_settles() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let settings = RestirGiSettings {
        adaptive_cap_settle_frames: 3,
        ..Default::default()
    };
    let mut s = setup(&gpu, &scene, 16, Mode::Gi(settings));
    let camera = scene.camera(None).unwrap();
    let mut moved = camera.clone();
    moved.transform.w_axis.x += 0.01;
    let run = |s: &mut Setup, frames: usize, camera: &solari_scene::Camera| {
        (0..frames)
            .map(|_| {
                s.frame_from(&gpu, &scene, camera, [0.0; 2]);
                s.gi.adaptive_cap_active()
            })
            .collect::<Vec<_>>()
    };
    // The first frame has no history; then 1, 2, 3 settled frames keep the cap, the 4th not.
    assert_eq!(
        run(&mut s, 6, &camera),
        [true, true, true, true, false, false]
    );
    // A moved camera unsettles the view; holding the new one settles it again.
    assert_eq!(run(&mut s, 1, &moved), [true]);
    assert_eq!(run(&mut s, 5, &moved), [true, true, true, false, false]);
    s.gi.unsettle();
    assert_eq!(run(&mut s, 5, &moved), [true, true, true, false, false]);
    // A light change: its short histories, then the settling.
    s.gi.follow_light_change(2);
    assert_eq!(
        run(&mut s, 7, &moved),
        [true, true, true, true, true, false, false]
    );
    s.gi.reset();
    assert_eq!(run(&mut s, 5, &moved), [true, true, true, true, false]);
    // `u32::MAX` keeps it always; the setting off never runs it.
    for (settle, adaptive_cap, expected) in [(u32::MAX, true, true), (3, false, false)] {
        let settings = RestirGiSettings {
            adaptive_cap_settle_frames: settle,
            adaptive_cap,
            ..Default::default()
        };
        let mut s = setup(&gpu, &scene, 16, Mode::Gi(settings));
        assert!(run(&mut s, 8, &camera).iter().all(|&on| on == expected));
    }
}

/// `spatial_history` off: next frame's history is the pixel's own reservoir from before
/// spatial reuse, the temporal merge's output bit for bit; on (the default), the merge's,
/// which differs wherever a neighbour's sample was chosen or the confidences were summed.
#[test]
fn the_history_is_the_spatial_merge_or_the_pixels_own() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    for spatial_history in [false, true] {
        let settings = RestirGiSettings {
            spatial_history,
            ..Default::default()
        };
        let (mut s, scratch) = setup_reading_initial(&gpu, &scene, 32, settings);
        for _ in 0..6 {
            s.frame(&gpu, &scene);
        }
        let own = initial_reservoirs(&gpu, &s, &scratch);
        let history = reservoirs_in(&gpu, &s, s.gi.reservoirs());
        let differ = own
            .iter()
            .zip(&history)
            .filter(|(a, b)| bytemuck::bytes_of(*a) != bytemuck::bytes_of(*b))
            .count();
        if spatial_history {
            assert!(differ > own.len() / 4, "{differ} of {} differ", own.len());
        } else {
            assert_eq!(differ, 0, "the history must be the own reservoirs");
        }
    }
}

/// The Cornell box's floor and tall block, the block polished gold (metal, roughness 0.3), lit
/// by a sun that the block's front face reflects down onto the floor in front of it; the
/// camera looks down at that stretch of floor from above, so that every pixel is the
/// Lambertian floor and its indirect light is mostly the sun's reflection off the gold.
/// `roughness`: the gold's.
fn gold_block_in_the_sun(roughness: f32) -> Scene {
    use glam::{Vec3, Vec4};
    use solari_scene::{Camera, DirectionalLight, Material, SUN_ANGULAR_DIAMETER};
    let mut scene = default_scene::cornell_box();
    scene
        .instances
        .retain(|i| ["floor", "tall_block"].contains(&i.name.as_str()));
    scene.materials.push(Material {
        name: "gold".into(),
        base_color: Vec4::new(1.0, 0.78, 0.34, 1.0),
        metallic: 1.0,
        roughness,
        ..Default::default()
    });
    let gold = scene.materials.len() as u32 - 1;
    for i in &mut scene.instances {
        if i.name == "tall_block" {
            i.material = gold;
        }
    }
    scene.directional_lights.push(DirectionalLight {
        name: "sun".into(),
        direction: Vec3::new(0.0, -0.5, 0.866).normalize(),
        irradiance: Vec3::splat(3.0),
        angular_diameter: SUN_ANGULAR_DIAMETER,
    });
    let mut camera = Camera::look_at(
        "above",
        Vec3::new(2.8, 3.0, 0.0),
        Vec3::new(2.8, 0.0, 1.0),
        Vec3::Y,
        0.6,
    );
    camera.aspect = Some(1.0);
    scene.cameras = vec![camera];
    scene
}

#[test]
fn glossy_hits_bring_a_metals_reflected_sun_to_the_floor() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let scene = gold_block_in_the_sun(0.3);
    let backend = gpu.backend(Default::default()).unwrap();
    let truth = reference(&gpu, backend, &scene, size, 512, u32::MAX);
    let direct = reference(&gpu, backend, &scene, size, 128, 1);
    let luminance_sum = |im: &[[f32; 3]]| im.iter().map(|&c| common::luminance(c)).sum::<f64>();
    let truth_indirect = luminance_sum(&truth) - luminance_sum(&direct);
    let glossy =
        |glossy_hits: GlossyHits, s: RestirGiSettings| RestirGiSettings { glossy_hits, ..s };
    let restir = RestirGiSettings {
        spatial_radius: 3.0,
        spatial_visibility: SpatialVisibility::Both,
        adaptive_cap: false,
        ..Default::default()
    };
    let plain = RestirGiSettings::plain();
    let modes = [
        ("plain, the cache at every hit", plain),
        ("plain, light samples", glossy(GlossyHits::Lights, plain)),
        ("plain, paths", glossy(GlossyHits::Path, plain)),
        ("restir, light samples", glossy(GlossyHits::Lights, restir)),
        ("restir, paths", glossy(GlossyHits::Path, restir)),
    ];
    let mut shares = Vec::new();
    for (name, settings) in modes {
        let mut s = setup(&gpu, &scene, size, Mode::Gi(settings));
        assert_eq!(
            s.gi.glossy_hits(),
            settings.glossy_hits,
            "{name}: the initial pass is built for its glossy-hit setting"
        );
        let (mean, _) = s.mean(&gpu, &scene, 64, 192);
        let share = (luminance_sum(&mean) - luminance_sum(&direct)) / truth_indirect;
        eprintln!(
            "gold block {size}x{size} {name}: indirect light {share:.4} of the reference's, \
             total light {:+.2}%",
            total_light_bias(&mean, &truth) * 100.0
        );
        shares.push(share);
    }
    // Measured (lavapipe, 2026-12-07): the cache at every hit 0.322 of the reference's
    // indirect light (total light -21.0%): the uniform-light model spreads the gold's
    // reflection of the sun over every direction. Light samples 1.023 (plain path GI) and
    // 1.026 (ReSTIR GI): the light the gold reflects from the floor stays under the uniform
    // model; paths 0.987 and 0.990.
    assert!(
        shares[0] < 0.6,
        "without glossy hits the floor should miss most of the gold's reflection: {shares:?}"
    );
    for (share, (name, _)) in shares[1..].iter().zip(&modes[1..]) {
        assert!(
            (share - 1.0).abs() < 0.05,
            "{name}: indirect light {share:.4} of the reference's"
        );
    }
    // A mirror's delta lobe takes no light sample, and its one ray seldom finds the sun: under
    // `GlossyHits::Lights` and `Path` a mirror block keeps the cache's model, and reflects
    // what it reflects there, not nothing (0.12 of it without that rule, `Lights`).
    let mirror = gold_block_in_the_sun(0.0);
    let mirror_direct = luminance_sum(&reference(&gpu, backend, &mirror, size, 128, 1));
    let mut light = [0.0; 3];
    let all = [GlossyHits::Cache, GlossyHits::Lights, GlossyHits::Path];
    for (k, glossy_hits) in all.into_iter().enumerate() {
        let settings = glossy(glossy_hits, plain);
        let mut s = setup(&gpu, &mirror, size, Mode::Gi(settings));
        let (mean, _) = s.mean(&gpu, &mirror, 32, 64);
        light[k] = luminance_sum(&mean) - mirror_direct;
    }
    eprintln!(
        "mirror block {size}x{size}: light samples {:.4}, paths {:.4} of the cache's indirect \
         light",
        light[1] / light[0],
        light[2] / light[0]
    );
    for k in [1, 2] {
        assert!(
            (light[k] / light[0] - 1.0).abs() < 0.02,
            "a mirror keeps the cache's model: {light:?}"
        );
    }
}

/// The gold block polished to roughness 0.15 under a 5° sun, where the lobe is about as wide
/// as the disc: a light sample and a BRDF-sampled ray each find a share of the sun, and MIS
/// splits it between them. Under `GlossyHits::Path` the bounce that misses the scene must
/// count the disc (`sky_light`); under `Lights` the light sample alone carries it. Both
/// against the reference, which counts the disc the same way. (The real sun's disc on
/// roughness 0.05 makes a glint that cosine-sampled GI rays find a dozen times in the whole
/// run: its estimates ranged from 0.29 to 1.22 of the reference between variants that
/// should agree. Hence a rougher metal and a wider sun here.)
#[test]
fn glossy_hits_carry_a_polished_metals_sun_to_the_floor() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let mut scene = gold_block_in_the_sun(0.15);
    scene.directional_lights[0].angular_diameter = 5f32.to_radians();
    let backend = gpu.backend(Default::default()).unwrap();
    let truth = reference(&gpu, backend, &scene, size, 512, u32::MAX);
    let direct = reference(&gpu, backend, &scene, size, 128, 1);
    let luminance_sum = |im: &[[f32; 3]]| im.iter().map(|&c| common::luminance(c)).sum::<f64>();
    let truth_indirect = luminance_sum(&truth) - luminance_sum(&direct);
    let mut shares = Vec::new();
    for glossy_hits in [GlossyHits::Cache, GlossyHits::Lights, GlossyHits::Path] {
        let settings = RestirGiSettings {
            glossy_hits,
            ..RestirGiSettings::plain()
        };
        let mut s = setup(&gpu, &scene, size, Mode::Gi(settings));
        let (mean, _) = s.mean(&gpu, &scene, 64, 192);
        let share = (luminance_sum(&mean) - luminance_sum(&direct)) / truth_indirect;
        eprintln!(
            "polished gold block {size}x{size} {}: indirect light {share:.4} of the reference's",
            glossy_hits.name()
        );
        shares.push(share);
    }
    // Measured (lavapipe, 2026-12-07): the cache 0.282, light samples 0.964, paths 0.927.
    // The two halves of the path's estimate alone: the light sample at weight 1 (no disc in
    // the bounce) 0.930, the bounce alone (no light sample) 0.873. Without the disc in the
    // bounce under MIS (the reference's old defect), paths read 0.710 and this test failed.
    assert!(
        shares[0] < 0.6,
        "the cache's model should miss most of the glint: {shares:?}"
    );
    for (share, name) in shares[1..].iter().zip(["lights", "path"]) {
        assert!(
            (share - 1.0).abs() < 0.1,
            "{name}: indirect light {share:.4} of the reference's"
        );
    }
}
