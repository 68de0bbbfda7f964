//! Rows of a quality sweep (`benches/results/quality_table.py`'s CSV): a setting per scene,
//! named SCALE-GI[-nodi] as `quality_h200.sh` runs it, with its GPU time and error.

use crate::table::Table;

/// One setting of one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct QualityRow {
    /// Scene name.
    pub scene: String,
    /// SCALE-GI[-nodi]: SCALE `50`, `67` (internal scale 0.5, 0.67 with the temporal
    /// upscaler), `100` (native) or `aa` (native, jittered through the upscaler); GI `cache`
    /// (specular GI off), `path` or `restir` (specular GI on); `-nodi`: ReSTIR DI without reuse.
    pub setting: String,
    /// GPU ms of the whole frame at the output size.
    pub gpu_ms: f64,
    /// relMSE of one frame against the reference (NaN where not measured).
    pub rel_mse: f64,
}

impl QualityRow {
    /// The scale part: `50`, `67`, `100` or `aa`.
    pub fn scale(&self) -> &str {
        self.setting.split('-').next().unwrap_or("")
    }

    /// The GI part: `cache`, `path` or `restir`.
    pub fn gi(&self) -> &str {
        self.setting.split('-').nth(1).unwrap_or("")
    }

    /// Whether ReSTIR DI ran with its reuse steps.
    pub fn di_reuse(&self) -> bool {
        !self.setting.split('-').any(|s| s == "nodi")
    }
}

/// Parses the CSV; the error names the line and column that failed.
pub fn parse_quality(text: &str) -> Result<Vec<QualityRow>, String> {
    let t = Table::parse(text)?;
    let (scene, setting, ms, err) = (
        t.column("scene")?,
        t.column("setting")?,
        t.column("gpu_ms")?,
        t.column("rel_mse")?,
    );
    (0..t.len())
        .map(|i| {
            Ok(QualityRow {
                scene: t.text(i, scene)?.to_string(),
                setting: t.text(i, setting)?.to_string(),
                gpu_ms: t.num(i, ms)?,
                rel_mse: t.num(i, err)?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_quality_table_writes_and_splits_settings() {
        let csv = "scene,setting,gpu_ms,wall_ms,rel_mse,flip,mean_ratio,chosen\n\
                   interior,67-path-nodi,3.06,3.17,0.00986,0.086,0.971,\n\
                   interior,aa-cache,6.36,6.48,nan,nan,nan,x\n";
        let rows = parse_quality(csv).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[0].scale(), rows[0].gi()), ("67", "path"));
        assert!(!rows[0].di_reuse() && rows[1].di_reuse());
        assert_eq!((rows[1].scale(), rows[1].gi()), ("aa", "cache"));
        assert!(rows[1].rel_mse.is_nan());
        let bad = parse_quality("scene,setting,gpu_ms,rel_mse\nx,100-path,slow,1\n");
        assert!(bad.unwrap_err().contains("gpu_ms"));
    }
}
