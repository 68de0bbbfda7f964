//! Output files: the format follows the extension (`.png` tone-mapped 8-bit, `.exr` linear
//! 32-bit float), every path is checked before any work starts (its folder exists and is
//! writable, the extension is known), and files are written atomically (a temporary file
//! beside the target, then a rename), so a failure never leaves a corrupt or partial file.

use solari_reference::image_io::{encode_exr, encode_png, encode_png_rgb8, srgb_encode};
use std::io::Write;
use std::path::{Path, PathBuf};

/// An image file format, chosen by the output path's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit sRGB PNG through the documented tone curve (`image_io`).
    Png,
    /// Linear 32-bit float RGB OpenEXR.
    Exr,
}

impl ImageFormat {
    /// The format for `path`'s extension (case-insensitive), or an error naming the known ones.
    pub fn for_path(path: &Path) -> Result<Self, String> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("exr") => Ok(Self::Exr),
            Some(other) => Err(format!(
                "{}: unknown image extension .{other}: use .png (tone-mapped) or .exr (linear)",
                path.display()
            )),
            None => Err(format!(
                "{}: no extension: use .png (tone-mapped) or .exr (linear)",
                path.display()
            )),
        }
    }
}

/// Checks that `path` can be written: it is not a folder, its folder exists, and a file can be
/// created there (tried with a temporary file, removed at once). `what` names the option in
/// messages.
pub fn check_writable(path: &Path, what: &str) -> Result<(), String> {
    if path.as_os_str().is_empty() {
        return Err(format!("{what}: empty path"));
    }
    if path.is_dir() {
        return Err(format!("{what} {}: is a folder", path.display()));
    }
    let folder = parent_of(path);
    if !folder.is_dir() {
        return Err(format!(
            "{what} {}: folder {} does not exist",
            path.display(),
            folder.display()
        ));
    }
    AtomicFile::create(path)
        .map(drop)
        .map_err(|e| format!("{what} {e}"))
}

fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A file written under a temporary name beside its destination and renamed into place by
/// [`AtomicFile::commit`]; dropped without a commit, the temporary file is removed and the
/// destination is untouched.
pub struct AtomicFile {
    dest: PathBuf,
    tmp: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Creates the temporary file for `dest`.
    pub fn create(dest: &Path) -> Result<Self, String> {
        let name = dest
            .file_name()
            .ok_or_else(|| format!("{}: not a file name", dest.display()))?;
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}.tmp", std::process::id()));
        let tmp = parent_of(dest).join(tmp_name);
        let file = std::fs::File::create(&tmp)
            .map_err(|e| format!("{}: cannot create a file there: {e}", dest.display()))?;
        Ok(Self {
            dest: dest.to_path_buf(),
            tmp,
            file: Some(std::io::BufWriter::new(file)),
        })
    }

    /// The writer of the temporary file.
    pub fn writer(&mut self) -> &mut impl Write {
        self.file.as_mut().expect("present until commit")
    }

    /// Flushes, syncs and renames the file into place.
    pub fn commit(mut self) -> Result<(), String> {
        let fail = |e: std::io::Error| format!("{}: {e}", self.dest.display());
        let file = self.file.take().expect("present until commit");
        let file = file.into_inner().map_err(|e| fail(e.into_error()))?;
        file.sync_all().map_err(fail)?;
        drop(file);
        std::fs::rename(&self.tmp, &self.dest).map_err(fail)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes `bytes` to `dest` atomically.
pub fn write_atomic(dest: &Path, bytes: &[u8]) -> Result<(), String> {
    let mut f = AtomicFile::create(dest)?;
    f.writer()
        .write_all(bytes)
        .map_err(|e| format!("{}: {e}", dest.display()))?;
    f.commit()
}

/// The image files a command will write, checked up front.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImageOutputs {
    /// Each path with its format.
    pub files: Vec<(PathBuf, ImageFormat)>,
}

impl ImageOutputs {
    /// Checks every path (known extension, writable folder, no path twice).
    pub fn check(paths: &[PathBuf]) -> Result<Self, String> {
        let mut files = Vec::new();
        for p in paths {
            if p.is_dir() {
                return Err(format!("--out {}: is a folder", p.display()));
            }
            let format = ImageFormat::for_path(p)?;
            if files.iter().any(|(q, _)| q == p) {
                return Err(format!("--out {} is given twice", p.display()));
            }
            check_writable(p, "--out")?;
            files.push((p.clone(), format));
        }
        if files.is_empty() {
            return Err("no output file: give --out FILE.png or FILE.exr".into());
        }
        Ok(Self { files })
    }

