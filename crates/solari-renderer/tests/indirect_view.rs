//! The indirect view (`FrameView::Indirect`): the GI passes' light alone, which a reference
//! of `min_bounces: 2` measures. The lit frame less the indirect view is the direct light, the
//! indirect view converges to the indirect reference as the lit frame does to the full one,
//! GI switched off leaves it black, and under the fallback denoiser an emitter does not get
//! its emission back.
mod common;

use common::{Cornell, SIZE, frame_mean, rgb};
use solari_denoise::DenoiserKind;
use solari_reference::{ReferenceSettings, reference_image};
use solari_renderer::{FrameView, GiMode, RealtimeRenderer, RealtimeSettings};

fn settings(gi: GiMode, view: FrameView, denoiser: DenoiserKind) -> RealtimeSettings {
    RealtimeSettings {
        gi,
        specular_gi: gi != GiMode::Off,
        view,
        denoiser: Some(denoiser),
        ..common::settings()
    }
}

// A `min_bounces .. max_bounces` reference of the box at pixel centres, 256 paths.
fn reference(c: &Cornell, min_bounces: u32, max_bounces: u32) -> Vec<[f32; 3]> {
    let settings = ReferenceSettings {
        spp: 256,
        min_bounces,
        max_bounces,
        pixel_centre: true,
        ..Default::default()
    };
    reference_image(&c.gpu, c.backend, &c.scene, SIZE, SIZE, &settings)
        .expect("reference")
        .pixels
}

fn total(image: &[[f32; 3]]) -> f64 {
    image.iter().map(|p| common::luminance(*p)).sum()
}

// The image's light over the reference's, in 4 × 4 blocks of the image (16 × 16 pixels
// each at SIZE 64): the largest relative miss of a block that holds at least `min_share`
// of the reference's light. A block's noise grows as its light shrinks, so dim blocks get
// their own, looser bound.
fn worst_block(image: &[[f32; 3]], reference: &[[f32; 3]], min_share: f64) -> f64 {
    let (n, side) = (4usize, SIZE as usize);
    let mut worst = 0.0f64;
    for by in 0..n {
        for bx in 0..n {
            let (mut a, mut b) = (0.0, 0.0);
            for y in by * side / n..(by + 1) * side / n {
                for x in bx * side / n..(bx + 1) * side / n {
                    a += common::luminance(image[y * side + x]);
                    b += common::luminance(reference[y * side + x]);
                }
            }
            if b > min_share * total(reference) {
                worst = worst.max((a / b - 1.0).abs());
            }
        }
    }
    worst
}

fn next_frame(c: &Cornell, r: &mut RealtimeRenderer) -> Vec<[f32; 4]> {
    r.render(&c.gpu, &c.scene, &c.gpu_scene, &c.camera)
        .expect("frame");
    r.read_output(&c.gpu).expect("read back")
}

// Plain path GI's indirect view, raw: the mean of `frames` frames after `warm_up`.
fn path_gi_indirect_mean(c: &Cornell, warm_up: u32, frames: u32) -> Vec<[f32; 3]> {
    let mut r = c.renderer(settings(
        GiMode::Path,
        FrameView::Indirect,
        DenoiserKind::None,
    ));
    for _ in 0..warm_up {
        next_frame(c, &mut r);
    }
    frame_mean(frames, || next_frame(c, &mut r)).0
}

