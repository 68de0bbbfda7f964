//! Paths to the test scenes and reference images that live in this repository, so that the
//! workspace's tests pass on a clone with nothing beside it.
//!
//! The files sit in this crate's folder (`scenes/`, `references/`), each scene with the
//! README and, for third-party assets, the licence it came with; see this crate's README for
//! what is here and why. Tests reach them through these functions, never through
//! `../shared` (which only the project's own machines have; benchmarks may still read it).
//!
//! ```
//! let path = solari_testdata::scene("cornell_box");
//! assert!(path.ends_with("cornell_box/cornell_box.gltf") && path.is_file());
//! ```

use std::path::{Path, PathBuf};

/// Every bundled scene, by folder name.
pub const SCENES: [&str; 8] = [
    "cornell_box",
    "emissive_strength_test",
    "furnace_sphere",
    "furnace_uniform",
    "interior",
    "many_lights",
    "metal_rough_spheres",
    "sun_boxes",
];

/// This crate's folder, or the folder `SOLARI_TESTDATA` names: a binary built here and run
/// elsewhere (a bench carried to another machine) finds the data through it.
pub fn root() -> PathBuf {
    match std::env::var_os("SOLARI_TESTDATA") {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => PathBuf::from(env!("CARGO_MANIFEST_DIR")),
    }
}

/// The folder of the bundled scene `name` (one of [`SCENES`]).
pub fn scene_dir(name: &str) -> PathBuf {
    root().join("scenes").join(name)
}

/// The `.gltf` file of the bundled scene `name` (one of [`SCENES`]).
///
/// # Panics
/// If `name` is not a bundled scene or its folder holds no `.gltf`: a test asking for data
/// that does not exist is a bug in the test.
pub fn scene(name: &str) -> PathBuf {
    let dir = scene_dir(name);
    let entries = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("no bundled scene {name:?} ({}: {e})", dir.display()));
    let mut found: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "gltf"))
        .collect();
    found.sort();
    found
        .into_iter()
        .next()
        .unwrap_or_else(|| panic!("{} holds no .gltf", dir.display()))
}

/// Every bundled scene's `.gltf`, in [`SCENES`] order.
pub fn all_scenes() -> Vec<PathBuf> {
    SCENES.iter().map(|s| scene(s)).collect()
}

/// A bundled reference image (`cornell_box.exr`, `cornell_box_direct.exr`).
///
/// # Panics
/// If the file does not exist.
pub fn reference(file: &str) -> PathBuf {
    let p = root().join("references").join(file);
    assert!(p.is_file(), "no bundled reference {file:?}");
    p
}

/// A file of the reproducer folder (`repro/`): inputs that once crashed or exhausted the
/// importer (see its README).
///
/// # Panics
/// If the file does not exist.
pub fn repro(file: &str) -> PathBuf {
    let p = root().join("repro").join(file);
    assert!(p.is_file(), "no reproducer {file:?}");
    p
}

/// A binary glTF (GLB) container of `json` and `bin`, both padded to 4 bytes as the format
/// requires; an empty `bin` writes no binary chunk. Tests and the fuzzer build GLB inputs
/// with it.
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut j = json.to_vec();
    j.resize(j.len().next_multiple_of(4), b' ');
    let mut b = bin.to_vec();
    b.resize(b.len().next_multiple_of(4), 0);
    let total = 12 + 8 + j.len() + if b.is_empty() { 0 } else { 8 + b.len() };
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    if !b.is_empty() {
        out.extend((b.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(b);
    }
    out
}

/// The scenes a criterion bench measures, by name: in criterion's test mode (`full` false:
/// `cargo test` runs each case once) the Cornell box and `interior`; for `cargo bench`
/// every bundled scene plus every scene in `../shared/scenes` beside the repository when it
/// is there (benches may read it; tests may not). `SOLARI_BENCH_SCENES` (comma-separated
/// names) keeps only those scenes, so a run skips loading and uploading the others (a
/// criterion filter skips only their timing).
pub fn bench_scenes(full: bool) -> Vec<(String, PathBuf)> {
    let names: &[&str] = if full {
        &SCENES
    } else {
        &["cornell_box", "interior"]
    };
    let mut out: Vec<(String, PathBuf)> = names.iter().map(|n| (n.to_string(), scene(n))).collect();
    // Beside the checkout, or `SOLARI_SHARED_SCENES` where the binary runs elsewhere.
    let shared = std::env::var_os("SOLARI_SHARED_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes"));
    if full && let Ok(dirs) = std::fs::read_dir(shared) {
        let mut extra: Vec<(String, PathBuf)> = dirs
            .flatten()
            .flat_map(|d| std::fs::read_dir(d.path()).into_iter().flatten().flatten())
            .map(|f| f.path())
            .filter(|p| p.extension().is_some_and(|e| e == "gltf"))
            .filter_map(|p| Some((p.file_stem()?.to_string_lossy().into_owned(), p)))
            .filter(|(n, _)| !out.iter().any(|(m, _)| m == n))
            .collect();
        extra.sort();
        out.extend(extra);
    }
    if let Ok(keep) = std::env::var("SOLARI_BENCH_SCENES") {
        let keep: Vec<&str> = keep.split(',').map(str::trim).collect();
        out.retain(|(n, _)| keep.contains(&n.as_str()));
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_listed_file_exists() {
        assert_eq!(super::all_scenes().len(), super::SCENES.len());
        super::reference("cornell_box.exr");
        super::reference("cornell_box_direct.exr");
    }

    #[test]
    fn glb_pads_chunks_and_states_the_total_length() {
        let out = super::glb(b"{}", &[1, 2, 3]);
        assert_eq!(&out[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(out[8..12].try_into().unwrap()) as usize,
            out.len()
        );
        assert_eq!(u32::from_le_bytes(out[12..16].try_into().unwrap()), 4);
        assert_eq!(&out[16..20], b"JSON");
        assert_eq!(&out[20..24], b"{}  ");
        assert_eq!(u32::from_le_bytes(out[24..28].try_into().unwrap()), 4);
        assert_eq!(&out[28..32], b"BIN\0");
        assert_eq!(&out[32..], &[1, 2, 3, 0]);
        assert_eq!(
            super::glb(b"{}", &[]).len(),
            24, // header 12 + JSON chunk header 8 + "{}  " 4
            "no binary chunk when bin is empty"
        );
    }
}
