//! ReSTIR GI's knobs, each with its default and its cost.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;

/// Every knob of [`crate::RestirGi`]. With `temporal` and `spatial` both off it is plain
/// path GI: one traced sample per pixel, shaded as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestirGiSettings {
    /// Reuse last frame's reservoir at the reprojected pixel (default on).
    pub temporal: bool,
    /// Reuse one neighbour's reservoir (default on). Costs one visibility ray per pixel (two
    /// with [`SpatialVisibility::Both`]).
    ///
    /// Off, with temporal reuse on (the CLI's `--gi-reuse temporal`), the spatial pass only
    /// shades: on an H100 at 1920×1080 ReSTIR GI's passes took 0.44 ms on the Cornell box and
    /// 1.18 on `interior` instead of 0.63 and 1.97. One raw frame of indirect light was 8% and
    /// 15% noisier than with spatial reuse, and less noisy with a higher
    /// [`RestirGiSettings::confidence_cap`], but a pixel's frames are more alike (its samples
    /// come from its own chain alone): through the fallback denoiser the lit frame was 9% better
    /// than path GI's on the Cornell box and 8% worse on `interior`, and 14% and 13% worse with
    /// a cap of 32 (`benches/RESULTS.md`, "ReSTIR GI with temporal reuse only").
    pub spatial: bool,
    /// Permute the temporal source pixel within 4×4 blocks each frame (default off). Solari
    /// 0.17 found that DLSS-RR turns unpermuted GI reuse into blotches, so turn it on for
    /// DLSS-RR. It costs accuracy: the permuted pixel's history is reused without a visibility
    /// ray, which measured 0.8% darker on the Cornell box (48², 256-frame mean), and its
    /// single-frame error was 12% higher (`tests/gi.rs`).
    pub permutation_sampling: bool,
    /// Cap on the confidence history carries into a frame (default 8, Bevy's value): higher
    /// is smoother on static views, slower to follow moving light (there is no validation
    /// ray, so moving lights leave trails for about this many frames).
    pub confidence_cap: f32,
    /// First spatial search radius in pixels (default 30), halved after each rejected try.
    pub spatial_radius: f32,
    /// Neighbours tried before spatial reuse gives up for the pixel (default 5).
    pub spatial_tries: u32,
    /// Reuse is refused where either reconnection Jacobian exceeds this (default 2, Solari
    /// 0.17's). It is what keeps reuse from concentrating a sample's weight on pixels that
    /// see it at a much larger solid angle, the source of fireflies and overflow.
    pub jacobian_bound: f32,
    /// Longest GI ray (default unbounded); a miss is lit by the scene's environment.
    pub max_ray_distance: f32,
    /// Which visibility rays spatial reuse traces (default [`SpatialVisibility::Chosen`]: one
    /// ray, unbiased; the error of two rays at about the cost of the biased one ray).
    pub spatial_visibility: SpatialVisibility,
    /// Candidate rays per pixel for the initial sample (default 1, Solari's; 1 to
    /// [`MAX_GI_INITIAL_SAMPLES`]), combined by resampled importance sampling with the
    /// target function: the pixel keeps one of them, weighted as if sampled in proportion to
    /// the target. Each costs a ray and a cache query; with plain path GI this is how more
    /// samples per pixel are bought, and plain path GI shades the candidates' average (the
    /// kept one still goes to specular GI's rough pixels): one resampled sample keeps the
    /// colour of the surface it came from, a noise that more candidates do not lower
    /// (lavapipe's 128² Cornell box, indirect light, raw frame: relMSE 0.0228 with 16
    /// candidates resampled, 0.0154 + 0.120 / n in all). With 1 the initial pass is built without its
    /// resampling loop (9.5–14% faster on an H100 at 1080p); a change to or from 1 builds the
    /// pass again at the next frame.
    pub initial_samples: u32,
    /// How many of the pixels trace GI rays each frame: all (the default), half or a quarter,
    /// each pixel at that many times the weight on its frames ([`GiRate`], with the costs and
    /// errors of each). The CLI's `--gi-half-rate` and `--gi-quarter-rate`.
    pub rate: GiRate,
    /// With [`GiRate::Half`] and reuse, spatial reuse too at half the pixels (default on;
    /// nothing without a reduced rate): those that did not trace this frame,
    /// packed into whole warps, so each pixel gets one new sample or one neighbour's reservoir
    /// a frame and the spatial pass traces half its visibility rays (at
    /// [`GiRate::Quarter`], a quarter of the pixels, those one frame past their traced
    /// frame). The other pixels shade the reservoir temporal reuse left them, as a
    /// pixel that finds no neighbour does.
    ///
    /// The neighbours are taken from the pixels that did not trace either. A pixel's
    /// reservoir is at the low point of the checkerboard's cycle on the frames it does not
    /// trace (an empty sample merged in) and at the high point on the others (a sample at
    /// twice the weight); reusing only on the low frames, from neighbours of both kinds,
    /// pulled every pixel up: the mean of frames 121–136 read 1.030 of the reference's
    /// brightness on the Cornell box and 1.068 on `interior` (1.003 and 1.010 with spatial
    /// reuse at every pixel; H200, 960×540).
    ///
    /// On an H200 at 1920×1080 (`--gi restir --gi-half-rate`, fallback denoiser, medians of
    /// two reps): the spatial pass 18–34% faster (`interior` 0.913 → 0.607 ms, ReSTIR GI's
    /// two passes 1.59 → 1.28 ms; many_lights 0.459 → 0.329). relMSE against a 1024-spp
    /// full-bounce reference at 960×540: after 136 frames equal or lower (`interior` one
    /// frame 0.00755 → 0.00688, a 16-frame mean 0.00731 → 0.00687; the three small scenes
    /// −2.4% to +1.1%), frame 32 2–10% lower, frame 8 (young histories) up to 22% higher
    /// (`interior`; −0.5% to +12% elsewhere) (`benches/RESULTS.md`, "Spatial reuse at half
    /// rate"). A change builds the spatial pass again at the next frame.
    pub half_rate_spatial: bool,
    /// At half or quarter rate with temporal reuse, a pixel with no history to carry (a first
    /// frame, a reset, surface the view uncovered) traces this frame at its full-rate weight,
    /// on its phase or off it (default on). Without it such a pixel waits up to three frames
    /// for its phase, and one on its phase starts at the rate's scale, n times too bright.
    ///
    /// On an H200 (`benches/RESULTS.md`, "ReSTIR GI from a quarter of the pixels"): along the
    /// orbit camera, `interior`'s relMSE after 96 frames 0.01010 → 0.00795 at a quarter
    /// (every pixel 0.00755) and 0.00844 → 0.00781 at half rate. The temporal merge decides,
    /// having looked the history up anyway, and traces such a pixel itself; at reduced rates
    /// it looks for the history about the reprojected pixel too, so that a pixel at a
    /// silhouette under the still camera's jitter keeps it instead of tracing every frame.
    /// With `--gi restir` on `interior` at 1080p (`benches/RESULTS.md`, "Pixels without
    /// history, traced by the merge") the rule costs the initial pass 0.02–0.03 ms at a
    /// quarter (the two passes 0.989–0.999 ms, 0.969 with it off), against 0.117 when the
    /// tracing dispatch looked the history up itself; nothing changes at full rate or
    /// without reuse.
    pub trace_fresh_pixels: bool,
    /// A GI ray whose hit lies in a world-cache cell that holds no samples yet (a cell made
    /// this frame or not yet updated) draws no sample, with confidence 0, instead of a
    /// sample of no light with confidence 1 (default on; it changes nothing without reuse,
    /// where no confidence is kept). The cell's zero means nothing is known there yet;
    /// counted as darkness it kept a pixel's reuse dark for up to the confidence cap's
    /// frames while the cache filled. On an H100 (960×540, fallback denoiser, against a
    /// 1024-spp full-bounce reference) ReSTIR GI's relMSE at frame 8 fell 40% on the
    /// Cornell box, 28% on sun_boxes, 4% on many_lights and 31% on `interior`, and was
    /// unchanged (±1%) at frame 136 (`benches/RESULTS.md`, "ReSTIR GI's young frames
    /// mended"). Once the cache is warm such hits are rare (a surface no pixel has asked
    /// about for the cell lifetime); reuse then spreads the known light over them rather
    /// than counting them dark, as the cache itself will a frame later.
    pub ignore_cold_cells: bool,
    /// Temporal reuse caps the history's confidence by a cap its sample carries (default
    /// on): [`RestirGiSettings::confidence_cap`] where the world cache saw the light at
    /// the sample steady when it was traced, down to 1 where the cell's running luminance
    /// change was as large as its luminance (the rule by which the cache shortens its own
    /// averaging). A reused sample keeps the radiance it was traced with, so a long history
    /// lags light that changes, most while the cache fills after a start or a cut. The cap
    /// is read when the sample is traced, so samples traced while their light was steady
    /// keep the full cap until replaced: after a light is switched off it helped little
    /// (`solari-renderer`'s `restir_gi_follows_a_light_switched_off`, measured before
    /// light changes shortened histories: 0.36 of the light left after 16 frames against
    /// 0.42, path GI 0.28; a change of the lights now shortens every history for a few
    /// frames, [`crate::RestirGi::follow_light_change`]). It is read from the cell the
    /// sample's radiance came from, already loaded: +0.7–1.0% on the initial pass (a second
    /// cache lookup at reuse time cost 8–14%). With [`RestirGiSettings::ignore_cold_cells`], against neither, on an
    /// H100 (as there): relMSE at frame 8 −56% (Cornell box), −51% (sun_boxes), −10%
    /// (many_lights), −49% (`interior`), which brings ReSTIR GI's young frames level with
    /// path GI's; at frame 32 −59%, −44%, −1%, −51%. The cost is in long histories: a cap
    /// that depends on the sample weighs a history by what it holds, so this is not
    /// unbiased; the 16-frame mean after 120 frames measured −2%, −1%, +1% and **+7%** on
    /// `interior`, whose mean brightness rose from 0.974 to 1.003 of the reference.
    ///
    /// That cost is now confined to unsettled views: the cap stops once the view has held
    /// still for [`RestirGiSettings::adaptive_cap_settle_frames`] frames with no light
    /// change. On a settled view it had made the indirect light alone (the real-time
    /// renderer's indirect view against a `min_bounces: 2` reference, raw frames) 2.6%
    /// too bright on the Cornell box and 3.2% on `interior` on the H200, and 4–5% on
    /// lavapipe's 128² Cornell box, where stopping it leaves +0.7% (+0.2% with the cap off
    /// throughout) and the young frames as with the cap (`benches/RESULTS.md`, "GI's own
    /// error").
    pub adaptive_cap: bool,
    /// Frames a view must hold still (the same camera, history kept, and no scene or light
    /// change reported through [`crate::RestirGi::unsettle`] or
    /// [`crate::RestirGi::follow_light_change`]) before [`RestirGiSettings::adaptive_cap`]
    /// stops (default
    /// [`crate::ADAPTIVE_CAP_SETTLE_FRAMES`], 32; `u32::MAX` keeps the cap always, as before).
    /// The world cache's cells average 30 samples by default, so by then they have settled
    /// and the cap would only weigh histories by the light they hold.
    pub adaptive_cap_settle_frames: u32,
    /// Plain path GI (no reuse) shades its samples in a second dispatch instead of the one
    /// that traces them (default off; ignored with reuse, whose temporal merge is always a
    /// dispatch of its own). The tracing kernel then holds no shading state across the
    /// traversal, for a second read of the G-buffer. On an H100 at 1080p (defaults with the
    /// fallback denoiser, three reps) GI's pass took 7.9% less on `interior` (0.920 → 0.847 ms,
    /// the frame 3.825 → 3.752) and 0.9% less on many_lights, and 6.1% more on sun_boxes and
    /// 19% more on the Cornell box, whose traversal is trivial (`benches/RESULTS.md`, "The
    /// temporal merge in a dispatch of its own"). The images are the same. Ignored with more
    /// than one [`RestirGiSettings::initial_samples`]: their average is shaded as they are
    /// traced. The renderer
    /// turns it on by the scene's triangle count (`solari_renderer`'s
    /// `PATH_GI_SHADE_APART_TRIANGLES`). A change builds the pass again at the next frame.
    pub shade_apart: bool,
    /// With two-ray spatial visibility ([`SpatialVisibility::Both`] or
    /// [`SpatialVisibility::Neighbour`]), the spatial pass shades both samples of its merge,
    /// each weighted by its resampling weight (Σ w_i · f(y_i) / p̂(y_i)), instead of the chosen
    /// sample alone (f(y) · W). That is the chosen sample's light averaged over the merge's
    /// choice (Rao–Blackwellisation): the same expectation, never more variance, and the
    /// choice and the history it leaves are unchanged. It matters most for colour: a
    /// reservoir holds one sample, and its target is a luminance, so a single shaded sample
    /// carries the colour of the one surface it came from (the Cornell box's red or green
    /// wall) however long its history; that colour noise does not fall with more reuse.
    /// `Chosen` traces one of the two rays and cannot shade the other sample (ignored there).
    /// On an H200 (the indirect light alone, raw frame 136 at 960×540) it took `Both`'s
    /// relMSE from 13.91 to 9.91 ×10⁻³ on the Cornell box and from 53.84 to 52.54 on
    /// `interior`, whose indirect light has little colour; lavapipe's 128² Cornell box
    /// 0.0323 → 0.0249, chroma alone 0.0172 → 0.0108 (`benches/RESULTS.md`, "Colour noise").
    /// It costs a few arithmetic operations.
    pub shade_both_samples: bool,
    /// Where the spatial merge shades its chosen sample alone ([`SpatialVisibility::Chosen`],
    /// or [`RestirGiSettings::shade_both_samples`] off), the share of a reusing pixel's light
    /// taken from its own reservoir before spatial reuse (its sample's contribution times its
    /// W), the rest from the merge's result (default 0.5; 0 shades the merge alone, as
    /// before). Both are unbiased estimates of the pixel's light, so any share keeps the
    /// mean; the blend shades two samples where the merge chose the neighbour's, and the two
    /// estimates' noise is only partly shared. Pixels without a neighbour shade their own
    /// reservoir whatever the share; a merge shaded over its choice holds both samples
    /// already, in balance, and ignores it (blended, the Cornell box's raw frame read 2% worse
    /// and `interior`'s 3% better, within the runs' noise).
    ///
    /// On an H200 (the indirect light alone, raw frame 136 at 960×540; `benches/RESULTS.md`,
    /// "Colour noise") the default one-ray merge's relMSE fell from 14.76 to 11.78 ×10⁻³ on the
    /// Cornell box and from 65.5 to 57.3 on `interior` (16-frame means −4% and −5%). The own
    /// sample's value comes from the merge's terms, so the blend costs a multiply-add: when
    /// it was evaluated again the spatial pass read 0.967 ms on `interior` at 1920×1080 and
    /// 0.282 on the Cornell box, now 0.926 and 0.274 (`benches/RESULTS.md`, "The spatial
    /// merge as history").
    pub own_sample_share: f32,
    /// Next frame's history is the reservoir spatial reuse made (true, the default and the
    /// seeds' way), or the pixel's own from before it (false), so that each pixel's temporal
    /// chain holds its own samples and spatial reuse only shades. Fed back, the spatial
    /// merge's reservoir returns through later merges with its confidence counted again, so
    /// neighbours come to hold the same samples; kept apart, one frame is less noisy but a
    /// pixel's frames are more alike. Specular GI's rough pixels shade the same reservoirs
    /// ([`crate::RestirGi::reservoirs`]), so off they too shade each pixel's own.
    ///
    /// On an H200 (`benches/RESULTS.md`, "The spatial merge as history"; the indirect light
    /// alone at 960×540, relMSE ×10⁻³ without the reference's noise, the one-ray default
    /// otherwise) the pixel's own history took the Cornell box's raw frame 136 from 11.68 to
    /// 9.95 but its 16-frame mean from 3.07 to 4.62, and `interior`'s raw frame from 56.6 to
    /// 59.6, its mean from 13.9 to 21.2; the lit frame with the fallback denoiser was equal on
    /// the Cornell box (0.0972 → 0.0971) and 9% worse on `interior` (2.00 → 2.19). Kept on.
    pub spatial_history: bool,
    /// How a GI ray's hit on a glossy metal ([`RestirGiSettings::glossy_hit_roughness`]) is
    /// lit: [`GlossyHits::Cache`] (the default) as every other hit.
    ///
    /// The default by measurement (an H100 at 1080p, path GI and the fallback denoiser;
    /// `benches/RESULTS.md`, "GI's glossy hits timed"): [`GlossyHits::Lights`] made GI's
    /// initial pass 6–45% slower and [`GlossyHits::Path`] 10–136% (`interior` 0.87 → 0.98 and
    /// 1.43 ms), and the denoised frame's relMSE at 960×540 was 12–30% higher on sun_boxes and
    /// 1–8% lower on `interior`: the metal's glint comes back in the mean but arrives in few
    /// pixels at a time.
    pub glossy_hits: GlossyHits,
    /// The glossy metals of [`RestirGiSettings::glossy_hits`]: metallic at least 0.5 and
    /// roughness below this (default 0.5; above 0, at most 1).
    pub glossy_hit_roughness: f32,
}

