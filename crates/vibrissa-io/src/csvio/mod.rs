//! Reading and writing the CSV files of the command line (observables, elastica,
//! reconstructions, tabulated contours), on top of the `csv` crate.
//!
//! Numbers are written in the shortest form that parses back to the identical `f64`, so a
//! value copied through a CSV file survives bit for bit. The reader is lenient about what
//! other programs produce (comma, tab or semicolon as the delimiter, detected from the
//! header; free column order, extra columns, whitespace, CRLF, quoted fields, a byte order
//! mark, `#` comment lines, decimal commas in semicolon files) and strict about what the
//! command needs, naming the file, line and column of every problem.
//!
//! Units: a table may have a sidecar `NAME.units.csv` (same header, one row of units, see
//! [`units_sidecar_path`]); [`write_units_sidecar`] writes one and [`read_units_sidecar`]
//! reads it back.
//!
//! - this module: [`CsvWriter`] and [`format_f64`], and the units sidecars;
//! - [`read`]: [`read_table`], the one reader of CSV files ([`Table`]);
//! - [`lines`]: [`LineReader`], the same reader one line at a time (standard input).

pub mod lines;
pub mod read;

pub use lines::{HeaderProblemKind, LineProblem, LineReader};
pub use read::{
    check_header, detect_delimiter, parse_f64, parse_table, read_table, required_number,
    CellProblem, HeaderProblem, Table,
};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::error::IoError;

/// One cell of a row to write.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell<'a> {
    /// A number, written round-trip exact (`NaN`, `inf`, `-inf` for non-finite values).
    Num(f64),
    /// A text value (written quoted if it contains a delimiter, quote or line break).
    Text(&'a str),
}

impl From<f64> for Cell<'_> {
    fn from(v: f64) -> Self {
        Cell::Num(v)
    }
}

impl<'a> From<&'a str> for Cell<'a> {
    fn from(v: &'a str) -> Self {
        Cell::Text(v)
    }
}

/// Formats `v` in the shortest decimal form that parses back to exactly `v`.
///
/// Plain notation is used for moderate magnitudes, scientific notation otherwise.
pub fn format_f64(v: f64) -> String {
    if v.is_nan() {
        return "NaN".to_string();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    let a = v.abs();
    if a == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Builds a CSV table in memory (comma separated, RFC 4180 quoting by the `csv` crate):
/// a header and rows of numbers and strings, or serde records.
#[derive(Debug, Clone)]
pub struct CsvWriter {
    columns: usize,
    text: String,
}

/// One record encoded by the `csv` crate (quoting as needed, `\n` terminated).
fn encode_record<I, T>(fields: I) -> Result<String, String>
where
    I: IntoIterator<Item = T>,
    T: AsRef<[u8]>,
{
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(fields).map_err(|e| e.to_string())?;
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| e.to_string())
}

impl CsvWriter {
    /// Starts a table with the given header.
    pub fn new(header: &[&str]) -> Self {
        // Encoding plain strings cannot fail; keep a readable fallback all the same.
        let text = encode_record(header).unwrap_or_else(|_| header.join(",") + "\n");
        CsvWriter {
            columns: header.len(),
            text,
        }
    }

    /// Appends one row.
    ///
    /// # Errors
    /// [`IoError::InvalidArgument`] if the row does not have as many cells as the header
    /// (a programming error of the caller, reported instead of panicking).
    pub fn push_row(&mut self, row: &[Cell<'_>]) -> Result<(), IoError> {
        if row.len() != self.columns {
            return Err(IoError::invalid_argument(
                "csv row",
                format!("{} cells", row.len()),
                format!("the header has {} columns", self.columns),
            ));
        }
        let fields: Vec<String> = row
            .iter()
            .map(|c| match c {
                Cell::Num(v) => format_f64(*v),
                Cell::Text(s) => (*s).to_string(),
            })
            .collect();
        let line = encode_record(&fields)
            .map_err(|e| IoError::invalid_argument("csv row", fields.join(","), e))?;
        self.text.push_str(&line);
        Ok(())
    }

    /// Appends a row made only of numbers (as [`CsvWriter::push_row`] writes them: a number
    /// never needs quoting, so the fields are joined here without a `csv` writer).
    pub fn push_numbers(&mut self, row: &[f64]) -> Result<(), IoError> {
        if row.len() != self.columns || row.is_empty() {
            let cells: Vec<Cell<'_>> = row.iter().map(|&v| Cell::Num(v)).collect();
            return self.push_row(&cells);
        }
        for (i, &v) in row.iter().enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            self.text.push_str(&format_f64(v));
        }
        self.text.push('\n');
        Ok(())
    }

    /// Appends serde records (structs whose fields are the columns, in header order; numbers
    /// are written shortest round-trip exact by the `csv` crate), through one `csv` writer
    /// (a writer costs an 8 KiB zeroed buffer: one a record was most of the cost of a
    /// table). Nothing is appended if a record fails.
    ///
    /// # Errors
    /// [`IoError::InvalidArgument`] for the first record that cannot be serialised as one
    /// row of as many fields as the header.
    pub fn push_records<T: serde::Serialize>(
        &mut self,
        records: impl IntoIterator<Item = T>,
    ) -> Result<(), IoError> {
        let bad = |reason: String| IoError::invalid_argument("csv record", "", reason);
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(Vec::new());
        let mut start = 0;
        for record in records {
            w.serialize(record).map_err(|e| bad(e.to_string()))?;
            w.flush().map_err(|e| bad(e.to_string()))?;
            let bytes = w.get_ref();
            let fields = count_fields(&bytes[start..]);
            if fields != self.columns {
                return Err(bad(format!(
                    "{fields} fields, the header has {} columns",
                    self.columns
                )));
            }
            start = bytes.len();
        }
        let bytes = w.into_inner().map_err(|e| bad(e.to_string()))?;
        self.text
            .push_str(&String::from_utf8(bytes).map_err(|e| bad(e.to_string()))?);
        Ok(())
    }

    /// The CSV text built so far.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// Writes the table to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), IoError> {
        write_atomic(path, self.text.as_bytes())
    }
}

