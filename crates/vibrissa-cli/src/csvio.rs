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

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::error::CliError;

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

    /// The number of columns of the header.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Appends one row.
    ///
    /// # Errors
    /// [`CliError::InvalidArgument`] if the row does not have as many cells as the header
    /// (a programming error of the caller, reported instead of panicking).
    pub fn push_row(&mut self, row: &[Cell<'_>]) -> Result<(), CliError> {
        if row.len() != self.columns {
            return Err(CliError::invalid_argument(
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
            .map_err(|e| CliError::invalid_argument("csv row", fields.join(","), e))?;
        self.text.push_str(&line);
        Ok(())
    }

    /// Appends a row made only of numbers.
    pub fn push_numbers(&mut self, row: &[f64]) -> Result<(), CliError> {
        let cells: Vec<Cell<'_>> = row.iter().map(|&v| Cell::Num(v)).collect();
        self.push_row(&cells)
    }

    /// Appends one serde record (a struct whose fields are the columns, in header order;
    /// numbers are written shortest round-trip exact by the `csv` crate).
    ///
    /// # Errors
    /// [`CliError::InvalidArgument`] if the record cannot be serialised as one row of as
    /// many fields as the header.
    pub fn push_record<T: serde::Serialize>(&mut self, record: &T) -> Result<(), CliError> {
        let bad = |reason: String| CliError::invalid_argument("csv record", "", reason);
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(Vec::new());
        w.serialize(record).map_err(|e| bad(e.to_string()))?;
        let bytes = w.into_inner().map_err(|e| bad(e.to_string()))?;
        let fields = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(bytes.as_slice())
            .records()
            .next()
            .transpose()
            .map_err(|e| bad(e.to_string()))?
            .map_or(0, |r| r.len());
        if fields != self.columns {
            return Err(bad(format!(
                "{fields} fields, the header has {} columns",
                self.columns
            )));
        }
        self.text
            .push_str(&String::from_utf8(bytes).map_err(|e| bad(e.to_string()))?);
        Ok(())
    }

    /// The CSV text built so far.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// Writes the table to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), CliError> {
        write_atomic(path, self.text.as_bytes())
    }
}

/// A table read from a CSV file.
///
/// Columns whose every value parses as a number are numeric; the others (such as `phase`)
/// are kept as text. Required columns are always numeric and finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The file the table was read from.
    pub path: PathBuf,
    /// The column names in file order, trimmed.
    pub header: Vec<String>,
    /// The numeric columns by name.
    pub numeric: BTreeMap<String, Vec<f64>>,
    /// The text columns by name.
    pub text: BTreeMap<String, Vec<String>>,
    /// The 1-based file line of each data row.
    pub lines: Vec<usize>,
    /// The 1-based file line of the header.
    pub header_line: usize,
    /// The delimiter found in the header (`,`, tab or `;`).
    pub delimiter: u8,
}

impl Table {
    /// The number of data rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// The numeric column `name`, if there is one.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.numeric.get(name).map(Vec::as_slice)
    }

    /// The text column `name`, if there is one (numeric columns are not listed here).
    pub fn text_column(&self, name: &str) -> Option<&[String]> {
        self.text.get(name).map(Vec::as_slice)
    }

    /// The 1-based file line of data row `row` (0-based), for error messages.
    pub fn line_of(&self, row: usize) -> Option<usize> {
        self.lines.get(row).copied()
    }
}

/// Reads the CSV file `path`, requiring the numeric, finite columns `required` and at least
/// `min_rows` data rows.
pub fn read_table(path: &Path, required: &[&str], min_rows: usize) -> Result<Table, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::io(path, e))?;
    parse_table(&text, path, required, min_rows)
}