/// How many of the pixels trace GI rays each frame ([`RestirGiSettings::rate`]). At a reduced
/// rate each pixel traces one frame in two or four at that many times the weight, so every
/// frame's estimate stays unbiased over the cycle; with reuse,
/// [`RestirGiSettings::half_rate_spatial`] runs spatial reuse at the same share of the pixels
/// and [`RestirGiSettings::trace_fresh_pixels`] lets a pixel without history trace at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GiRate {
    /// Every pixel traces every frame (the default).
    #[default]
    Full,
    /// Half the pixels trace each frame, a checkerboard that flips every frame, at twice the
    /// weight; the others draw no sample that frame. The tracing pixels are packed into whole
    /// warps, so the tracing work halves.
    ///
    /// - Plain path GI (no reuse): unbiased, and the denoiser's filters fill the gaps. On
    ///   an H100 at 1080p GI's first pass took 0.60 ms instead of 1.03 on `interior` (the
    ///   default frame 4.49 ms instead of 4.91) and 0.32 instead of 0.51 on many_lights. The
    ///   cost is noise, most where histories are young: relMSE against the full-bounce
    ///   reference (960×540, fallback denoiser) rose 11% on interior's 8th frame, 3.4% on
    ///   its 136th and 1.9% on a 16-frame mean; 8–20% on the Cornell box and sun_boxes
    ///   (`benches/RESULTS.md`, "Path GI from half the pixels").
    /// - With reuse: an untraced pixel's reservoir is empty with confidence 1 (it drew a
    ///   sample worth nothing) and is merged with its temporal history as usual, so each
    ///   frame's reservoirs stay unbiased over the checkerboard's two phases (a pixel's
    ///   expected brightness alternates by about ±1/(2·cap + 1) between them, which the
    ///   denoiser averages out). ReSTIR GI's two passes on an H100 at 1080p: many_lights
    ///   0.94 ms instead of 1.14, interior 1.86 instead of 2.29; relMSE −2% to +2.5% of the
    ///   full rate's on frame 136 and on a 16-frame mean, 2–5% above it on frame 8
    ///   (`benches/RESULTS.md`, "ReSTIR GI from half the pixels").
    Half,
    /// A quarter of the pixels trace each frame: each pixel traces one frame in four, at four
    /// times the weight, where (x + 2y + frame) mod 4 is 0 (a pixel's phase: the frames since
    /// it traced), and the tracing pixels are packed into whole warps as at half rate. With
    /// [`RestirGiSettings::half_rate_spatial`] and reuse, spatial reuse runs at the pixels of
    /// phase 1 (the frame after they traced), from neighbours of that phase. Unbiased over the
    /// cycle as half rate is.
    ///
    /// On an H200 at 1920×1080 (`--gi restir --gi-quarter-rate`, fallback denoiser, medians
    /// of two reps; `benches/RESULTS.md`, "ReSTIR GI from a quarter of the pixels"): its two
    /// passes on `interior` 0.964 ms against 1.274 at half rate (0.521 + 0.443 ms; both with
    /// [`RestirGiSettings::trace_fresh_pixels`] off, which now adds 0.02–0.03 ms at a quarter:
    /// 0.989–0.999 ms, and half rate's 1.30 ms), on many_lights 0.603 against 0.703 and
    /// sun_boxes 0.557 against 0.606; on the Cornell box,
    /// whose traversal costs little, 0.493 against 0.465 (the spatial pass's threads serve
    /// four pixels each in turn). relMSE against a 1024-spp full-bounce reference at 960×540:
    /// after 136 frames within −4% to +9% of half rate's (`interior`'s 16-frame mean 0.00679
    /// against 0.00682; the Cornell box's 0.000255 against 0.000233), frame 32 at most 1%
    /// higher (`interior` 0.00739 against 0.00859), frame 8 from 35% lower (the Cornell box)
    /// to 15% higher (sun_boxes; `interior` +5%). Under a moving camera (the orbit path, a
    /// reference per frame) a quarter costs more: `interior` after 96 frames 0.01005 against
    /// 0.00855 at half rate and 0.00755 at every pixel, without `trace_fresh_pixels`; with
    /// it (the default) 0.00795 and 0.00781, and 0.0080–0.0081 at a quarter with the
    /// neighbour search that made it cheap. With plain path GI a quarter costs
    /// more than it saves: `interior`'s 16-frame mean 0.00712 against 0.00654 at full rate,
    /// frame 8 0.0385 against 0.0212. (These relMSE figures carry the 1024-spp references'
    /// own noise, about 4.6×10⁻³ on `interior`'s still camera and 0.12×10⁻³ on the Cornell
    /// box, so their ratios understate the differences; without it, against 4096-spp
    /// references, a quarter's still `interior` reads 6% above plain path GI at full rate
    /// and its orbit 11–13%: `benches/RESULTS.md`, "The reference's own noise".)
    Quarter,
}

