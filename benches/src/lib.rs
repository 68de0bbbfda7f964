//! Shared helpers for the Solari benchmarks.

use std::path::{Path, PathBuf};

/// Every shared glTF scene beside the checkout (`../shared/scenes`), sorted by path.
pub fn shared_scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes");
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .flat_map(|e| std::fs::read_dir(e.path()).into_iter().flatten().flatten())
        .map(|f| f.path())
        .filter(|p| p.extension().is_some_and(|e| e == "gltf"))
        .collect();
    out.sort();
    out
}

pub mod denoise;
pub mod font;
pub mod gi_table;
pub mod quality_table;
pub mod scatter;
pub mod sweep;
pub mod table;