#[test]
fn the_indirect_view_is_what_the_gi_passes_add() {
    let Some(c) = Cornell::new() else { return };
    let (warm_up, frames) = (16, 48);
    let none = DenoiserKind::None;
    let mut lit = c.renderer(settings(GiMode::Path, FrameView::Lit, none));
    let mut indirect = c.renderer(settings(GiMode::Path, FrameView::Indirect, none));
    // The two renderers draw the same random numbers, so their frames differ by DI alone.
    // The mean leaves out the world cache's first frames, while its cells fill.
    for _ in 0..warm_up {
        next_frame(&c, &mut lit);
        next_frame(&c, &mut indirect);
    }
    let (lit_mean, _) = frame_mean(frames, || next_frame(&c, &mut lit));
    let (indirect_mean, _) = frame_mean(frames, || next_frame(&c, &mut indirect));
    let direct: Vec<[f32; 3]> = lit_mean
        .iter()
        .zip(&indirect_mean)
        .map(|(l, i)| [l[0] - i[0], l[1] - i[1], l[2] - i[2]])
        .collect();
    let reference_direct = reference(&c, 0, 1);
    let reference_indirect = reference(&c, 2, u32::MAX);
    let direct_bias = total(&direct) / total(&reference_direct) - 1.0;
    let indirect_bias = total(&indirect_mean) / total(&reference_indirect) - 1.0;
    // Blocks with at least a 64th of the light (a block is a 16th of the image), and the
    // dim ones (the ceiling's corners hold 0.3–1% of the direct light).
    let (bright, dim) = (1.0 / 64.0, 1e-3);
    let (direct_block, direct_dim_block, indirect_block) = (
        worst_block(&direct, &reference_direct, bright),
        worst_block(&direct, &reference_direct, dim),
        worst_block(&indirect_mean, &reference_indirect, dim),
    );
    println!(
        "lit − indirect against the direct reference: total {direct_bias:+.4}, worst block \
         {direct_block:.4} (with the dim ones {direct_dim_block:.4}); indirect against the \
         indirect reference: total {indirect_bias:+.4}, worst block {indirect_block:.4}"
    );
    // Direct light is unbiased: what is left after the indirect view is taken out is the
    // direct reference within its noise (48 frames of ReSTIR DI; lavapipe's frames vary from
    // run to run, the world cache's atomics landing in another order). Over eleven runs here
    // the worst bright block missed by 1.2–2.3% and the worst dim one by 2.1–5.4%; CI's
    // machine read 5.1% in a dim block, which failed the single 5% bound this test had.
    assert!(direct_bias.abs() < 0.01, "{direct_bias}");
    assert!(direct_block < 0.04, "{direct_block}");
    assert!(direct_dim_block < 0.10, "{direct_dim_block}");
    // Path GI ends in the world cache, whose light lags and blurs: a few per cent low in
    // total, more in some blocks (measured on lavapipe over eleven runs: −1.8% to −2.7% in
    // total, 5.0–6.5% in the worst block; the tolerance states that bias).
    assert!(indirect_bias.abs() < 0.05, "{indirect_bias}");
    assert!(indirect_block < 0.10, "{indirect_block}");
}

#[test]
fn no_gi_leaves_the_indirect_view_black_and_the_denoiser_puts_no_emission_back() {
    let Some(c) = Cornell::new() else { return };
    let none = DenoiserKind::None;
    let mut off = c.renderer(settings(GiMode::Off, FrameView::Indirect, none));
    let mut off_lit = c.renderer(settings(GiMode::Off, FrameView::Lit, none));
    for _ in 0..3 {
        let pixels = next_frame(&c, &mut off);
        assert!(
            pixels
                .iter()
                .all(|p| p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0),
            "GI off, but the indirect view holds light"
        );
        // Alpha (surface or background) is the lit frame's.
        let alpha = |pixels: &[[f32; 4]]| pixels.iter().map(|p| p[3]).collect::<Vec<_>>();
        assert_eq!(alpha(&pixels), alpha(&next_frame(&c, &mut off_lit)));
    }
    // The ceiling light's emission is the brightest thing in the lit frame; the light it
    // reflects is far dimmer. Under the fallback denoiser the indirect view must not get the
    // emission back (the filter puts back what it took out of lighting that holds it).
    let fallback = DenoiserKind::Fallback;
    let mut lit = c.renderer(settings(GiMode::Path, FrameView::Lit, fallback));
    let mut indirect = c.renderer(settings(GiMode::Path, FrameView::Indirect, fallback));
    let brightest = |pixels: &[[f32; 4]]| {
        rgb(pixels)
            .iter()
            .map(|p| common::luminance(*p))
            .fold(0.0, f64::max)
    };
    let (mut lit_max, mut indirect_max) = (0.0f64, 0.0f64);
    for _ in 0..8 {
        lit_max = lit_max.max(brightest(&next_frame(&c, &mut lit)));
        indirect_max = indirect_max.max(brightest(&next_frame(&c, &mut indirect)));
    }
    println!("brightest pixel: lit {lit_max:.3}, indirect {indirect_max:.3}");
    assert!(lit_max > 5.0, "{lit_max}");
    assert!(
        indirect_max < 0.1 * lit_max,
        "{indirect_max} against {lit_max}"
    );
}