/// The fields of one CSV record as the `csv` crate writes it (`,` between fields, `"`
/// quoting with `""` for a quote inside): one more than the commas outside quotes; 0 for
/// an empty record. (Parsing it back with a `csv::Reader` cost ~0.3 M instructions a row.)
fn count_fields(record: &[u8]) -> usize {
    let line = record
        .strip_suffix(b"\n")
        .map(|l| l.strip_suffix(b"\r").unwrap_or(l))
        .unwrap_or(record);
    if line.is_empty() {
        return 0;
    }
    let mut quoted = false;
    let mut commas = 0;
    for &b in line {
        match b {
            b'"' => quoted = !quoted,
            b',' if !quoted => commas += 1,
            _ => {}
        }
    }
    commas + 1
}

/// The sidecar holding the units of the CSV file `csv`: `NAME.units.csv` beside `NAME.csv`.
pub fn units_sidecar_path(csv: &Path) -> PathBuf {
    let stem = csv
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    csv.with_file_name(format!("{stem}.units.csv"))
}

/// Writes a units sidecar: the header of the table and one row with each column's unit
/// (`mm`, `N`, `N mm`, `rad`, `1` for dimensionless, empty for text columns).
pub fn write_units_sidecar(path: &Path, header: &[&str], units: &[&str]) -> Result<(), IoError> {
    let mut w = CsvWriter::new(header);
    let cells: Vec<Cell<'_>> = units.iter().map(|u| Cell::Text(u)).collect();
    w.push_row(&cells)?;
    w.write(path)
}

