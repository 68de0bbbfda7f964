//! The CSV `solari bench-di` writes, read back for plotting.

use crate::table::Table;

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
    /// The light grid's share (`off` for tiles alone, also when the CSV predates the
    /// column).
    pub light_grid: String,
    /// GPU ms of light tiles plus both ReSTIR DI passes.
    pub lighting_ms: f64,
    /// RMSE of a frame against the reference.
    pub rmse: f64,
}

/// Parses the CSV; the error names the line and column that failed.
pub fn parse_sweep(text: &str) -> Result<Vec<SweepRow>, String> {
    let t = Table::parse(text)?;
    let (scene, cand, tiles, spt, ms, rmse) = (
        t.column("scene")?,
        t.column("candidates")?,
        t.column("tiles")?,
        t.column("samples_per_tile")?,
        t.column("lighting_ms")?,
        t.column("rmse")?,
    );
    let grid = t.column("light_grid_share").ok();
    (0..t.len())
        .map(|i| {
            Ok(SweepRow {
                light_grid: match grid {
                    Some(c) => t.text(i, c)?.to_string(),
                    None => "off".into(),
                },
                scene: t.text(i, scene)?.to_string(),
                candidates: t.num(i, cand)? as u32,
                tiles: t.num(i, tiles)? as u32,
                samples_per_tile: t.num(i, spt)? as u32,
                lighting_ms: t.num(i, ms)?,
                rmse: t.num(i, rmse)?,
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
        assert_eq!(rows[0].light_grid, "off");
        let grid = parse_sweep(
            "scene,candidates,tiles,samples_per_tile,light_grid_share,lighting_ms,rmse\n\
             f,8,128,1024,0.75,1,0.1\n",
        )
        .unwrap();
        assert_eq!(grid[0].light_grid, "0.75");
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
