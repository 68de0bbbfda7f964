//! glTF import: every bundled test scene loads, and every kind of malformed input gives a typed
//! error naming the file and element (never a panic).

use base64::Engine as _;
use serde_json::{Value, json};
use solari_scene::*;
use std::path::Path;

/// A minimal valid glTF: one triangle (or what `positions`/`indices` say), as JSON with an
/// embedded base64 buffer.
fn doc(positions: &[[f32; 3]], indices: &[u32]) -> Value {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let pos_len = bytes.len();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let b64 = base64::engine::general_purpose::STANDARD.encode(&bytes);
    let (lo, hi) = positions
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(mut lo, mut hi), p| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            (lo, hi)
        });
    let (lo, hi) = if lo.iter().all(|x| x.is_finite()) && hi.iter().all(|x| x.is_finite()) {
        (json!(lo), json!(hi))
    } else {
        (json!([0.0, 0.0, 0.0]), json!([1.0, 1.0, 1.0]))
    };
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "tri", "mesh": 0}],
        "meshes": [{"name": "m", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{b64}")}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": pos_len},
            {"buffer": 0, "byteOffset": pos_len, "byteLength": indices.len() * 4}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}
        ]
    })
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

fn import_json(v: &Value) -> Result<Scene, SceneError> {
    import_dir_json(v, Path::new("."))
}

fn import_dir_json(v: &Value, dir: &Path) -> Result<Scene, SceneError> {
    let bytes = serde_json::to_vec(v).unwrap();
    import_slice(
        &bytes,
        dir,
        Path::new("test.gltf"),
        &ImportOptions::default(),
    )
}

#[test]
fn every_bundled_scene_loads() {
    for p in solari_testdata::all_scenes() {
        let scene = load_gltf(&p).unwrap_or_else(|e| panic!("{e}"));
        let s = scene.stats();
        assert!(s.triangles > 0 && s.instances > 0, "{}", p.display());
        assert!(scene.camera(None).is_some());
        for m in &scene.meshes {
            assert_eq!(m.normals.len(), m.positions.len());
            assert_eq!(m.uvs.len(), m.positions.len());
            assert_eq!(m.tangents.len(), m.positions.len());
            assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
            assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3));
        }
    }
}

#[test]
fn bundled_scene_details_are_imported() {
    let cornell = load_gltf(solari_testdata::scene("cornell_box")).unwrap();
    let s = cornell.stats();
    assert_eq!(s.triangles, 32);
    assert_eq!(s.emissive_triangles, 2);
    let light = cornell.materials.iter().find(|m| m.is_emissive()).unwrap();
    assert!((light.emissive - glam::Vec3::new(17.0, 12.0, 4.0)).length() < 1e-4);
    // specularFactor 0 marks an exact Lambertian.
    assert!(
        cornell
            .materials
            .iter()
            .all(|m| m.dielectric_f0 == glam::Vec3::ZERO && m.dielectric_f90 == 0.0)
    );
    let cam = cornell.camera(Some("camera")).unwrap();
    assert!((cam.position() - glam::Vec3::new(2.78, 2.73, -8.0)).length() < 1e-5);
    // Looks along +Z: the camera's -Z axis is world +Z.
    assert!((-cam.transform.z_axis.truncate() - glam::Vec3::Z).length() < 1e-5);

    let sun = load_gltf(solari_testdata::scene("sun_boxes")).unwrap();
    assert_eq!(sun.directional_lights.len(), 1);
    let d = &sun.directional_lights[0];
    assert!((d.direction.length() - 1.0).abs() < 1e-5 && d.irradiance.max_element() > 0.0);
    assert!((d.angular_diameter - SUN_ANGULAR_DIAMETER).abs() < 1e-7);

    let strength = load_gltf(solari_testdata::scene("emissive_strength_test")).unwrap();
    assert_eq!(strength.camera(None).unwrap().name, "render_setup");
    let max_emission = strength
        .materials
        .iter()
        .map(|m| m.emissive.max_element())
        .fold(0.0, f32::max);
    // The brightest cube is emissiveFactor 0.9 × strength 16.
    assert!(
        (max_emission - 14.4).abs() < 1e-3,
        "emissive strength applied: {max_emission}"
    );
}