impl GiRate {
    /// log2 of the frames between a pixel's traced frames: 0, 1 or 2 (the shader's
    /// `rate_shift`).
    pub fn shift(self) -> u32 {
        match self {
            Self::Full => 0,
            Self::Half => 1,
            Self::Quarter => 2,
        }
    }

    /// Frames between a pixel's traced frames: 1, 2 or 4.
    pub fn interval(self) -> u32 {
        1 << self.shift()
    }

    /// Whether fewer than all the pixels trace each frame.
    pub fn reduced(self) -> bool {
        self != Self::Full
    }
}

/// Which visibility rays ReSTIR GI's spatial reuse traces between the pixel (`c`, its own
/// sample y_c) and the chosen neighbour (`o`, its sample y_o). Reuse weighs the two samples
/// by balance-heuristic MIS weights, which need to know whether each pixel could have
/// produced the other's sample, that is, whether it sees it.
///
/// Measured on an H100 at 1920×1080 (`benches/RESULTS.md`, "One visibility ray in ReSTIR
/// GI's spatial reuse"; error at 960×540 against a 1024-spp full-bounce reference, fallback
/// denoiser): `Chosen` takes 18–34% off the spatial pass against `Both` (ReSTIR GI 0.61 ms on
/// the Cornell box, 0.91 on sun_boxes, 1.16 on many_lights, 2.31 on interior), its spatial
/// pass within 4% of `Neighbour`'s time, with `Both`'s error (relMSE of one frame within
/// ±2.4% of it, of a 16-frame mean within −1.3% to +3.1%, on all four scenes; `Neighbour`'s
/// is 20–31% higher on three of them and darkens interior by 3.5%). With two rays the
/// spatial pass can shade both samples of its merge ([`RestirGiSettings::shade_both_samples`],
/// on by default), which `Chosen` cannot: on an H200 (the indirect light alone, raw frame 136
/// at 960×540, GI ms at 1920×1080; `benches/RESULTS.md`, "Colour noise") `Both` read relMSE
/// 9.91 ×10⁻³ on the Cornell box against `Chosen`'s 14.96, for 0.659 ms against 0.577
/// (1.32× as efficient), and 52.5 against 64.4 on `interior` for 2.471 ms against 1.928
/// (0.96×). `Chosen` then gained [`RestirGiSettings::own_sample_share`]; measured again
/// with it (`benches/RESULTS.md`, "The spatial merge as history": errors from one call, GI
/// ms from another) `Chosen` read 11.68 on the Cornell box for 0.579 ms and 56.6 on
/// `interior` for 1.938 ms, `Both` 9.90 for 0.669 and 52.0 for 2.519: `Both` 1.02× as
/// efficient on the Cornell box, 0.84× on `interior`. `Chosen` stays the default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpatialVisibility {
    /// Two rays: y_o from the pixel (a hidden y_o cannot be chosen) and y_c from the
    /// neighbour (a neighbour that cannot see y_c does not count in y_c's MIS weight).
    /// Unbiased, and the weights are exact before the choice (each ray is skipped where its
    /// answer cannot change the merge).
    Both,
    /// One ray, for the sample the merge chooses (the default): the choice is made as if
    /// both pixels saw both samples, then the chosen sample's ray corrects its weight (y_c
    /// hidden from the neighbour: its MIS weight becomes 1; y_o hidden from the pixel: the
    /// pixel's light is zero this frame and it keeps an empty reservoir). Unbiased: over the
    /// choice, its expectation is `Both`'s. The empty reservoirs make a pixel's frames a
    /// little more alike: on the 48² Cornell box of `tests/gi.rs` a 256-frame mean is
    /// 0–6% further from the reference than with two rays (one frame: no difference).
    #[default]
    Chosen,
    /// One ray, y_o from the pixel; the neighbour counts in y_c's MIS weight as if it saw
    /// y_c. Biased: darkens indirect light near occluders.
    Neighbour,
}