/// Reads a units sidecar written by [`write_units_sidecar`] (or by hand): column name ->
/// unit. `Ok(None)` if the file does not exist.
pub fn read_units_sidecar(path: &Path) -> Result<Option<BTreeMap<String, String>>, IoError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(IoError::io(path, e)),
    };
    let table = parse_table(&text, path, &[], 1)?;
    if table.rows() != 1 {
        return Err(IoError::Csv {
            path: path.to_path_buf(),
            line: table.line_of(1).unwrap_or(table.header_line),
            column: None,
            reason: format!(
                "a units file has one row of units under its header, found {}",
                table.rows()
            ),
        });
    }
    let mut out = BTreeMap::new();
    for h in &table.header {
        let unit = match (table.text_column(h), table.column(h)) {
            (Some(t), _) => t[0].clone(),
            (None, Some(n)) => format_f64(n[0]),
            (None, None) => String::new(),
        };
        out.insert(h.clone(), unit);
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The field count of a written record is the `csv` reader's, with quotes, commas and
    /// quotes inside quotes, empty fields and NaN.
    #[test]
    fn fields_are_counted_as_the_csv_reader_counts_them() {
        let records: Vec<Vec<String>> = vec![
            vec!["1.5".into(), "NaN".into(), "".into()],
            vec!["a,b".into(), "say \"hi\"".into(), "x".into(), "".into()],
            vec!["single".into()],
            vec!["\"".into(), ",".into()],
        ];
        for rec in &records {
            let mut w = csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(Vec::new());
            w.serialize(rec).unwrap();
            let bytes = w.into_inner().unwrap();
            let read = csv::ReaderBuilder::new()
                .has_headers(false)
                .from_reader(bytes.as_slice())
                .records()
                .next()
                .unwrap()
                .unwrap()
                .len();
            assert_eq!(count_fields(&bytes), read, "{rec:?}");
        }
        assert_eq!(count_fields(b""), 0);
    }

    #[test]
    fn format_round_trips() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            -2.5e-7,
            6.02214076e23,
            f64::MIN_POSITIVE,
            f64::MAX,
            5e-324,
            123456.789,
        ] {
            let s = format_f64(v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
        }
        assert_eq!(format_f64(0.25), "0.25");
        assert_eq!(format_f64(1e-20), "1e-20");
    }

    #[test]
    fn writer_quotes_as_needed() {
        let mut w = CsvWriter::new(&["name", "v"]);
        w.push_row(&[Cell::Text("a,\"b\""), Cell::Num(0.5)])
            .unwrap();
        assert_eq!(w.as_str(), "name,v\n\"a,\"\"b\"\"\",0.5\n");
        assert!(w.push_numbers(&[1.0]).is_err());
    }

    /// Rows of numbers joined without the `csv` crate read as the crate writes them.
    #[test]
    fn number_rows_are_written_as_the_csv_crate_writes_them() {
        let rows = [
            [0.0, -0.0, 1.5, f64::NAN],
            [f64::INFINITY, f64::NEG_INFINITY, 1e-20, 6.02214076e23],
            [-2.5e-7, 1.0 / 3.0, 123456.789, 5e-324],
        ];
        let (mut fast, mut by_crate) = (CsvWriter::new(&["a", "b", "c", "d"]), None);
        let mut slow = CsvWriter::new(&["a", "b", "c", "d"]);
        for row in &rows {
            fast.push_numbers(row).unwrap();
            let cells: Vec<Cell<'_>> = row.iter().map(|&v| Cell::Num(v)).collect();
            slow.push_row(&cells).unwrap();
            by_crate = Some(slow.as_str().to_string());
        }
        assert_eq!(Some(fast.as_str().to_string()), by_crate);
        assert!(fast.push_numbers(&[1.0, 2.0]).is_err());
    }

    /// A batch of records is written as one record at a time would be; a batch with a bad
    /// record appends nothing.
    #[test]
    fn record_batches_match_single_records() {
        #[derive(serde::Serialize)]
        struct Rec<'a> {
            x: f64,
            name: &'a str,
        }
        let recs = [
            Rec {
                x: 0.1,
                name: "a,b",
            },
            Rec {
                x: f64::NAN,
                name: "",
            },
            Rec {
                x: -3e-9,
                name: "say \"hi\"",
            },
        ];
        let mut one = CsvWriter::new(&["x", "name"]);
        for r in &recs {
            one.push_records(std::iter::once(r)).unwrap();
        }
        let mut batch = CsvWriter::new(&["x", "name"]);
        batch.push_records(recs.iter()).unwrap();
        assert_eq!(one.as_str(), batch.as_str());
        let mut narrow = CsvWriter::new(&["x"]);
        assert!(narrow.push_records(recs.iter()).is_err());
        assert_eq!(narrow.as_str(), "x\n");
    }
}