/// A 4×4 PNG as a data URI.
fn png_uri(rgba: [u8; 4]) -> String {
    let mut png = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut png),
        &rgba.repeat(16),
        4,
        4,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .unwrap();
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&png)
    )
}

#[test]
fn texture_slots_get_their_colour_spaces() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["meshes"][0]["primitives"][0]["material"] = json!(0);
    v["materials"] = json!([{
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                 "metallicRoughnessTexture": {"index": 1}},
        "normalTexture": {"index": 2},
        "emissiveTexture": {"index": 3},
        "emissiveFactor": [1.0, 1.0, 1.0]
    }]);
    v["textures"] = json!([{"source": 0}, {"source": 1}, {"source": 2}, {"source": 0}]);
    v["images"] = json!([
        {"uri": png_uri([200, 100, 50, 255])},
        {"uri": png_uri([0, 128, 255, 255])},
        {"uri": png_uri([128, 128, 255, 255])}
    ]);
    let s = import_json(&v).unwrap();
    let m = &s.materials[0];
    let space = |t: Option<u32>| s.textures[t.unwrap() as usize].color_space;
    assert_eq!(space(m.base_color_texture), ColorSpace::Srgb);
    assert_eq!(space(m.emissive_texture), ColorSpace::Srgb);
    assert_eq!(space(m.normal_texture), ColorSpace::Linear);
    assert_eq!(space(m.metallic_roughness_texture), ColorSpace::Linear);
    // The base colour and emission share image 0 and a colour space: one texture.
    assert_eq!(m.base_color_texture, m.emissive_texture);
    assert_eq!(s.textures.len(), 3);
}

#[test]
fn instancing_stores_a_mesh_once() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["scenes"][0]["nodes"] = json!([0, 1, 2]);
    v["nodes"] = json!([
        {"mesh": 0},
        {"mesh": 0, "translation": [2.0, 0.0, 0.0]},
        {"children": [3], "translation": [0.0, 5.0, 0.0]},
        {"mesh": 0, "translation": [0.0, 1.0, 0.0]}
    ]);
    let s = import_json(&v).unwrap();
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.instances.len(), 3);
    // The child's world transform composes its parent's.
    let t = s.instances[2].transform.w_axis.truncate();
    assert!((t - glam::Vec3::new(0.0, 6.0, 0.0)).length() < 1e-6);
}

#[test]
fn a_valid_minimal_file_gets_generated_normals() {
    let s = import_json(&doc(&TRI, &[0, 1, 2])).unwrap();
    assert_eq!(s.warnings.generated_normals, 1);
    assert!((s.meshes[0].normals[0] - glam::Vec3::Z).length() < 1e-6);
    // No camera in the file: one that frames the scene is made.
    assert_eq!(s.camera(None).unwrap().name, "auto");
}

fn expect_err(v: &Value, check: impl Fn(&SceneError) -> bool) -> String {
    let e = import_json(v).expect_err("import must fail");
    let msg = e.to_string();
    assert!(check(&e), "unexpected error: {msg}");
    assert!(msg.contains("test.gltf"), "error must name the file: {msg}");
    msg
}

#[test]
fn nan_and_inf_positions_are_refused() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let v = doc(
            &[[0.0, 0.0, 0.0], [1.0, bad, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
        );
        let msg = expect_err(&v, |e| {
            matches!(
                e,
                SceneError::BadPrimitive {
                    mesh: 0,
                    primitive: 0,
                    ..
                }
            )
        });
        assert!(msg.contains("vertex 1"), "{msg}");
    }
}

#[test]
fn out_of_range_indices_are_refused() {
    let msg = expect_err(&doc(&TRI, &[0, 1, 3]), |e| {
        matches!(e, SceneError::BadPrimitive { .. })
    });
    assert!(msg.contains("index 3"), "{msg}");
    let msg = expect_err(&doc(&TRI, &[0, 1, u32::MAX]), |e| {
        matches!(e, SceneError::BadPrimitive { .. })
    });
    assert!(msg.contains("out of range"), "{msg}");
}