impl SpatialVisibility {
    /// The name the CLI and reports use (`both`, `chosen`, `neighbour`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Both => "both",
            Self::Chosen => "chosen",
            Self::Neighbour => "neighbour",
        }
    }

    /// The setting [`SpatialVisibility::name`] names, if any.
    pub fn parse(name: &str) -> Option<Self> {
        [Self::Both, Self::Chosen, Self::Neighbour]
            .into_iter()
            .find(|v| v.name() == name)
    }
}

/// How a GI ray's hit on a glossy metal is lit ([`RestirGiSettings::glossy_hits`]).
///
/// Every other hit sends its directional albedo times the world cache's irradiance toward the
/// pixel: what it reflects under uniform light. A glossy metal reflects a light into a narrow
/// cone, so that model spreads a sun's reflection over every direction, and the surfaces it
/// should light read dark: on a floor beside a gold block in the sun (`tests/gi.rs`) the cache
/// gives 0.32 of the reference's indirect light; near sun_boxes' gold sphere 0.92
/// (`benches/RESULTS.md`). A mirror (roughness under the BRDF's mirror threshold, 0.02) keeps
/// the cache's model under every setting: no light sample lands in its delta lobe, and its one
/// ray finds a sun's disc only where the mirror happens to point at it, a caustic too noisy
/// to trace this way. The radiance of a glossy hit depends on direction, but reuse still
/// carries a sample's radiance to neighbours and later frames unchanged, as for every hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GlossyHits {
    /// The cache's irradiance through the directional albedo, as at every hit (no extra ray).
    #[default]
    Cache,
    /// One light-tile sample through the metal's BRDF (a shadow ray), plus the cache's
    /// irradiance from everything but the light list through the directional albedo: direct
    /// light exact, the rest under the uniform model.
    Lights,
    /// One light-tile sample through the BRDF, MIS-weighted against one BRDF-sampled bounce
    /// whose hit gives its emission and its directional albedo times the cache (a shadow ray
    /// and a bounce ray): both direct and indirect light through the BRDF, noisier.
    Path,
}

