//! What the sweep commands (`bench-di`, `bench-cache`) and `render --mode realtime` share:
//! the reference image, error metrics, the frame progress bar, CSV output.

use indicatif::{ProgressBar, ProgressStyle};
use solari_reference::image_io::read_linear;
use std::io::Write;
use std::path::PathBuf;

/// RMSE and relative MSE as `solari compare` defines them (FLIP is left to `compare`: at
/// 1080p it would cost seconds per setting).
pub fn errors(test: &[[f32; 3]], reference: &[[f32; 3]]) -> (f64, f64) {
    let (mut se, mut rel) = (0.0, 0.0);
    for (t, r) in test.iter().zip(reference) {
        for c in 0..3 {
            let d = t[c] as f64 - r[c] as f64;
            se += d * d;
            rel += d * d / ((r[c] as f64).powi(2) + 0.01);
        }
    }
    let n = (test.len() * 3).max(1) as f64;
    ((se / n).sqrt(), rel / n)
}

/// The reference image at `path`, which must be `w × h`.
pub fn load_reference(
    path: Option<&PathBuf>,
    w: u32,
    h: u32,
) -> Result<Option<Vec<[f32; 3]>>, String> {
    let Some(p) = path else { return Ok(None) };
    let (rw, rh, px) = read_linear(p)?;
    if (rw, rh) != (w, h) {
        return Err(format!(
            "{}: reference is {rw}x{rh}, the benchmark renders {w}x{h}",
            p.display()
        ));
    }
    Ok(Some(px))
}

/// A progress bar counting `frames` frames (hidden when `hidden`, e.g. for JSON output).
pub fn frame_bar(frames: u64, hidden: bool) -> Result<ProgressBar, String> {
    let bar = if hidden {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(frames)
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed} elapsed, ETA {eta}")
            .map_err(|e| e.to_string())?,
    );
    Ok(bar)
}

/// Prints the CSV `lines` and, with `csv`, writes them to that file too.
pub fn emit_csv(lines: &[String], csv: Option<&PathBuf>) -> Result<(), String> {
    if let Some(p) = csv {
        let mut f = solari_app::output::AtomicFile::create(p)?;
        for l in lines {
            writeln!(f.writer(), "{l}").map_err(|e| e.to_string())?;
        }
        f.commit()?;
        eprintln!("wrote {}", p.display());
    }
    for l in lines {
        println!("{l}");
    }
    Ok(())
}