#[test]
fn accessors_past_their_view_are_refused() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["accessors"][1]["count"] = json!(6);
    expect_err(&v, |e| {
        matches!(e, SceneError::BadAccessor { accessor: 1, .. })
    });
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["accessors"][0]["byteOffset"] = json!(4);
    expect_err(&v, |e| {
        matches!(e, SceneError::BadAccessor { accessor: 0, .. })
    });
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["bufferViews"][1]["byteLength"] = json!(1 << 20);
    expect_err(&v, |e| matches!(e, SceneError::BadAccessor { .. }));
}

#[test]
fn truncated_and_missing_buffers_are_refused() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["buffers"][0]["byteLength"] = json!(1000);
    let msg = expect_err(&v, |e| {
        matches!(
            e,
            SceneError::TruncatedBuffer {
                index: 0,
                declared: 1000,
                ..
            }
        )
    });
    assert!(msg.contains("buffer 0"));
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["buffers"][0]["uri"] = json!("does_not_exist.bin");
    let msg = expect_err(&v, |e| {
        matches!(e, SceneError::MissingBuffer { index: 0, .. })
    });
    assert!(msg.contains("does_not_exist.bin"), "{msg}");
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@@");
    expect_err(&v, |e| matches!(e, SceneError::MissingBuffer { .. }));
}

#[test]
fn missing_and_broken_textures_are_refused() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["meshes"][0]["primitives"][0]["material"] = json!(0);
    v["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    v["textures"] = json!([{"source": 0}]);
    v["images"] = json!([{"uri": "missing.png"}]);
    let msg = expect_err(&v, |e| matches!(e, SceneError::BadImage { image: 0, .. }));
    assert!(msg.contains("missing.png"), "{msg}");
    v["images"] = json!([{"uri": "data:image/png;base64,AAAA"}]);
    expect_err(&v, |e| matches!(e, SceneError::BadImage { image: 0, .. }));
}

#[test]
fn zero_area_triangles_are_dropped_and_counted() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    ];
    // Second triangle is collinear, third repeats a vertex.
    let s = import_json(&doc(&p, &[0, 1, 2, 0, 1, 3, 2, 2, 1])).unwrap();
    assert_eq!(s.warnings.degenerate_triangles, 2);
    assert_eq!(s.meshes[0].triangle_count(), 1);
    assert!(s.warnings.lines().iter().any(|l| l.contains("2 zero-area")));
}

#[test]
fn empty_scenes_are_refused() {
    // Only degenerate triangles.
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    expect_err(&doc(&p, &[0, 1, 2]), |e| {
        matches!(e, SceneError::EmptyScene { .. })
    });
    // No nodes placing a mesh.
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["nodes"] = json!([{"name": "empty"}]);
    expect_err(&v, |e| matches!(e, SceneError::EmptyScene { .. }));
    // No scene at all.
    let mut v = doc(&TRI, &[0, 1, 2]);
    v.as_object_mut().unwrap().remove("scene");
    v.as_object_mut().unwrap().remove("scenes");
    expect_err(&v, |e| matches!(e, SceneError::EmptyScene { .. }));
}

#[test]
fn malformed_json_and_bad_references_are_refused() {
    let e = import_slice(
        b"{ not json",
        Path::new("."),
        Path::new("test.gltf"),
        &ImportOptions::default(),
    );
    assert!(matches!(e, Err(SceneError::Gltf { .. })));
    let e = import_slice(
        b"glTF\x02\x00\x00\x00",
        Path::new("."),
        Path::new("test.gltf"),
        &ImportOptions::default(),
    );
    assert!(matches!(e, Err(SceneError::Gltf { .. })));
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["nodes"][0]["mesh"] = json!(7);
    expect_err(&v, |e| matches!(e, SceneError::Gltf { .. }));
}