impl GlossyHits {
    /// The name the CLI and reports use (`cache`, `lights`, `path`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Cache => "cache",
            Self::Lights => "lights",
            Self::Path => "path",
        }
    }

    /// The setting [`GlossyHits::name`] names, if any.
    pub fn parse(name: &str) -> Option<Self> {
        [Self::Cache, Self::Lights, Self::Path]
            .into_iter()
            .find(|v| v.name() == name)
    }

    /// The value of the initial pass's pipeline constant `GI_GLOSSY_HITS`.
    pub(crate) fn constant(self) -> f64 {
        match self {
            Self::Cache => 0.0,
            Self::Lights => 1.0,
            Self::Path => 2.0,
        }
    }
}

/// Most initial GI candidates per pixel (the shader loop's bound).
pub const MAX_GI_INITIAL_SAMPLES: u32 = 16;

impl Default for RestirGiSettings {
    fn default() -> Self {
        Self {
            temporal: true,
            spatial: true,
            permutation_sampling: false,
            confidence_cap: 8.0,
            spatial_radius: 30.0,
            spatial_tries: 5,
            jacobian_bound: 2.0,
            max_ray_distance: f32::MAX,
            spatial_visibility: SpatialVisibility::Chosen,
            initial_samples: 1,
            rate: GiRate::Full,
            half_rate_spatial: true,
            trace_fresh_pixels: true,
            ignore_cold_cells: true,
            adaptive_cap: true,
            adaptive_cap_settle_frames: crate::ADAPTIVE_CAP_SETTLE_FRAMES,
            shade_apart: false,
            shade_both_samples: true,
            own_sample_share: 0.5,
            spatial_history: true,
            glossy_hits: GlossyHits::Cache,
            glossy_hit_roughness: 0.5,
        }
    }
}

