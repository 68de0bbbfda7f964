//! The DLSS-RR copy passes (`dlss_io`) on lavapipe, without DLSS: the input copy's textures
//! are read back and checked against the G-buffer of the grey box and a lighting buffer with
//! adversarial values; the output copy is fed a texture the test uploads.

use glam::Vec3;
use solari_denoise::dlss_io::{DlssTextures, INPUT_FORMATS, OUTPUT_FORMAT};

mod common;

use common::{Harness, SIZE, grey_box};

const N: usize = (SIZE * SIZE) as usize;

/// f16 bits to f32 (subnormals, infinities and NaN included).
fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let mantissa = (h & 0x3ff) as f32;
    sign * match exp {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

/// f32 to f16 bits for values f16 represents exactly (the test's own).
fn f32_to_f16(v: f32) -> u16 {
    if v == 0.0 {
        return 0;
    }
    let bits = v.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    assert!(
        (1..31).contains(&exp) && bits & 0x1fff == 0,
        "{v} is not a normal f16"
    );
    sign | ((exp as u16) << 10) | ((bits >> 13) & 0x3ff) as u16
}

fn f16s(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks(2)
        .map(|b| f16_to_f32(u16::from_le_bytes([b[0], b[1]])))
        .collect()
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytemuck::cast_slice(bytes).to_vec()
}

// The lighting value of pixel `i`: finite, negative, over f16's range, NaN and infinite, in
// turn.
fn lighting(i: usize) -> [f32; 4] {
    match i % 6 {
        0 => [1.5, 0.25, 3.0, 1.0],
        1 => [-1.0, 0.5, 0.0, 1.0],
        2 => [1.0e6, 2.0, 1.0, 1.0],
        3 => [f32::NAN, 1.0, 1.0, 1.0],
        4 => [f32::INFINITY, 1.0, 1.0, 1.0],
        _ => [0.125, f32::NEG_INFINITY, 0.5, 1.0],
    }
}

fn expected_colour(i: usize) -> [f32; 3] {
    match i % 6 {
        0 => [1.5, 0.25, 3.0],
        1 => [0.0, 0.5, 0.0],
        2 => [65504.0, 2.0, 1.0],
        // A non-finite channel zeroes the pixel.
        _ => [0.0; 3],
    }
}

#[test]
fn the_input_copy_writes_what_dlss_reads() {
    let Some(mut h) = Harness::new() else { return };
    let mut textures = DlssTextures::new(&h.gpu, (SIZE, SIZE), (SIZE, SIZE)).expect("textures");
    let input: Vec<[f32; 4]> = (0..N).map(lighting).collect();
    // Frame 1 at the scene's camera, frame 2 a step to the camera's right: motion is known in
    // sign.
    let mut run = |h: &mut Harness| {
        let mut encoder = h.gbuffer_encoder();
        let buffer = h.write_lighting(&input).clone();
        textures
            .encode_inputs(&h.gpu, &mut encoder, None, &buffer, h.gbuffer())
            .expect("encode");
        h.gpu.queue.submit([encoder.finish()]);
        (0..INPUT_FORMATS.len())
            .map(|k| {
                h.gpu
                    .read_texture(&textures.inputs[k].0, wgpu::TextureAspect::All)
                    .expect("read")
            })
            .collect::<Vec<_>>()
    };
    run(&mut h);
    let right = grey_box()
        .camera(None)
        .expect("camera")
        .transform
        .x_axis
        .truncate();
    h.camera_offset = 0.05 * right;
    let t = run(&mut h);
    let colour = f16s(&t[0]);
    let (diffuse, specular) = (&t[1], &t[2]);
    let normal = f16s(&t[3]);
    let depth = f32s(&t[4]);
    let motion = f32s(&t[5]);

    let scene = grey_box();
    let roughness = scene.materials[0].roughness;
    assert!(
        scene.materials.iter().all(|m| m.roughness == roughness),
        "the test assumes one roughness"
    );
    let (mut surfaces, mut moving_left) = (0, 0);
    for i in 0..N {
        let c = &colour[4 * i..4 * i + 4];
        let want = expected_colour(i);
        for k in 0..3 {
            assert!(
                (c[k] - want[k]).abs() <= 1e-3 * want[k].max(1.0),
                "pixel {i}: colour {c:?}, want {want:?} (input {:?})",
                lighting(i)
            );
        }
        assert_eq!(c[3], 1.0, "pixel {i}: colour alpha");
        let background = depth[i] >= 1.0e29;
        if background {
            assert_eq!(diffuse[4 * i + 3], 0, "pixel {i}: background albedo alpha");
            continue;
        }
        surfaces += 1;
        assert!(
            depth[i].is_finite() && depth[i] > 0.0,
            "pixel {i}: depth {}",
            depth[i]
        );
        // Grey dielectric: diffuse albedo 0.5 (8-bit), specular albedo its F0, alpha 1.
        let d = &diffuse[4 * i..4 * i + 4];
        assert!(
            d[..3]
                .iter()
                .all(|v| (*v as f32 / 255.0 - 0.5).abs() < 0.01)
                && d[3] == 255,
            "pixel {i}: diffuse albedo {d:?}"
        );
        let s = &specular[4 * i..4 * i + 4];
        assert!(
            s[..3].iter().all(|v| *v as f32 / 255.0 <= 0.05) && s[3] == 255,
            "pixel {i}: specular albedo {s:?}"
        );
        let n = Vec3::new(normal[4 * i], normal[4 * i + 1], normal[4 * i + 2]);
        assert!((n.length() - 1.0).abs() < 0.01, "pixel {i}: normal {n}");
        assert!(
            (normal[4 * i + 3] - roughness).abs() < 0.01,
            "pixel {i}: roughness {}",
            normal[4 * i + 3]
        );
        let m = [motion[2 * i], motion[2 * i + 1]];
        assert!(m.iter().all(|v| v.is_finite()), "pixel {i}: motion {m:?}");
        // The camera stepped right: what it sees moved left on screen (uv now − uv before).
        moving_left += (m[0] < 0.0) as usize;
    }
    println!("DLSS input copy: {surfaces} surface pixels, {moving_left} moving left");
    assert!(surfaces > N / 2, "only {surfaces} surface pixels");
    assert_eq!(moving_left, surfaces, "every surface should move left");
}

#[test]
fn the_output_copy_reads_every_texel_into_the_buffer() {
    let Some(h) = Harness::new() else { return };
    // An output twice the input size, as an upscaling DLSS would write.
    let (w, hgt) = (2 * SIZE + 3, 2 * SIZE);
    let textures = DlssTextures::new(&h.gpu, (SIZE, SIZE), (w, hgt)).expect("textures");
    let value = |x: u32, y: u32, c: u32| (x + 2 * y + 4 * c) as f32 * 0.25;
    let mut texels = Vec::new();
    for y in 0..hgt {
        for x in 0..w {
            for c in 0..4 {
                texels.extend(f32_to_f16(value(x, y, c)).to_le_bytes());
            }
        }
    }
    let texel = OUTPUT_FORMAT.block_copy_size(None).expect("plain format");
    h.gpu.queue.write_texture(
        textures.output_texture.0.as_image_copy(),
        &texels,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * texel),
            rows_per_image: Some(hgt),
        },
        textures.output_texture.0.size(),
    );
    let mut encoder = h.gpu.device.create_command_encoder(&Default::default());
    textures.encode_output(&mut encoder, None);
    h.gpu.queue.submit([encoder.finish()]);
    let bytes = h
        .gpu
        .read_buffer(&textures.output, (w * hgt * 16) as u64)
        .expect("read");
    let out: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    for y in 0..hgt {
        for x in 0..w {
            let got = out[(y * w + x) as usize];
            // Alpha is 1 everywhere: DLSS's alpha carries nothing, and at the output
            // resolution there is no surface mask to write.
            let want = [value(x, y, 0), value(x, y, 1), value(x, y, 2), 1.0];
            assert_eq!(got, want, "texel ({x}, {y})");
        }
    }
}