#[test]
fn node_cycles_and_bad_transforms_are_refused() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    let r = import_json(&v);
    assert!(
        matches!(
            r,
            Err(SceneError::BadNode { .. }) | Err(SceneError::Gltf { .. })
        ),
        "{r:?}"
    );
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["nodes"][0]["matrix"] = json!([1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
    let r = import_json(&v);
    assert!(
        matches!(
            r,
            Err(SceneError::BadNode { node: 0, .. }) | Err(SceneError::Gltf { .. })
        ),
        "{r:?}"
    );
}

#[test]
fn points_and_lines_are_skipped_strips_converted() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["meshes"][0]["primitives"] = json!([
        {"attributes": {"POSITION": 0}, "indices": 1, "mode": 1},
        {"attributes": {"POSITION": 0}, "indices": 1, "mode": 5}
    ]);
    let s = import_json(&v).unwrap();
    assert_eq!(s.warnings.skipped_primitives, 1);
    assert_eq!(s.warnings.converted_topologies, 1);
    assert_eq!(s.instances.len(), 1);
}

#[test]
fn absurd_emission_is_clamped_and_broken_emission_refused() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["meshes"][0]["primitives"][0]["material"] = json!(0);
    v["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    v["materials"] = json!([{"emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e38}}}]);
    // Huge but finite: clamped per channel to MAX_RADIANCE, with a warning.
    let s = import_json(&v).unwrap();
    assert_eq!(
        s.materials[0].emissive,
        glam::Vec3::new(MAX_RADIANCE, MAX_RADIANCE, 0.0)
    );
    assert!(
        s.warnings
            .lines()
            .iter()
            .any(|l| l.contains("emission clamped")),
        "{:?}",
        s.warnings.lines()
    );
    // NaN (1e30 × 1e30 overflows to infinity) or negative: the file is broken.
    for (factor, strength) in [([1e30, 1.0, 1.0], 1e30), ([1.0, -0.5, 1.0], 1.0)] {
        v["materials"][0]["emissiveFactor"] = json!(factor);
        v["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] =
            json!(strength);
        let msg = expect_err(&v, |e| {
            matches!(e, SceneError::BadMaterial { material: 0, .. })
        });
        assert!(msg.contains("finite and non-negative"), "{msg}");
    }
}

#[test]
fn cameras_are_selected_by_name_or_index() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["scenes"][0]["nodes"] = json!([0, 1, 2]);
    v["nodes"] = json!([{"mesh": 0}, {"camera": 0, "name": "a", "translation": [0, 0, 5]}, {"camera": 1, "name": "b"}]);
    v["cameras"] = json!([
        {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}},
        {"type": "perspective", "name": "second", "perspective": {"yfov": 0.7, "znear": 0.1}}
    ]);
    let s = import_json(&v).unwrap();
    assert_eq!(s.camera(None).unwrap().yfov, 0.5);
    assert_eq!(s.camera(Some("second")).unwrap().yfov, 0.7);
    assert_eq!(s.camera(Some("1")).unwrap().yfov, 0.7);
    assert!(s.camera(Some("nope")).is_none());
}

#[test]
fn unreadable_file_is_an_io_error() {
    let e = load_gltf("/nonexistent/scene.gltf").unwrap_err();
    assert!(matches!(e, SceneError::Unreadable { .. }));
    assert!(e.to_string().contains("/nonexistent/scene.gltf"));
}