impl RestirGiSettings {
    /// log2 of the frames between a pixel's traced frames ([`GiRate::shift`]).
    pub fn rate_shift(&self) -> u32 {
        self.rate.shift()
    }

    /// Plain path GI: the same initial sample with no reuse.
    pub fn plain() -> Self {
        Self {
            temporal: false,
            spatial: false,
            ..Self::default()
        }
    }

    /// Whether any reuse is on (off: plain path GI).
    pub fn reuse(&self) -> bool {
        self.temporal || self.spatial
    }

    /// Checks every knob is in range; the error names the bad one.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |what: String| Err(GpuError::Validation(format!("ReSTIR GI settings: {what}")));
        crate::settings::check_reuse(
            "ReSTIR GI",
            self.spatial_tries,
            self.confidence_cap,
            self.spatial_radius,
        )?;
        if !(self.jacobian_bound.is_finite() && self.jacobian_bound >= 1.0) {
            return bad(format!(
                "jacobian_bound is {}, expected a finite value of at least 1",
                self.jacobian_bound
            ));
        }
        if !(1..=MAX_GI_INITIAL_SAMPLES).contains(&self.initial_samples) {
            return bad(format!(
                "initial_samples is {}, expected 1 to {MAX_GI_INITIAL_SAMPLES}",
                self.initial_samples
            ));
        }
        if !(0.0..=1.0).contains(&self.own_sample_share) {
            return bad(format!(
                "own_sample_share is {}, expected 0 to 1",
                self.own_sample_share
            ));
        }
        if !(self.glossy_hit_roughness > 0.0 && self.glossy_hit_roughness <= 1.0) {
            return bad(format!(
                "glossy_hit_roughness is {}, expected above 0, at most 1",
                self.glossy_hit_roughness
            ));
        }
        if self.max_ray_distance.is_nan() || self.max_ray_distance <= 0.0 {
            return bad(format!(
                "max_ray_distance is {}, expected a positive distance",
                self.max_ray_distance
            ));
        }
        Ok(())
    }
}

