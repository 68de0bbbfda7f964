//! The CSV `benches/results/gi_table.py` writes from a `gi_h200.sh` run, read back for
//! plotting: one row per scene and GI mode.

use crate::table::Table;

/// One scene and mode: what a frame cost and how far it was from the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct GiRow {
    /// Scene name.
    pub scene: String,
    /// Mode as gi_h200.sh names it: a GI mode with `+spec` (specular GI) and `+nodi`
    /// (ReSTIR DI without reuse) suffixes.
    pub mode: String,
    /// GPU ms of the whole frame at 1920×1080.
    pub gpu_ms: f64,
    /// relMSE of one frame against the reference.
    pub rel_mse_1: f64,
    /// relMSE of the mean of 16 frames.
    pub rel_mse_16: f64,
    /// What the reference's own noise adds to both (`compare --reference-variance`); NaN
    /// where the run did not record it (the column is absent or `nan`).
    pub reference_noise: f64,
}

impl GiRow {
    /// The GI mode without its suffixes (`cache`, `path`, `restir`, `off`).
    pub fn gi(&self) -> &str {
        self.mode.split('+').next().unwrap_or("")
    }

    /// Whether specular GI ran.
    pub fn specular(&self) -> bool {
        self.mode.split('+').any(|s| s == "spec")
    }

    /// Whether ReSTIR DI ran with its reuse steps.
    pub fn di_reuse(&self) -> bool {
        !self.mode.split('+').any(|s| s == "nodi")
    }

    /// One frame's relMSE without the reference's noise where the run recorded it, else as
    /// measured. At least [`MIN_OWN_ERROR_SHARE`] of the measured figure stays, as automatic
    /// quality counts it (`solari_renderer::auto_quality::ErrorTable::own_error`): the noise
    /// is an estimate, and a frame measured below it still has an error to plot.
    pub fn own_rel_mse_1(&self) -> f64 {
        if self.reference_noise.is_finite() {
            (self.rel_mse_1 - self.reference_noise).max(MIN_OWN_ERROR_SHARE * self.rel_mse_1)
        } else {
            self.rel_mse_1
        }
    }
}

/// `solari_renderer::auto_quality::MIN_OWN_ERROR_SHARE` (this crate does not depend on the
/// renderer): the least share of a measured relMSE counted as the frame's own.
pub const MIN_OWN_ERROR_SHARE: f64 = 0.05;

/// Parses the CSV; the error names the line and column that failed.
pub fn parse_gi(text: &str) -> Result<Vec<GiRow>, String> {
    let t = Table::parse(text)?;
    let (scene, mode, ms, e1, e16) = (
        t.column("scene")?,
        t.column("mode")?,
        t.column("gpu_ms")?,
        t.column("rel_mse_1")?,
        t.column("rel_mse_16")?,
    );
    let noise = t.column("reference_noise").ok();
    (0..t.len())
        .map(|i| {
            Ok(GiRow {
                scene: t.text(i, scene)?.to_string(),
                mode: t.text(i, mode)?.to_string(),
                gpu_ms: t.num(i, ms)?,
                rel_mse_1: t.num(i, e1)?,
                rel_mse_16: t.num(i, e16)?,
                reference_noise: noise.map_or(Ok(f64::NAN), |c| t.num(i, c))?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_gi_table_writes_and_names_bad_cells() {
        let csv = "scene,mode,gpu_ms,di_ms,gi_ms,specular_ms,rel_mse_1,rel_mse_16,flip_1,mean_ratio_1\n\
                   interior,path+spec+nodi,5.47,0.3,1.47,0.53,0.00872,0.00846,0.09,1.01\n\
                   interior,restir,9.86,1.6,5.02,0,0.01435,0.01439,0.13,0.96\n";
        let rows = parse_gi(csv).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].gi(), "path");
        assert!(rows[0].specular() && !rows[0].di_reuse());
        assert!(!rows[1].specular() && rows[1].di_reuse());
        assert_eq!(rows[1].gpu_ms, 9.86);
        assert!(rows[1].reference_noise.is_nan());
        assert_eq!(rows[1].own_rel_mse_1(), 0.01435);
        let with_noise = parse_gi(
            "scene,mode,gpu_ms,rel_mse_1,rel_mse_16,reference_noise\n\
             interior,path,3.8,0.0066,0.0065,0.0046\ninterior,rq,4.0,0.0067,0.0066,nan\n",
        )
        .unwrap();
        assert!((with_noise[0].own_rel_mse_1() - 0.002).abs() < 1e-12);
        assert_eq!(with_noise[1].own_rel_mse_1(), 0.0067);
        // Measured below the noise: 5% of the figure stays.
        let below = parse_gi(
            "scene,mode,gpu_ms,rel_mse_1,rel_mse_16,reference_noise\ninterior,path,3.8,0.004,0.004,0.0046\n",
        )
        .unwrap();
        assert!((below[0].own_rel_mse_1() - MIN_OWN_ERROR_SHARE * 0.004).abs() < 1e-12);
        let bad = parse_gi("scene,mode,gpu_ms,rel_mse_1,rel_mse_16\nx,path,fast,1,1\n");
        assert!(bad.unwrap_err().contains("gpu_ms"));
        assert!(parse_gi("scene,mode\n").unwrap_err().contains("gpu_ms"));
    }
}
