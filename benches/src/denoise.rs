//! The CSV `solari bench-denoise` writes, read back for plotting.

use crate::table::Table;

/// One row: one frame of one à-trous setting.
#[derive(Clone, Debug, PartialEq)]
pub struct DenoiseRow {
    /// Scene name.
    pub scene: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// À-trous iterations.
    pub iterations: u32,
    /// Frame number, from 1.
    pub frame: u32,
    /// The denoiser's mean GPU ms per frame in the setting's timing run (no read-backs).
    pub denoise_ms: f64,
    /// RMSE of the raw frame.
    pub rmse_raw: f64,
    /// RMSE of the mean of the raw frames so far.
    pub rmse_raw_mean: f64,
    /// RMSE of the denoised frame.
    pub rmse_denoised: f64,
    /// RMS change of the raw frame from the previous one (NaN on frame 1).
    pub change_raw: f64,
    /// RMS change of the denoised frame from the previous one (NaN on frame 1).
    pub change_denoised: f64,
}

/// Parses the CSV; the error names the line and column that failed.
pub fn parse_denoise(text: &str) -> Result<Vec<DenoiseRow>, String> {
    let t = Table::parse(text)?;
    let names = [
        "width",
        "height",
        "iterations",
        "frame",
        "denoise_ms",
        "rmse_raw",
        "rmse_raw_mean",
        "rmse_denoised",
        "change_raw",
        "change_denoised",
    ];
    let scene = t.column("scene")?;
    let cols: Vec<usize> = names
        .iter()
        .map(|n| t.column(n))
        .collect::<Result<_, _>>()?;
    (0..t.len())
        .map(|i| {
            let v: Vec<f64> = cols
                .iter()
                .map(|c| t.num(i, *c))
                .collect::<Result<_, _>>()?;
            Ok(DenoiseRow {
                scene: t.text(i, scene)?.to_string(),
                width: v[0] as u32,
                height: v[1] as u32,
                iterations: v[2] as u32,
                frame: v[3] as u32,
                denoise_ms: v[4],
                rmse_raw: v[5],
                rmse_raw_mean: v[6],
                rmse_denoised: v[7],
                change_raw: v[8],
                change_denoised: v[9],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_bench_denoise_writes() {
        let csv = "scene,width,height,tracer,adapter,iterations,frame,denoise_ms,rmse_raw,\
                   rmse_raw_mean,rmse_denoised,energy_denoised,change_raw,change_denoised\n\
                   box,64,64,software,gpu,5,1,1.0,0.008,0.008,0.007,1.0,NaN,NaN\n\
                   box,64,64,software,gpu,5,2,1.0,0.008,0.006,0.006,1.0,0.01,0.002\n";
        let rows = parse_denoise(csv).unwrap();
        assert_eq!(rows.len(), 2);
        assert!(rows[0].change_raw.is_nan());
        assert_eq!((rows[1].frame, rows[1].change_denoised), (2, 0.002));
        let bad = parse_denoise("scene,width\nbox,64\n").unwrap_err();
        assert!(bad.contains("height"), "{bad}");
    }
}