/// The delimiter of a CSV text: the one of `,`, tab and `;` that occurs most often (outside
/// quotes) in its first line that is neither empty nor a comment; `,` if none occurs.
pub fn detect_delimiter(text: &str) -> u8 {
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    let mut counts = [(b',', 0usize), (b'\t', 0), (b';', 0)];
    let mut quoted = false;
    for c in first.bytes() {
        if c == b'"' {
            quoted = !quoted;
        } else if !quoted {
            for (d, n) in counts.iter_mut() {
                if c == *d {
                    *n += 1;
                }
            }
        }
    }
    counts
        .iter()
        .copied()
        .max_by_key(|&(d, n)| (n, d == b','))
        .filter(|&(_, n)| n > 0)
        .map_or(b',', |(d, _)| d)
}

fn delimiter_name(d: u8) -> &'static str {
    match d {
        b'\t' => "tab",
        b';' => "semicolon",
        _ => "comma",
    }
}

/// Parses one number as written by people and programs: `1.5`, `-2e-3`, `inf`, `NaN`, and
/// in a semicolon-separated file also a decimal comma (`1,5`).
pub fn parse_f64(s: &str, delimiter: u8) -> Option<f64> {
    let s = s.trim();
    if let Ok(v) = s.parse::<f64>() {
        return Some(v);
    }
    if delimiter == b';' && s.contains(',') && !s.contains('.') {
        return s.replacen(',', ".", 1).parse::<f64>().ok();
    }
    None
}

