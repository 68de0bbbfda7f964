//! The CSV `solari bench-di` writes, read back for plotting.

/// One row: a setting and what it cost and scored.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// Scene name.
    pub scene: String,
    /// Initial candidates.
    pub candidates: u32,
    /// Light tiles.
    pub tiles: u32,
    /// Samples per tile.
    pub samples_per_tile: u32,
    /// GPU ms of light tiles plus both ReSTIR DI passes.
    pub lighting_ms: f64,
    /// RMSE of a frame against the reference.
    pub rmse: f64,
}

/// Parses the CSV; the error names the line and column that failed.
pub fn parse_sweep(text: &str) -> Result<Vec<SweepRow>, String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty CSV")?.split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or(format!("CSV has no column '{name}'"))
    };
    let (scene, cand, tiles, spt, ms, rmse) = (
        col("scene")?,
        col("candidates")?,
        col("tiles")?,
        col("samples_per_tile")?,
        col("lighting_ms")?,
        col("rmse")?,
    );
    lines
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let f: Vec<&str> = l.split(',').collect();
            let get = |c: usize| {
                f.get(c)
                    .copied()
                    .ok_or(format!("line {}: too few columns", i + 2))
            };
            let num = |c: usize| -> Result<f64, String> {
                get(c)?
                    .parse::<f64>()
                    .map_err(|_| format!("line {}: column {} is not a number", i + 2, header[c]))
            };
            Ok(SweepRow {
                scene: get(scene)?.to_string(),
                candidates: num(cand)? as u32,
                tiles: num(tiles)? as u32,
                samples_per_tile: num(spt)? as u32,
                lighting_ms: num(ms)?,
                rmse: num(rmse)?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_bench_di_writes_and_names_bad_cells() {
        let csv = "scene,width,candidates,tiles,samples_per_tile,lighting_ms,rmse\n\
                   box,64,8,128,1024,0.5,0.01\nbox,64,1,16,256,0.25,0.02\n";
        let rows = parse_sweep(csv).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].candidates, 1);
        assert_eq!(rows[0].lighting_ms, 0.5);
        let bad = parse_sweep(
            "scene,candidates,tiles,samples_per_tile,lighting_ms,rmse\nbox,x,1,1,1,1\n",
        );
        assert!(bad.unwrap_err().contains("candidates"));
        assert!(
            parse_sweep("scene,rmse\n")
                .unwrap_err()
                .contains("candidates")
        );
        assert!(parse_sweep("").is_err());
    }
}
