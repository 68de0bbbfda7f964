//! Untrusted assets: every reproducer that once crashed the importer, exhausted memory or read
//! outside the asset's folder now gives a clear error; URIs stay inside the asset's folder;
//! every read and decoded image is bounded before allocation; shared images decode once.

use base64::Engine as _;
use serde_json::{Value, json};
use solari_scene::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn repro(file: &str) -> Result<Scene, SceneError> {
    load_gltf(solari_testdata::repro(file))
}

/// A fresh folder under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let dir = std::env::temp_dir().join(format!(
            "solari-untrusted-{tag}-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The reproducers' control document: one triangle in a data-URI buffer.
fn base_doc() -> Value {
    let text = std::fs::read_to_string(solari_testdata::repro("base_ok.gltf")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The control document with its buffer's URI replaced.
fn with_buffer_uri(uri: &str) -> Value {
    let mut v = base_doc();
    v["buffers"][0]["uri"] = json!(uri);
    v
}

/// The control document's buffer bytes.
fn base_buffer() -> Vec<u8> {
    let v = base_doc();
    let uri = v["buffers"][0]["uri"].as_str().unwrap();
    let payload = uri.split_once(";base64,").unwrap().1;
    base64::engine::general_purpose::STANDARD
        .decode(payload)
        .unwrap()
}

fn write_gltf(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_vec(v).unwrap()).unwrap();
    p
}

#[test]
fn the_control_imports() {
    let s = repro("base_ok.gltf").unwrap();
    assert_eq!(s.stats().triangles, 1);
}

#[test]
fn every_panic_reproducer_is_a_typed_error() {
    let cases: [(&str, &str); 8] = [
        ("panic1_uri_percent_multibyte.gltf", "buffer 0"),
        ("panic2_position_accessor_oob.gltf", "accessor"),
        (
            "panic3_indices_byte_type.gltf",
            "Indices must be SCALAR UNSIGNED",
        ),
        ("panic4_texcoord_u32_type.gltf", "TexCoord must be VEC2"),
        ("panic5_texcoord_stride_4.gltf", "byteStride 4"),
        ("panic6_position_stride_4.gltf", "byteStride 4"),
        (
            "panic7_image_without_source.gltf",
            "neither a uri nor a buffer view",
        ),
        ("panic7b_image_view_without_mime.gltf", "no mimeType"),
    ];
    for (file, needle) in cases {
        let e = repro(file).expect_err(file);
        let msg = e.to_string();
        assert!(
            !matches!(e, SceneError::ImporterPanic { .. }),
            "{file} reached the panic guard: {msg}"
        );
        assert!(msg.contains(needle), "{file}: {msg}");
        assert!(msg.contains(file), "the error names the file: {msg}");
    }
}

#[test]
fn a_device_file_uri_is_refused_at_once() {
    let start = Instant::now();
    let e = repro("dos_buffer_uri_dev_zero.gltf").unwrap_err();
    assert!(
        matches!(e, SceneError::MissingBuffer { index: 0, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("absolute path"), "{e}");
    assert!(start.elapsed().as_secs() < 5);
}

#[test]
fn png_bombs_are_refused_from_their_header() {
    for file in ["dos_png_bomb_1tex.gltf", "dos_png_bomb_6tex.gltf"] {
        let start = Instant::now();
        let e = repro(file).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, SceneError::BadImage { image: 0, .. }), "{msg}");
        assert!(
            msg.contains("16384x16384") && msg.contains("limit"),
            "{msg}"
        );
        // Refused from the header: no 1 GiB decode (which took seconds per texture).
        assert!(
            start.elapsed().as_secs_f64() < 2.0,
            "{file}: {:?}",
            start.elapsed()
        );
    }
}

#[test]
fn uris_cannot_leave_the_asset_folder() {
    let tmp = TempDir::new("escape");
    let inside = tmp.0.join("asset");
    std::fs::create_dir_all(&inside).unwrap();
    std::fs::write(tmp.0.join("outside.bin"), base_buffer()).unwrap();
    std::fs::write(inside.join("inside.bin"), base_buffer()).unwrap();
    std::os::unix::fs::symlink(tmp.0.join("outside.bin"), inside.join("link.bin")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", inside.join("zero.bin")).unwrap();
    let outside_abs = tmp.0.join("outside.bin").display().to_string();
    let cases = [
        ("../outside.bin", "outside the asset folder"),
        ("sub/../../outside.bin", "outside the asset folder"),
        ("%2e%2e/outside.bin", "outside the asset folder"),
        ("link.bin", "outside the asset folder"),
        ("zero.bin", "outside the asset folder"),
        (outside_abs.as_str(), "absolute path"),
        ("/etc/hostname", "absolute path"),
        ("file:///etc/hostname", "scheme"),
        ("http://example.invalid/x.bin", "scheme"),
    ];
    std::fs::create_dir_all(inside.join("sub")).unwrap();
    for (uri, needle) in cases {
        let path = write_gltf(&inside, "scene.gltf", &with_buffer_uri(uri));
        let e = load_gltf(&path).expect_err(uri);
        assert!(matches!(e, SceneError::MissingBuffer { .. }), "{uri}: {e}");
        assert!(e.to_string().contains(needle), "{uri}: {e}");
    }
    // Inside the folder, through `sub/..` too, is fine.
    for uri in ["inside.bin", "sub/../inside.bin", "./inside.bin"] {
        let path = write_gltf(&inside, "scene.gltf", &with_buffer_uri(uri));
        load_gltf(&path).unwrap_or_else(|e| panic!("{uri}: {e}"));
    }
    // A wider asset root lets a model reach a shared folder beside it.
    let path = write_gltf(&inside, "scene.gltf", &with_buffer_uri("../outside.bin"));
    let options = ImportOptions {
        asset_root: Some(tmp.0.clone()),
        ..Default::default()
    };
    load_gltf_with(&path, &options).unwrap();
}

#[test]
fn non_regular_files_and_directories_are_refused() {
    let tmp = TempDir::new("special");
    // A socket is a file system entry that is not a regular file.
    let _socket = std::os::unix::net::UnixListener::bind(tmp.0.join("sock.bin")).unwrap();
    std::fs::create_dir_all(tmp.0.join("dir.bin")).unwrap();
    for (uri, needle) in [("sock.bin", "not a regular file"), ("dir.bin", "directory")] {
        let path = write_gltf(&tmp.0, "scene.gltf", &with_buffer_uri(uri));
        let e = load_gltf(&path).expect_err(uri);
        assert!(e.to_string().contains(needle), "{uri}: {e}");
    }
    // The scene file itself.
    let e = load_gltf(&tmp.0).unwrap_err();
    assert!(matches!(e, SceneError::Unreadable { .. }), "{e}");
    assert!(e.to_string().contains("directory"), "{e}");
    let e = load_gltf(tmp.0.join("sock.bin")).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
}

#[test]
fn reads_are_limited_before_allocation() {
    let tmp = TempDir::new("limits");
    std::fs::write(tmp.0.join("b.bin"), base_buffer()).unwrap();
    let path = write_gltf(&tmp.0, "scene.gltf", &with_buffer_uri("b.bin"));
    let tight = |bytes| ImportOptions {
        limits: ImportLimits {
            max_file_bytes: bytes,
            ..Default::default()
        },
        ..Default::default()
    };
    // The scene file (about 1 KB) passes a 4 KB limit; the 68-byte buffer does not pass 64.
    let size = std::fs::metadata(&path).unwrap().len();
    let e = load_gltf_with(&path, &tight(size - 1)).unwrap_err();
    assert!(matches!(e, SceneError::Unreadable { .. }), "{e}");
    assert!(e.to_string().contains("over the import limit"), "{e}");
    let mut v = with_buffer_uri("b.bin");
    v["buffers"][0]["byteLength"] = json!(64);
    let path = write_gltf(&tmp.0, "scene.gltf", &v);
    let e = load_gltf_with(&path, &tight(64)).unwrap_err();
    assert!(e.to_string().contains("over the import limit of 64"), "{e}");
    load_gltf_with(&path, &tight(4096)).unwrap();
}

fn png(w: u32, h: u32) -> Vec<u8> {
    let mut out = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut out),
        &vec![128u8; (w * h * 4) as usize],
        w,
        h,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .unwrap();
    out
}

/// The base document with `textures` textures all showing image 0 (`image.png` beside it),
/// spread over the material slots.
fn shared_image_doc(textures: usize) -> Value {
    let mut v = base_doc();
    v["images"] = json!([{"uri": "image.png"}]);
    v["textures"] = json!(
        (0..textures)
            .map(|_| json!({"source": 0}))
            .collect::<Vec<_>>()
    );
    v["meshes"][0]["primitives"][0]["material"] = json!(0);
    v["materials"] = json!([{
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                 "metallicRoughnessTexture": {"index": 1 % textures}},
        "normalTexture": {"index": 2 % textures},
        "emissiveTexture": {"index": 3 % textures},
        "emissiveFactor": [1.0, 1.0, 1.0]
    }]);
    v
}