#[test]
fn malformed_render_setup_is_refused() {
    let dir = std::env::temp_dir().join(format!("solari-rs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("s.gltf"),
        serde_json::to_vec(&doc(&TRI, &[0, 1, 2])).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("render_setup.json"),
        r#"{"camera": {"eye": [0, 0], "target": [0, 0, 0]}}"#,
    )
    .unwrap();
    let e = load_gltf(dir.join("s.gltf")).unwrap_err();
    assert!(matches!(e, SceneError::BadSideFile { .. }), "{e}");
    std::fs::write(
        dir.join("render_setup.json"),
        r#"{"environment_radiance": [0.5, 0.5, 0.5]}"#,
    )
    .unwrap();
    assert_eq!(
        load_gltf(dir.join("s.gltf")).unwrap().environment_radiance,
        glam::Vec3::splat(0.5)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Point and spot lights come in with their world position and direction, glTF's cone angles,
/// the radius the options give, and a warning for each `range` (which is not used).
#[test]
fn point_and_spot_lights_are_imported_for_rendering() {
    let mut v = doc(&TRI, &[0, 1, 2]);
    v["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    v["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "name": "bulb", "color": [1.0, 0.5, 0.25], "intensity": 8.0, "range": 5.0},
        {"type": "spot", "intensity": 2.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
    ]}});
    v["scenes"][0]["nodes"] = json!([0, 1, 2]);
    v["nodes"] = json!([
        {"mesh": 0},
        {"translation": [1.0, 2.0, 3.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        // Rotated -90° about x: the spot's local -z points down (-y).
        {"translation": [0.0, 4.0, 0.0], "rotation": [-0.70710677, 0.0, 0.0, 0.70710677],
         "extensions": {"KHR_lights_punctual": {"light": 1}}}
    ]);
    let bytes = serde_json::to_vec(&v).unwrap();
    let options = ImportOptions {
        point_light_radius: 0.25,
        ..Default::default()
    };
    let s = import_slice(&bytes, Path::new("."), Path::new("test.gltf"), &options).unwrap();
    assert_eq!(s.punctual_lights.len(), 2);
    let (bulb, spot) = (&s.punctual_lights[0], &s.punctual_lights[1]);
    assert_eq!(bulb.kind, model::PunctualKind::Point);
    assert_eq!(bulb.position, glam::Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(bulb.intensity, glam::Vec3::new(8.0, 4.0, 2.0));
    assert_eq!(bulb.radius, 0.25);
    assert_eq!(
        spot.kind,
        model::PunctualKind::Spot {
            inner: 0.2,
            outer: 0.6
        }
    );
    assert!(
        (spot.direction - glam::Vec3::NEG_Y).length() < 1e-5,
        "{}",
        spot.direction
    );
    assert_eq!(s.warnings.ignored_light_ranges, 1);
    assert!(
        s.warnings.lines().iter().any(|l| l.contains("range")),
        "{:?}",
        s.warnings.lines()
    );
}

/// Bad light input (issue 19): a negative or overflowing intensity is refused with the
/// light named; a zero range and a spot whose inner angle exceeds its outer one are imported
/// as given (the range is not used and warned about; `solari_lights::SpotCone` clamps the
/// angles to glTF's 0 ≤ inner ≤ outer ≤ π/2).
#[test]
fn bad_point_light_input_is_refused_or_documented() {
    let with_light = |light: Value| {
        let mut v = doc(&TRI, &[0, 1, 2]);
        v["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        v["extensions"] = json!({"KHR_lights_punctual": {"lights": [light]}});
        v["scenes"][0]["nodes"] = json!([0, 1]);
        v["nodes"] = json!([{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}]);
        v
    };
    for intensity in [json!(-2.0), json!(1e39)] {
        let v = with_light(json!({"type": "point", "name": "lamp", "intensity": intensity}));
        let msg = match import_json(&v) {
            Err(e) => e.to_string(),
            Ok(s) => panic!("intensity {intensity} imported: {:?}", s.punctual_lights),
        };
        assert!(
            msg.contains("lamp") && msg.contains("finite and non-negative"),
            "{msg}"
        );
    }
    let v = with_light(json!({"type": "point", "intensity": 1.0, "range": 0.0}));
    match import_json(&v) {
        Ok(s) => {
            assert_eq!(s.punctual_lights.len(), 1);
            assert_eq!(s.warnings.ignored_light_ranges, 1);
        }
        // glTF requires range > 0: a parser that refuses it must say so.
        Err(e) => assert!(e.to_string().contains("range"), "{e}"),
    }
    let v = with_light(json!({"type": "spot", "intensity": 1.0,
        "spot": {"innerConeAngle": 0.9, "outerConeAngle": 0.3}}));
    match import_json(&v) {
        Ok(s) => assert!(matches!(
            s.punctual_lights[0].kind,
            model::PunctualKind::Spot { inner, outer } if inner == 0.9 && outer == 0.3
        )),
        Err(e) => assert!(
            e.to_string().contains("Angle") || e.to_string().contains("cone"),
            "{e}"
        ),
    }
}
