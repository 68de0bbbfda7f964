//! Seed inputs: scene files read from folders (the bundled test scenes and reproducers by
//! default; `../shared/scenes` or any folder on demand), each also turned into variants the
//! mutators can reach deeper with: external buffers and images embedded as data URIs, and the
//! whole scene packed as a GLB.

use base64::Engine as _;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// One seed: the bytes of a `.gltf` or `.glb`, and the folder its relative URIs resolve in.
#[derive(Clone, Debug)]
pub struct Seed {
    /// For reports: file name plus variant.
    pub name: String,
    /// The file's bytes.
    pub bytes: Vec<u8>,
    /// The folder relative URIs resolve in (the seed's own).
    pub base: PathBuf,
}

/// Largest external file embedded into a data-URI variant (bigger ones stay external).
const EMBED_LIMIT: u64 = 2 << 20;

/// Every `.gltf`/`.glb` under each of `dirs` (one level of sub-folders), with their variants,
/// sorted by name so runs are reproducible.
pub fn load(dirs: &[PathBuf]) -> Vec<Seed> {
    let mut files = Vec::new();
    for dir in dirs {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path())
            .collect();
        entries.sort();
        for e in entries {
            if e.is_dir() {
                let mut inner: Vec<PathBuf> = std::fs::read_dir(&e)
                    .into_iter()
                    .flatten()
                    .flatten()
                    .map(|x| x.path())
                    .collect();
                inner.sort();
                files.extend(inner.into_iter().filter(|p| is_scene(p)));
            } else if is_scene(&e) {
                files.push(e);
            }
        }
    }
    let mut seeds = Vec::new();
    for f in files {
        let Ok(bytes) = std::fs::read(&f) else {
            continue;
        };
        let base = f.parent().map(Path::to_path_buf).unwrap_or_default();
        let name = f
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        if let Ok(json) = serde_json::from_slice::<Value>(&bytes) {
            let embedded = embed(&json, &base);
            if embedded != json {
                seeds.push(Seed {
                    name: format!("{name}+embedded"),
                    bytes: serde_json::to_vec(&embedded).unwrap_or_default(),
                    base: base.clone(),
                });
            }
            if let Some(glb) = to_glb(&embedded) {
                seeds.push(Seed {
                    name: format!("{name}+glb"),
                    bytes: glb,
                    base: base.clone(),
                });
            }
        }
        seeds.push(Seed { name, bytes, base });
    }
    seeds
}

fn is_scene(p: &Path) -> bool {
    p.extension().is_some_and(|e| e == "gltf" || e == "glb")
}

/// `json` with every small external buffer and image embedded as a data URI.
pub fn embed(json: &Value, base: &Path) -> Value {
    let mut out = json.clone();
    for list in ["buffers", "images"] {
        let Some(items) = out.get_mut(list).and_then(Value::as_array_mut) else {
            continue;
        };
        for item in items {
            let Some(uri) = item.get("uri").and_then(Value::as_str) else {
                continue;
            };
            if uri.starts_with("data:") || uri.contains("..") || uri.starts_with('/') {
                continue;
            }
            let path = base.join(uri);
            let small =
                std::fs::metadata(&path).is_ok_and(|m| m.is_file() && m.len() <= EMBED_LIMIT);
            if let (true, Ok(bytes)) = (small, std::fs::read(&path)) {
                let mime = if list == "buffers" {
                    "application/octet-stream"
                } else if uri.ends_with(".png") {
                    "image/png"
                } else {
                    "image/jpeg"
                };
                let b64 = base64::engine::general_purpose::STANDARD.encode(bytes);
                item["uri"] = Value::String(format!("data:{mime};base64,{b64}"));
            }
        }
    }
    out
}

/// `json` as a GLB whose binary chunk is its first buffer (when that buffer is a data URI),
/// or `None`.
pub fn to_glb(json: &Value) -> Option<Vec<u8>> {
    let mut json = json.clone();
    let first = json.get_mut("buffers")?.as_array_mut()?.first_mut()?;
    let uri = first.get("uri")?.as_str()?.to_string();
    let payload = uri
        .strip_prefix("data:")?
        .split_once(";base64,")?
        .1
        .to_string();
    let bin = base64::engine::general_purpose::STANDARD
        .decode(payload)
        .ok()?;
    first.as_object_mut()?.remove("uri");
    Some(glb(&serde_json::to_vec(&json).ok()?, &bin))
}

pub use solari_testdata::glb;

/// The folders seeds come from when none are given: the repository's test scenes and
/// reproducers.
pub fn default_dirs() -> Vec<PathBuf> {
    vec![
        solari_testdata::root().join("scenes"),
        solari_testdata::root().join("repro"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_seeds_load_with_their_variants_and_import() {
        let seeds = load(&default_dirs());
        assert!(seeds.len() >= 20, "{} seeds", seeds.len());
        assert!(seeds.iter().any(|s| s.name.ends_with("+glb")));
        // The cornell box's embedded and GLB variants import like the original.
        for s in seeds
            .iter()
            .filter(|s| s.name.starts_with("cornell_box.gltf"))
        {
            let scene = solari_scene::import_slice(
                &s.bytes,
                &s.base,
                Path::new(&s.name),
                &Default::default(),
            )
            .unwrap_or_else(|e| panic!("{}: {e}", s.name));
            assert_eq!(scene.stats().triangles, 32, "{}", s.name);
        }
    }
}
