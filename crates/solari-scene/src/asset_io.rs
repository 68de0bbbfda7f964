//! Reading what an asset refers to, treating the asset as untrusted: URIs resolve only inside
//! the asset's folder, only regular files are read, and every read has a size limit checked
//! before anything is allocated.

use base64::Engine as _;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// Size limits on what an import reads and decodes; all configurable, all checked before the
/// memory is allocated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportLimits {
    /// Largest file read (the glTF or GLB itself, an external buffer or image), in bytes.
    /// Default 2 GiB, wgpu's largest storage-buffer binding on the project's GPUs.
    pub max_file_bytes: u64,
    /// Largest decoded image, in pixels (width × height). Default 2^26 (8192²: 256 MiB of
    /// RGBA8 before mips). A 33 KB PNG can declare 16384² pixels (1 GiB decoded).
    pub max_image_pixels: u64,
    /// Longest image side, in pixels. Default 16384.
    pub max_image_side: u32,
    /// Decoded image memory over the whole scene, in bytes (RGBA8 level 0, each image counted
    /// once however many textures use it). Default 4 GiB.
    pub max_total_image_bytes: u64,
}

impl Default for ImportLimits {
    fn default() -> Self {
        Self {
            max_file_bytes: 2 << 30,
            max_image_pixels: 1 << 26,
            max_image_side: 16384,
            max_total_image_bytes: 4 << 30,
        }
    }
}

/// Reads a regular file of at most `limit` bytes. Directories, devices, pipes and sockets are
/// refused before they are opened for reading; the size is checked from the metadata and again
/// while reading, so a file that grows cannot run past the limit.
pub fn read_file_limited(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("is a directory, not a file".into());
    }
    if !meta.is_file() {
        return Err("is not a regular file (device, pipe or socket)".into());
    }
    if meta.len() > limit {
        return Err(format!(
            "is {} bytes, over the import limit of {limit} bytes",
            meta.len()
        ));
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut out = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1)
        .read_to_end(&mut out)
        .map_err(|e| e.to_string())?;
    if out.len() as u64 > limit {
        return Err(format!("grew past the import limit of {limit} bytes"));
    }
    Ok(out)
}

/// Where an asset's URIs may point: inside `root` only.
#[derive(Clone, Debug)]
pub struct AssetFolder {
    /// The folder relative URIs resolve against.
    pub base: PathBuf,
    /// The folder they must stay inside (the asset's own folder unless the caller widens it).
    pub root: PathBuf,
    /// Limit on each file read.
    pub max_file_bytes: u64,
}

impl AssetFolder {
    /// Reads a `data:` URI, or a file that the relative URI `uri` names inside the folder.
    ///
    /// Refused: URIs with a scheme other than `data:` (`file:`, `http:`), absolute paths, and
    /// relative paths whose resolved location (symbolic links followed) leaves [`Self::root`]
    /// (`../`, a link pointing outside); non-regular files and files over the size limit.
    pub fn read_uri(&self, uri: &str) -> Result<Vec<u8>, String> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let (_, payload) = rest
                .split_once(";base64,")
                .ok_or("data URI is not base64")?;
            // Decoded size is at most 3/4 of the text, which is already in memory.
            return base64::engine::general_purpose::STANDARD
                .decode(payload.trim_end())
                .map_err(|e| format!("bad base64 in data URI: {e}"));
        }
        let path = self.resolve(uri)?;
        read_file_limited(&path, self.max_file_bytes).map_err(|e| format!("{uri}: {e}"))
    }

    /// The file that `uri` names, if it lies inside the folder.
    pub fn resolve(&self, uri: &str) -> Result<PathBuf, String> {
        if has_scheme(uri) {
            return Err(format!(
                "URI {uri:?} has a scheme: only relative paths and data: URIs are read"
            ));
        }
        let decoded = percent_decode(uri);
        if decoded.contains('\0') {
            return Err(format!("URI {uri:?} holds a NUL character"));
        }
        let rel = Path::new(&decoded);
        if rel.is_absolute()
            || decoded.starts_with(['/', '\\'])
            || rel
                .components()
                .any(|c| matches!(c, Component::Prefix(_) | Component::RootDir))
        {
            return Err(format!(
                "URI {uri:?} is an absolute path: assets may only refer to files inside their folder"
            ));
        }
        let joined = self.base.join(rel);
        let resolved = joined
            .canonicalize()
            .map_err(|e| format!("{}: {e}", joined.display()))?;
        // A scene named by a bare file name (`scene.gltf`) has an empty parent folder, which
        // is the current one.
        let root = if self.root.as_os_str().is_empty() {
            Path::new(".")
        } else {
            &self.root
        };
        let root = root
            .canonicalize()
            .map_err(|e| format!("asset folder {}: {e}", root.display()))?;
        if !resolved.starts_with(&root) {
            return Err(format!(
                "URI {uri:?} resolves to {}, outside the asset folder {}",
                resolved.display(),
                root.display()
            ));
        }
        Ok(resolved)
    }
}

/// Whether `uri` starts with an RFC 3986 scheme (`letter *( letter / digit / + - . ) ":"`).
/// A Windows drive (`C:`) counts as one too, which is what we want: it is not relative.
fn has_scheme(uri: &str) -> bool {
    let Some((scheme, _)) = uri.split_once(':') else {
        return false;
    };
    let mut chars = scheme.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// Decodes `%XX` escapes byte-wise (so an escape next to a multi-byte character is fine);
/// malformed escapes are kept as they are, invalid UTF-8 becomes U+FFFD.
pub fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let hex = |b: u8| (b as char).to_digit(16);
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let (Some(hi), Some(lo)) = (hex(bytes[i + 1]), hex(bytes[i + 2]))
        {
            out.push((hi * 16 + lo) as u8);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b.png"), "a b.png");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz"), "%zz");
        assert_eq!(percent_decode("%41%42"), "AB");
        // A '%' before a multi-byte character used to slice inside it.
        assert_eq!(percent_decode("%é.png"), "%é.png");
        assert_eq!(percent_decode("%4é"), "%4é");
        assert_eq!(percent_decode("é%41"), "éA");
    }

    #[test]
    fn schemes_are_recognised() {
        for s in [
            "file:///etc/passwd",
            "http://x/y.bin",
            "C:/x.bin",
            "a+b.c-d:x",
        ] {
            assert!(has_scheme(s), "{s}");
        }
        for s in ["x.bin", "dir/x.bin", "1abc:x", ":x", "a b:x"] {
            assert!(!has_scheme(s), "{s}");
        }
    }
}
