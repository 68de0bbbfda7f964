//! Environment map files: what loads, what is refused with which message, and the fallbacks
//! (repaired texels, reduction) the module docs promise.

use glam::Vec3;
use solari_scene::environment::MAX_FILE_TEXELS;
use solari_scene::{EnvironmentMap, EnvironmentOptions, SceneError};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("solari-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn pattern(w: u32, h: u32) -> Vec<Vec3> {
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            Vec3::new(
                0.1 + x / w as f32,
                0.2 + y / h as f32 * 4.0,
                3.0 + (x * y) % 5.0,
            )
        })
        .collect()
}

fn write_hdr(path: &Path, w: u32, h: u32, texels: &[Vec3]) {
    let pixels: Vec<image::Rgb<f32>> = texels.iter().map(|t| image::Rgb(t.to_array())).collect();
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, w as usize, h as usize)
        .unwrap();
}

fn write_exr(path: &Path, w: u32, h: u32, texels: &[Vec3]) {
    let data: Vec<f32> = texels.iter().flat_map(|t| t.to_array()).collect();
    image::Rgb32FImage::from_raw(w, h, data)
        .unwrap()
        .save_with_format(path, image::ImageFormat::OpenExr)
        .unwrap();
}

fn load_err(path: &Path) -> String {
    match EnvironmentMap::load(path, &EnvironmentOptions::default()) {
        Ok(m) => panic!(
            "{} loaded as {} x {}",
            path.display(),
            m.width(),
            m.height()
        ),
        Err(e @ SceneError::Environment { .. }) => e.to_string(),
        Err(e) => panic!("wrong error kind: {e:?}"),
    }
}

#[test]
fn hdr_and_exr_files_load_as_written() {
    let (w, h) = (16, 8);
    let texels = pattern(w, h);
    let hdr = scratch("sky.hdr");
    write_hdr(&hdr, w, h, &texels);
    let map = EnvironmentMap::load(&hdr, &EnvironmentOptions::default()).unwrap();
    assert_eq!((map.width(), map.height()), (w, h));
    for (a, b) in map.texels().iter().zip(&texels) {
        // RGBE keeps 8 bits of mantissa under a shared exponent.
        assert!(
            (*a - *b).abs().max_element() <= b.max_element() / 100.0,
            "{a} vs {b}"
        );
    }
    let exr = scratch("sky.exr");
    write_exr(&exr, w, h, &texels);
    let map = EnvironmentMap::load(&exr, &EnvironmentOptions::default()).unwrap();
    assert_eq!(map.texels(), &texels[..]);
    assert_eq!(map.repaired_texels(), 0);
}

#[test]
fn unusable_texels_are_repaired_and_counted() {
    let mut texels = pattern(4, 2);
    texels[1] = Vec3::new(f32::NAN, 1.0, 1.0);
    texels[5] = Vec3::new(-2.0, f32::INFINITY, 1.0);
    let path = scratch("bad_texels.exr");
    write_exr(&path, 4, 2, &texels);
    let map = EnvironmentMap::load(&path, &EnvironmentOptions::default()).unwrap();
    assert_eq!(map.repaired_texels(), 2);
    assert!(
        map.texels()
            .iter()
            .all(|t| t.is_finite() && t.min_element() >= 0.0)
    );
    assert_eq!(map.texel(1, 0), Vec3::new(0.0, 1.0, 1.0));
}

#[test]
fn wide_maps_are_reduced_keeping_their_mean() {
    let (w, h) = (64, 32);
    let texels = pattern(w, h);
    let path = scratch("wide.exr");
    write_exr(&path, w, h, &texels);
    let full = EnvironmentMap::load(&path, &EnvironmentOptions::default()).unwrap();
    let small = EnvironmentMap::load(&path, &EnvironmentOptions { max_width: 20 }).unwrap();
    assert_eq!((small.width(), small.height()), (16, 8));
    let (a, b) = (full.mean_radiance(), small.mean_radiance());
    assert!(
        (a - b).abs().max_element() < 0.02 * a.max_element(),
        "{a} vs {b}"
    );
}

#[test]
fn missing_corrupt_and_non_hdr_files_are_refused_with_a_reason() {
    let missing = scratch("does_not_exist.hdr");
    let e = load_err(&missing);
    assert!(
        e.contains("does_not_exist.hdr") && e.contains("cannot read"),
        "{e}"
    );

    let garbage = scratch("garbage.hdr");
    std::fs::write(
        &garbage,
        b"this is not a radiance file at all\n\x00\x01\x02",
    )
    .unwrap();
    let e = load_err(&garbage);
    assert!(e.contains("not a readable Radiance HDR file"), "{e}");

    let garbage = scratch("garbage.exr");
    std::fs::write(&garbage, [0x76u8, 0x2f, 0x31, 0x01, 2, 0, 0, 0, 9, 9, 9]).unwrap();
    let e = load_err(&garbage);
    assert!(e.contains("not a readable OpenEXR file"), "{e}");

    // A valid header and too few pixels.
    let truncated = scratch("truncated.hdr");
    write_hdr(&truncated, 16, 8, &pattern(16, 8));
    let bytes = std::fs::read(&truncated).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() - 100]).unwrap();
    let e = load_err(&truncated);
    assert!(e.contains("not a readable Radiance HDR file"), "{e}");

    let png = scratch("sky.png");
    image::RgbImage::new(4, 2).save(&png).unwrap();
    let e = load_err(&png);
    assert!(e.contains("must be HDR images"), "{e}");

    let folder = scratch("folder.hdr");
    std::fs::create_dir_all(&folder).unwrap();
    let e = load_err(&folder);
    assert!(e.contains("not a regular file"), "{e}");
}

#[test]
fn a_32k_by_16k_map_is_refused_before_decoding() {
    // The header of a 32768 x 16384 Radiance file and a few bytes of data: decoding it would
    // take 6 GiB, so the size must be refused from the header alone.
    let path = scratch("huge.hdr");
    let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 32768\n".to_vec();
    bytes.extend([128u8, 128, 128, 129].repeat(64));
    std::fs::write(&path, bytes).unwrap();
    let start = std::time::Instant::now();
    let e = load_err(&path);
    assert!(
        e.contains("32768 x 16384") && e.contains("over the limit"),
        "{e}"
    );
    assert_eq!(MAX_FILE_TEXELS, 16384 * 8192);
    // Refused unread: no decoding pass over half a billion texels.
    assert!(start.elapsed().as_secs_f64() < 5.0);
}

#[test]
fn the_scene_reads_its_environment_through_the_map() {
    let map = EnvironmentMap::new(4, 2, pattern(4, 2)).unwrap();
    let mut scene = solari_scene::Scene {
        environment_radiance: Vec3::splat(2.0),
        ..Default::default()
    };
    assert_eq!(scene.environment(Vec3::Y), Vec3::splat(2.0));
    scene.environment_map = Some(std::sync::Arc::new(map.clone()));
    let d = Vec3::new(0.3, 0.5, -0.8).normalize();
    assert_eq!(scene.environment(d), 2.0 * map.radiance(d));
}