#[test]
fn an_image_shared_by_textures_is_decoded_and_stored_once_per_colour_space() {
    let tmp = TempDir::new("shared-image");
    std::fs::write(tmp.0.join("image.png"), png(8, 8)).unwrap();
    let path = write_gltf(&tmp.0, "scene.gltf", &shared_image_doc(4));
    let s = load_gltf(&path).unwrap();
    // Four textures over one image: one sRGB copy (base colour, emission), one linear copy
    // (metallic-roughness, normal).
    assert_eq!(s.textures.len(), 2);
    let m = &s.materials[0];
    assert_eq!(m.base_color_texture, m.emissive_texture);
    assert_eq!(m.normal_texture, m.metallic_roughness_texture);
}

#[test]
fn image_limits_apply_per_image_and_per_scene() {
    let tmp = TempDir::new("image-limits");
    std::fs::write(tmp.0.join("image.png"), png(64, 32)).unwrap();
    let path = write_gltf(&tmp.0, "scene.gltf", &shared_image_doc(4));
    let with = |limits: ImportLimits| ImportOptions {
        limits,
        ..Default::default()
    };
    let e = load_gltf_with(
        &path,
        &with(ImportLimits {
            max_image_pixels: 64 * 32 - 1,
            ..Default::default()
        }),
    )
    .unwrap_err();
    assert!(e.to_string().contains("64x32"), "{e}");
    let e = load_gltf_with(
        &path,
        &with(ImportLimits {
            max_image_side: 63,
            ..Default::default()
        }),
    )
    .unwrap_err();
    assert!(e.to_string().contains("over the image limit"), "{e}");
    // One image decoded once: 8 KiB of RGBA8 passes a scene budget of 8 KiB.
    load_gltf_with(
        &path,
        &with(ImportLimits {
            max_total_image_bytes: 64 * 32 * 4,
            ..Default::default()
        }),
    )
    .unwrap();
    let e = load_gltf_with(
        &path,
        &with(ImportLimits {
            max_total_image_bytes: 64 * 32 * 4 - 1,
            ..Default::default()
        }),
    )
    .unwrap_err();
    assert!(e.to_string().contains("over the limit"), "{e}");
}