/// `GI_FLAG_*` in `restir_gi.wesl` beyond the reuse bits shared with DI
/// (`settings::flags::reuse`).
pub(crate) mod flags {
    /// [`super::SpatialVisibility::Both`]: the neighbour's view of the pixel's sample too.
    pub const UNBIASED_SPATIAL: u32 = 16;
    // (64 was CHOSEN_VISIBILITY: `SpatialVisibility::Chosen` is a spatial pipeline of its
    // own, `gi::CHOSEN_ONLY`.)
    /// [`super::GiRate`] below full: a reduced rate (the uniform's `rate_shift` says which).
    pub const HALF_RATE: u32 = 128;
    /// [`super::RestirGiSettings::ignore_cold_cells`].
    pub const IGNORE_COLD: u32 = 256;
    /// [`super::RestirGiSettings::adaptive_cap`].
    pub const ADAPTIVE_CAP: u32 = 512;
    /// [`super::RestirGiSettings::trace_fresh_pixels`].
    pub const TRACE_FRESH: u32 = 1024;
    /// `RestirGi::set_indirect_only`: a ray that misses carries no sky.
    pub const INDIRECT_ONLY: u32 = 2048;
    /// [`super::RestirGiSettings::shade_both_samples`] (with two spatial rays).
    pub const SHADE_BOTH: u32 = 4096;
    /// GI_FLAG_SPATIAL_HISTORY: [`super::RestirGiSettings::spatial_history`].
    pub const SPATIAL_HISTORY: u32 = 8192;
}