#[test]
fn restir_gi_on_a_settled_view_converges_without_the_adaptive_caps_bias() {
    let Some(c) = Cornell::new() else { return };
    let none = DenoiserKind::None;
    let reference = reference(&c, 2, u32::MAX);
    // The indirect light of frames 65-128, after the adaptive cap stopped (at frame 33), and
    // with the cap kept on throughout, as before it stopped on settled views.
    let mean_bias = |settle_frames: u32| {
        let mut s = settings(GiMode::Restir, FrameView::Indirect, none);
        s.restir_gi.adaptive_cap_settle_frames = settle_frames;
        let mut r = c.renderer(s);
        for _ in 0..64 {
            next_frame(&c, &mut r);
        }
        let (mean, _) = frame_mean(64, || next_frame(&c, &mut r));
        total(&mean) / total(&reference) - 1.0
    };
    let settled = mean_bias(solari_restir::ADAPTIVE_CAP_SETTLE_FRAMES);
    let capped = mean_bias(u32::MAX);
    println!("indirect light against the reference: settled {settled:+.4}, capped {capped:+.4}");
    // The cap weighs histories by the light they hold, dim ones less: too bright.
    assert!(capped > settled + 0.02, "{capped} against {settled}");
    assert!(settled.abs() < 0.03, "{settled}");
}

#[test]
fn a_uniform_sky_seen_after_one_bounce_stays_out_of_the_indirect_view() {
    // The box's open front lets GI rays escape to a uniform sky, which light sampling does
    // not cover: GI adds it in the lit frame, but from the primary surface it is one
    // scattering event, direct light.
    let mut scene = solari_scene::default_scene::cornell_box();
    scene.environment_radiance = glam::Vec3::splat(4.0);
    let Some(c) = Cornell::with_scene(scene) else {
        return;
    };
    let indirect_reference = reference(&c, 2, u32::MAX);
    let mean = path_gi_indirect_mean(&c, 16, 48);
    let bias = total(&mean) / total(&indirect_reference) - 1.0;
    println!("indirect view against the indirect reference: {bias:+.4}");
    assert!(bias.abs() < 0.05, "{bias}");
}

// relMSE per channel, as `solari compare` counts it (d² / (ref² + 0.01)): colour noise counts.
fn rel_mse(image: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    let mut sum = 0.0;
    for (a, b) in image.iter().zip(reference) {
        for c in 0..3 {
            let (a, b) = (a[c] as f64, b[c] as f64);
            sum += (a - b) * (a - b) / (b * b + 0.01);
        }
    }
    sum / (3 * image.len()) as f64
}

// The mean relMSE of `frames` single frames after `warm_up`, and the mean of those frames.
fn frame_errors(
    c: &Cornell,
    r: &mut RealtimeRenderer,
    reference: &[[f32; 3]],
    warm_up: u32,
    frames: u32,
) -> (f64, Vec<[f32; 3]>) {
    for _ in 0..warm_up {
        next_frame(c, r);
    }
    let mut error = 0.0;
    let (mean, _) = frame_mean(frames, || {
        let pixels = next_frame(c, r);
        error += rel_mse(&rgb(&pixels), reference) / frames as f64;
        pixels
    });
    (error, mean)
}

#[test]
fn plain_path_gi_shades_the_average_of_its_candidates() {
    let Some(c) = Cornell::new() else { return };
    let reference = reference(&c, 2, u32::MAX);
    let error = |candidates: u32| {
        let mut s = settings(GiMode::Path, FrameView::Indirect, DenoiserKind::None);
        s.restir_gi.initial_samples = candidates;
        let mut r = c.renderer(s);
        frame_errors(&c, &mut r, &reference, 16, 8).0
    };
    let (one, sixteen) = (error(1), error(16));
    println!("path GI, one frame's relMSE: 1 candidate {one:.5}, 16 candidates {sixteen:.5}");
    // Averaged, 16 independent candidates have 1/16 of one's variance (0.0625 of its error,
    // more with the reference's own noise); resampled to one they kept the colour noise of
    // a single sample: 0.168 of one candidate's error (lavapipe, 128², `lavapipe_probes.sh
    // floor` of `benches/results/gi_indirect_2026-11-29`).
    assert!(sixteen < 0.10 * one, "{sixteen} against {one}");
}

// Two ReSTIR GI runs of the indirect view that differ only in how they shade (`configure`
// sets the baseline with `false`, the variant with `true`): each one frame's relMSE (the mean
// of 128 frames' after 48), the variant's over the baseline's, the two 128-frame means' total
// light apart, and the variant's mean against the reference. Printed with `what`. None
// without a GPU (as `Cornell::new`).
fn shading_variant(
    what: &str,
    configure: impl Fn(&mut RealtimeSettings, bool),
) -> Option<(f64, f64, f64)> {
    let c = Cornell::new()?;
    let reference = reference(&c, 2, u32::MAX);
    let run = |variant: bool| {
        let mut s = settings(GiMode::Restir, FrameView::Indirect, DenoiserKind::None);
        configure(&mut s, variant);
        let mut r = c.renderer(s);
        frame_errors(&c, &mut r, &reference, 48, 128)
    };
    let ((base, base_mean), (variant, variant_mean)) = (run(false), run(true));
    let shift = total(&variant_mean) / total(&base_mean) - 1.0;
    let bias = total(&variant_mean) / total(&reference) - 1.0;
    println!(
        "ReSTIR GI, {what}: one frame's relMSE {base:.5} -> {variant:.5}; the means' total \
         light {shift:+.4} apart, the variant against the reference {bias:+.4}"
    );
    Some((variant / base, shift, bias))
}