/// Parses CSV `text` as [`read_table`] does; `path` only names the source in errors.
pub fn parse_table(
    text: &str,
    path: &Path,
    required: &[&str],
    min_rows: usize,
) -> Result<Table, CliError> {
    let err = |line: usize, column: Option<&str>, reason: String| CliError::Csv {
        path: path.to_path_buf(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let delimiter = detect_delimiter(text);
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(delimiter)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut records = reader.records().filter(|r| match r {
        Ok(rec) => rec.iter().any(|f| !f.is_empty()),
        Err(_) => true,
    });
    // 1-based file lines. The csv crate reports where a record's reading began (right
    // after the previous record, before skipped blank and comment lines): step over those
    // to the record's first line.
    let bytes = text.as_bytes();
    let newlines: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .map(|(i, _)| i)
        .collect();
    let line_at = |byte: u64| {
        let mut i = (byte as usize).min(bytes.len());
        loop {
            while i < bytes.len() && (bytes[i] == b'\n' || bytes[i] == b'\r') {
                i += 1;
            }
            let end = bytes[i..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |k| i + k);
            let line = &bytes[i..end];
            let skip = line.first() == Some(&b'#')
                || (!line.is_empty() && line.iter().all(u8::is_ascii_whitespace));
            if skip && end < bytes.len() {
                i = end;
            } else {
                break;
            }
        }
        newlines.partition_point(|&k| k < i) + 1
    };
    let line_of_err = |e: &csv::Error| e.position().map_or(1, |p| line_at(p.byte()));
    let (header_line, header) = match records.next() {
        None => {
            return Err(err(
                1,
                None,
                "the file is empty: no header line".to_string(),
            ))
        }
        Some(Err(e)) => return Err(err(line_of_err(&e), None, csv_reason(&e))),
        Some(Ok(rec)) => (
            rec.position().map_or(1, |p| line_at(p.byte())),
            rec.iter().map(str::to_string).collect::<Vec<_>>(),
        ),
    };
    for (i, h) in header.iter().enumerate() {
        if h.is_empty() {
            return Err(err(
                header_line,
                None,
                format!("header field {} is empty", i + 1),
            ));
        }
        if header[..i].contains(h) {
            return Err(err(
                header_line,
                Some(h),
                "the column appears twice in the header".to_string(),
            ));
        }
    }
    for r in required {
        if !header.iter().any(|h| h == r) {
            return Err(err(
                header_line,
                Some(r),
                format!(
                    "missing required column (the header has: {}; {} separated)",
                    header.join(","),
                    delimiter_name(delimiter)
                ),
            ));
        }
    }
    let mut raw: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    let mut lines = Vec::new();
    let mut last_line = header_line;
    for rec in records {
        let rec = rec.map_err(|e| err(line_of_err(&e), None, csv_reason(&e)))?;
        let line = rec.position().map_or(last_line + 1, |p| line_at(p.byte()));
        last_line = line;
        if rec.len() != header.len() {
            return Err(err(
                line,
                None,
                format!(
                    "expected {} fields as in the header, found {} ({} separated)",
                    header.len(),
                    rec.len(),
                    delimiter_name(delimiter)
                ),
            ));
        }
        for (col, f) in raw.iter_mut().zip(rec.iter()) {
            col.push(f.to_string());
        }
        lines.push(line);
    }
    let mut numeric = BTreeMap::new();
    let mut text_cols = BTreeMap::new();
    for (name, values) in header.iter().zip(raw) {
        let is_required = required.contains(&name.as_str());
        let parsed: Result<Vec<f64>, (usize, &String)> = values
            .iter()
            .enumerate()
            .map(|(i, v)| parse_f64(v, delimiter).ok_or((i, v)))
            .collect();
        match parsed {
            Ok(nums) => {
                if is_required {
                    if let Some(i) = nums.iter().position(|v| !v.is_finite()) {
                        return Err(err(
                            lines[i],
                            Some(name),
                            format!("value `{}` is not finite", values[i]),
                        ));
                    }
                }
                numeric.insert(name.clone(), nums);
            }
            Err((i, v)) => {
                if is_required {
                    let shown = if v.is_empty() { "(empty)" } else { v.as_str() };
                    return Err(err(
                        lines[i],
                        Some(name),
                        format!("`{shown}` is not a number"),
                    ));
                }
                text_cols.insert(name.clone(), values);
            }
        }
    }
    if lines.len() < min_rows {
        return Err(err(
            last_line,
            None,
            format!(
                "expected at least {min_rows} data rows, found {}",
                lines.len()
            ),
        ));
    }
    Ok(Table {
        path: path.to_path_buf(),
        header,
        numeric,
        text: text_cols,
        lines,
        header_line,
        delimiter,
    })
}

fn csv_reason(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::Utf8 { .. } => "the line is not valid UTF-8 text".to_string(),
        _ => {
            // The csv crate's message repeats the position; keep what follows it.
            let s = e.to_string();
            s.rsplit_once("): ")
                .map_or(s.clone(), |(_, r)| r.to_string())
        }
    }
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
pub fn write_units_sidecar(path: &Path, header: &[&str], units: &[&str]) -> Result<(), CliError> {
    let mut w = CsvWriter::new(header);
    let cells: Vec<Cell<'_>> = units.iter().map(|u| Cell::Text(u)).collect();
    w.push_row(&cells)?;
    w.write(path)
}

/// Reads a units sidecar written by [`write_units_sidecar`] (or by hand): column name ->
/// unit. `Ok(None)` if the file does not exist.
pub fn read_units_sidecar(path: &Path) -> Result<Option<BTreeMap<String, String>>, CliError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(CliError::io(path, e)),
    };
    let table = parse_table(&text, path, &[], 1)?;
    if table.rows() != 1 {
        return Err(CliError::Csv {
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
    fn delimiters_are_detected_from_the_header() {
        assert_eq!(detect_delimiter("# c\nx_mm;y_mm\n1,5;2\n"), b';');
        assert_eq!(detect_delimiter("x\ty\n"), b'\t');
        assert_eq!(detect_delimiter("\"a;b\",c\n"), b',');
        assert_eq!(detect_delimiter("x\n"), b',');
        assert_eq!(parse_f64("1,5", b';'), Some(1.5));
        assert_eq!(parse_f64("1,5", b','), None);
    }

    #[test]
    fn quoted_fields_and_writer() {
        let t = parse_table(" a , b \n x ,\"b,c\"\n", Path::new("q.csv"), &[], 1).unwrap();
        assert_eq!(t.text_column("b").unwrap(), &["b,c"]);
        let mut w = CsvWriter::new(&["name", "v"]);
        w.push_row(&[Cell::Text("a,\"b\""), Cell::Num(0.5)])
            .unwrap();
        assert_eq!(w.as_str(), "name,v\n\"a,\"\"b\"\"\",0.5\n");
    }
}