/// WGSL twin: `GiParams` in `restir_gi.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuGiParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame index (seeds random numbers).
    pub frame: u32,
    /// `GI_FLAG_*` bits.
    pub flags: u32,
    /// [`RestirGiSettings::spatial_radius`].
    pub spatial_radius: f32,
    /// [`RestirGiSettings::confidence_cap`].
    pub confidence_cap: f32,
    /// [`RestirGiSettings::spatial_tries`].
    pub spatial_tries: u32,
    /// [`RestirGiSettings::jacobian_bound`].
    pub jacobian_bound: f32,
    /// [`RestirGiSettings::max_ray_distance`].
    pub max_ray_distance: f32,
    /// [`RestirGiSettings::initial_samples`].
    pub initial_samples: u32,
    /// The most confidence temporal reuse gives a history this frame:
    /// [`RestirGiSettings::confidence_cap`], or 1 for a few frames after
    /// `RestirGi::follow_light_change` (samples keep carrying caps from `confidence_cap`).
    pub history_cap: f32,
    /// [`RestirGiSettings::rate_shift`].
    pub rate_shift: u32,
    /// [`RestirGiSettings::own_sample_share`].
    pub own_share: f32,
    /// Light-tile samples in all, for the light samples at glossy hits.
    pub tile_samples: u32,
    /// [`RestirGiSettings::glossy_hit_roughness`].
    pub glossy_roughness: f32,
    /// Pads the uniform to a multiple of 16 bytes.
    pub pad: u32,
}

const _: () = assert!(size_of::<GpuGiParams>() == 64);

#[cfg(test)]
mod tests {
    use super::flags;
    use crate::settings::flags as shared;

    /// Every `GI_FLAG_*` that `restir_gi.wesl` declares has its Rust twin with the same bit,
    /// and every Rust GI flag has its WGSL one: a flag set on one side only would switch on
    /// nothing, or something else.
    #[test]
    fn gi_flags_match_the_shader() {
        let rust = [
            ("TEMPORAL", shared::TEMPORAL),
            ("SPATIAL", shared::SPATIAL),
            ("PERMUTATION", shared::PERMUTATION),
            ("HISTORY", shared::HISTORY),
            ("UNBIASED_SPATIAL", flags::UNBIASED_SPATIAL),
            ("HALF_RATE", flags::HALF_RATE),
            ("IGNORE_COLD", flags::IGNORE_COLD),
            ("ADAPTIVE_CAP", flags::ADAPTIVE_CAP),
            ("TRACE_FRESH", flags::TRACE_FRESH),
            ("INDIRECT_ONLY", flags::INDIRECT_ONLY),
            ("SHADE_BOTH", flags::SHADE_BOTH),
            ("SPATIAL_HISTORY", flags::SPATIAL_HISTORY),
        ];
        let wgsl: Vec<(&str, u32)> = include_str!("../shaders/restir_gi.wesl")
            .lines()
            .filter_map(|line| {
                let rest = line.trim().strip_prefix("const GI_FLAG_")?;
                let (name, value) = rest.split_once(": u32 = ")?;
                Some((name, value.strip_suffix("u;")?.parse().ok()?))
            })
            .collect();
        assert_eq!(wgsl.len(), rust.len(), "WGSL declares {wgsl:?}");
        for (name, bit) in rust {
            let found = wgsl.iter().find(|(n, _)| *n == name).map(|f| f.1);
            assert_eq!(found, Some(bit), "GI_FLAG_{name}");
        }
        let mut bits: Vec<u32> = rust.iter().map(|r| r.1).collect();
        bits.sort_unstable();
        bits.dedup();
        assert_eq!(bits.len(), rust.len(), "two flags share a bit");
    }
}