    /// Writes linear radiance `pixels` (`width × height`, row-major from the top left) to every
    /// file: EXR as is, PNG through the tone curve at `exposure_ev`, or with `exposure_ev`
    /// `None` (display-referred images: the G-buffer views) sRGB-encoded as they are. An image holding
    /// non-finite values is refused (nothing is written): it means a renderer bug, which
    /// `--check-finite` traces to its pass.
    pub fn write(
        &self,
        width: u32,
        height: u32,
        pixels: &[[f32; 3]],
        exposure_ev: Option<f32>,
    ) -> Result<(), String> {
        let bad = pixels
            .iter()
            .filter(|p| p.iter().any(|c| !c.is_finite()))
            .count();
        if bad > 0 {
            return Err(format!(
                "the image holds {bad} non-finite pixel(s); nothing was written (a renderer \
                 bug: run with --check-finite to find the pass that produced them)"
            ));
        }
        let mut encoded = Vec::new();
        for (path, format) in &self.files {
            let bytes = match format {
                ImageFormat::Png => match exposure_ev {
                    Some(ev) => encode_png(width, height, pixels, ev)?,
                    None => encode_png_rgb8(width, height, &display_rgb8(pixels))?,
                },
                ImageFormat::Exr => encode_exr(width, height, pixels)?,
            };
            encoded.push((path, bytes));
        }
        // Encoding can fail (size mismatch); only then do files get touched.
        for (path, bytes) in encoded {
            write_atomic(path, &bytes)?;
        }
        Ok(())
    }

    /// The paths, for messages.
    pub fn describe(&self) -> String {
        self.files
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" and ")
    }
}

// Display-referred values in [0, 1] (clamped) as 8-bit sRGB, without exposure or tone curve.
fn display_rgb8(pixels: &[[f32; 3]]) -> Vec<u8> {
    pixels
        .iter()
        .flat_map(|p| p.map(|c| (srgb_encode(c.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("solari-output-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(
            ImageFormat::for_path(Path::new("a.PNG")),
            Ok(ImageFormat::Png)
        );
        assert_eq!(
            ImageFormat::for_path(Path::new("a.exr")),
            Ok(ImageFormat::Exr)
        );
        assert!(
            ImageFormat::for_path(Path::new("a.jpg"))
                .unwrap_err()
                .contains(".jpg")
        );
        assert!(ImageFormat::for_path(Path::new("a")).is_err());
    }

    #[test]
    fn bad_paths_are_refused_before_work() {
        let d = tmp_dir("paths");
        assert!(
            check_writable(&d, "--out")
                .unwrap_err()
                .contains("is a folder")
        );
        let missing = d.join("nope/x.png");
        assert!(
            check_writable(&missing, "--out")
                .unwrap_err()
                .contains("does not exist")
        );
        check_writable(&d.join("x.png"), "--out").unwrap();
        // The check leaves nothing behind.
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
        let twice = [d.join("a.png"), d.join("a.png")];
        assert!(ImageOutputs::check(&twice).unwrap_err().contains("twice"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn writes_are_atomic_and_non_finite_images_refused() {
        let d = tmp_dir("atomic");
        let png = d.join("a.png");
        let exr = d.join("a.exr");
        std::fs::write(&png, b"old").unwrap();
        let out = ImageOutputs::check(&[png.clone(), exr.clone()]).unwrap();
        let mut px = vec![[0.5f32; 3]; 4];
        px[2][1] = f32::NAN;
        let e = out.write(2, 2, &px, Some(0.0)).unwrap_err();
        assert!(e.contains("1 non-finite"), "{e}");
        assert_eq!(std::fs::read(&png).unwrap(), b"old");
        assert!(!exr.exists());
        // A size mismatch fails in encoding, before any file is touched.
        assert!(out.write(3, 2, &[[0.5; 3]; 4], Some(0.0)).is_err());
        assert_eq!(std::fs::read(&png).unwrap(), b"old");
        px[2][1] = 0.25;
        out.write(2, 2, &px, Some(0.0)).unwrap();
        let back = image::open(&exr).unwrap().to_rgb32f();
        assert_eq!(back.get_pixel(0, 1).0, [0.5, 0.25, 0.5]);
        assert_eq!(image::open(&png).unwrap().width(), 2);
        // Only the two outputs remain: no temporary files.
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn display_images_are_written_without_the_tone_curve() {
        let d = tmp_dir("display");
        let png = d.join("d.png");
        let out = ImageOutputs::check(std::slice::from_ref(&png)).unwrap();
        // Linear 0.5 is sRGB 0.735 (188/255); values past 1 clamp instead of tone-mapping.
        let px = [[0.0, 0.5, 1.0], [4.0, -1.0, 0.5]];
        out.write(2, 1, &px, None).unwrap();
        let back = image::open(&png).unwrap().to_rgb8();
        assert_eq!(back.get_pixel(0, 0).0, [0, 188, 255]);
        assert_eq!(back.get_pixel(1, 0).0, [255, 0, 188]);
        // The tone curve darkens 1.0 (ACES maps it to 0.80).
        out.write(2, 1, &px, Some(0.0)).unwrap();
        assert!(image::open(&png).unwrap().to_rgb8().get_pixel(0, 0).0[2] < 240);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_uncommitted_file_leaves_no_trace() {
        let d = tmp_dir("drop");
        let p = d.join("r.csv");
        {
            let mut f = AtomicFile::create(&p).unwrap();
            f.writer().write_all(b"half").unwrap();
        }
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
        std::fs::remove_dir_all(&d).unwrap();
    }
}