#[test]
fn shading_both_samples_of_a_spatial_merge_keeps_the_mean_and_lowers_the_noise() {
    // Two spatial rays: the chosen sample shaded, then both. Without the own reservoir's
    // share, which the chosen sample shaded alone would get (with it, 0.029 against both
    // samples' 0.028).
    let Some((ratio, shift, bias)) =
        shading_variant("two spatial rays, both samples shaded", |s, both| {
            s.restir_gi.spatial_visibility = solari_restir::SpatialVisibility::Both;
            s.restir_gi.shade_both_samples = both;
            s.restir_gi.own_sample_share = 0.0;
        })
    else {
        return;
    };
    // The merge draws the same random numbers either way and only the shading differs, by
    // its expectation over the choice, but lavapipe's world cache (atomics landing in another
    // order) soon makes the two runs' histories differ: the means agree within their noise,
    // and one frame is less noisy. Measured here over six runs: the means −0.5% to +0.1%
    // apart, both −1.4% to −1.9% against the reference (the world cache's lag, as path GI's
    // in `the_indirect_view_is_what_the_gi_passes_add`), one frame's error 0.81–0.83 of the
    // chosen sample's (0.78–0.87 over 32 frames instead of 128).
    assert!(shift.abs() < 0.02, "{shift}");
    assert!(bias.abs() < 0.05, "{bias}");
    assert!(ratio < 0.9, "{ratio}");
}

#[test]
fn the_own_reservoirs_share_keeps_the_mean_and_lowers_the_noise() {
    // The default one-ray merge, shaded from the merge alone and half from the pixel's own
    // reservoir before it.
    let Some((ratio, shift, bias)) =
        shading_variant("the own reservoir's share 0 -> 0.5", |s, blend| {
            s.restir_gi.own_sample_share = if blend { 0.5 } else { 0.0 };
        })
    else {
        return;
    };
    // Two unbiased estimates blended: the same mean (within the runs' noise and the world
    // cache's lag, as above), less noise in one frame. Five runs here: the means −1.1% to
    // +0.8% apart, the blend −1.0% to −1.7% against the reference, one frame's error
    // 0.80–0.87 of the merge's alone.
    assert!(shift.abs() < 0.02, "{shift}");
    assert!(bias.abs() < 0.05, "{bias}");
    assert!(ratio < 0.92, "{ratio}");
}

#[test]
fn a_gi_ray_takes_a_glossy_hits_specular_layer_from_the_cache() {
    // The box's side walls made dark glossy dielectrics: much of the light they send back into
    // the room is their specular layer's. A GI ray's hit is lit by the world cache (irradiance
    // / π) and sends its directional albedo toward the ray times it; with the base colour
    // alone it would send only the diffuse share. The walls' pixels themselves take their
    // specular share through specular GI, which reuses the GI reservoir where rough.
    let mut scene = solari_scene::default_scene::cornell_box();
    for m in scene.materials.iter_mut() {
        if m.name == "red" || m.name == "green" {
            m.base_color = glam::Vec4::new(0.05, 0.05, 0.05, 1.0);
            m.dielectric_f0 = glam::Vec3::splat(0.04);
            m.dielectric_f90 = 1.0;
            m.roughness = 0.5;
        }
    }
    let Some(c) = Cornell::with_scene(scene) else {
        return;
    };
    let indirect_reference = reference(&c, 2, u32::MAX);
    let mean = path_gi_indirect_mean(&c, 32, 64);
    let bias = total(&mean) / total(&indirect_reference) - 1.0;
    let block = worst_block(&mean, &indirect_reference, 1.0 / 64.0);
    println!(
        "glossy side walls, indirect view against the indirect reference: total {bias:+.4}, \
         worst bright block {block:.4}"
    );
    // Lavapipe: +0.3% and +0.6% in total over two runs (worst bright block 10%); with the
    // base colour at the hit −5.7% (20%), one run. The bound sits halfway, each side a
    // margin of about twice the ±1% that lavapipe's means move from run to run.
    assert!(bias.abs() < 0.03, "{bias}");
}
