//! A small CSV table: a header and rows of already formatted cells; cells
//! containing commas, quotes or newlines are quoted (RFC 4180).

/// A CSV table.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CsvTable {
    /// Column names.
    pub header: Vec<String>,
    /// Rows (each as long as the header; shorter rows are padded on output).
    pub rows: Vec<Vec<String>>,
}

impl CsvTable {
    /// An empty table with these columns.
    pub fn new<S: AsRef<str>>(header: &[S]) -> CsvTable {
        CsvTable {
            header: header.iter().map(|s| s.as_ref().to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push(&mut self, row: Vec<String>) {
        self.rows.push(row);
    }

    /// The table as CSV text.
    pub fn to_csv(&self) -> String {
        let mut s = line(&self.header);
        for r in &self.rows {
            let mut r = r.clone();
            r.resize(self.header.len().max(r.len()), String::new());
            s.push_str(&line(&r));
        }
        s
    }
}

fn line(cells: &[String]) -> String {
    let mut s = cells.iter().map(|c| quote(c)).collect::<Vec<_>>().join(",");
    s.push('\n');
    s
}

fn quote(cell: &str) -> String {
    if cell.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", cell.replace('"', "\"\""))
    } else {
        cell.to_string()
    }
}

/// Formats a number for CSV (shortest round-trip form; empty for NaN).
pub fn num(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v}")
    }
}

/// Formats an optional number (empty when absent).
pub fn opt(v: Option<f64>) -> String {
    v.map(num).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_and_pads() {
        let mut t = CsvTable::new(&["a", "b"]);
        t.push(vec!["1,5".into(), "x\"y".into()]);
        t.push(vec!["2".into()]);
        assert_eq!(t.to_csv(), "a,b\n\"1,5\",\"x\"\"y\"\n2,\n");
        assert_eq!(opt(None), "");
        assert_eq!(num(0.5), "0.5");
    }
}
