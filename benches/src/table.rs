//! A small CSV reader for the files the `solari bench-*` commands write: a header line, then
//! comma-separated cells with no quoting. Errors name the line and column.

/// The parsed file.
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// Splits `text` into a header and non-empty rows.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        let header = lines
            .next()
            .filter(|l| !l.trim().is_empty())
            .ok_or("empty CSV")?
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect();
        Ok(Self { header, rows })
    }

    /// The index of the column called `name`.
    pub fn column(&self, name: &str) -> Result<usize, String> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or(format!("CSV has no column '{name}'"))
    }

    /// The number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether there are no data rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The text of row `row`, column `col`.
    pub fn text(&self, row: usize, col: usize) -> Result<&str, String> {
        self.rows[row]
            .get(col)
            .map(String::as_str)
            .ok_or(format!("line {}: too few columns", row + 2))
    }

    /// Row `row`, column `col` as a number (`NaN` reads as NaN: the benches write it for
    /// cells that have no value).
    pub fn num(&self, row: usize, col: usize) -> Result<f64, String> {
        self.text(row, col)?.parse::<f64>().map_err(|_| {
            format!(
                "line {}: column {} is not a number",
                row + 2,
                self.header[col]
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_missing_column_and_the_bad_cell() {
        let t = Table::parse("a,b\n1,x\n\n2\n").unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t.num(0, 0).unwrap(), 1.0);
        assert!(t.num(0, 1).unwrap_err().contains("line 2: column b"));
        assert!(t.text(1, 1).unwrap_err().contains("too few"));
        assert!(t.column("c").unwrap_err().contains("'c'"));
        assert!(Table::parse("").is_err());
        assert!(
            Table::parse("a\nNaN\n")
                .unwrap()
                .num(0, 0)
                .unwrap()
                .is_nan()
        );
    }
}
