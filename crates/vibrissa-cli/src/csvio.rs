//! Reading and writing the CSV files of the command line (observables, elastica,
//! reconstructions).
//!
//! Numbers are written in the shortest form that parses back to the identical `f64`, so a
//! value copied through a CSV file survives bit for bit. The reader is lenient about what
//! other programs produce (free column order, extra columns, whitespace, CRLF, quoted
//! fields, a byte order mark) and strict about what the command needs, naming the file,
//! line and column of every problem.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::error::CliError;

/// One cell of a row to write.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell<'a> {
    /// A number, written round-trip exact (`NaN`, `inf`, `-inf` for non-finite values).
    Num(f64),
    /// A text value (written quoted if it contains a comma, quote or line break).
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

/// Builds a CSV text in memory: a header and rows of numbers and strings.
#[derive(Debug, Clone)]
pub struct CsvWriter {
    columns: usize,
    text: String,
}

impl CsvWriter {
    /// Starts a table with the given header.
    pub fn new(header: &[&str]) -> Self {
        let mut text = String::new();
        for (i, h) in header.iter().enumerate() {
            if i > 0 {
                text.push(',');
            }
            push_text(&mut text, h);
        }
        text.push('\n');
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
        for (i, c) in row.iter().enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            match c {
                Cell::Num(v) => {
                    let _ = write!(self.text, "{}", format_f64(*v));
                }
                Cell::Text(s) => push_text(&mut self.text, s),
            }
        }
        self.text.push('\n');
        Ok(())
    }

    /// Appends a row made only of numbers.
    pub fn push_numbers(&mut self, row: &[f64]) -> Result<(), CliError> {
        let cells: Vec<Cell<'_>> = row.iter().map(|&v| Cell::Num(v)).collect();
        self.push_row(&cells)
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

fn push_text(out: &mut String, s: &str) {
    if s.contains([',', '"', '\n', '\r']) || s.trim() != s {
        out.push('"');
        out.push_str(&s.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(s);
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
    let mut records = text
        .split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
        .filter(|(_, l)| {
            let t = l.trim();
            !t.is_empty() && !t.starts_with('#')
        });
    let (header_line, header_text) = records
        .next()
        .ok_or_else(|| err(1, None, "the file is empty: no header line".to_string()))?;
    let header = split_fields(header_text).map_err(|r| err(header_line, None, r))?;
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
                    "missing required column (the header has: {})",
                    header.join(",")
                ),
            ));
        }
    }
    let mut raw: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    let mut lines = Vec::new();
    let mut last_line = header_line;
    for (line, l) in records {
        last_line = line;
        let fields = split_fields(l).map_err(|r| err(line, None, r))?;
        if fields.len() != header.len() {
            return Err(err(
                line,
                None,
                format!(
                    "expected {} fields as in the header, found {}",
                    header.len(),
                    fields.len()
                ),
            ));
        }
        for (col, f) in raw.iter_mut().zip(fields) {
            col.push(f);
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
            .map(|(i, v)| v.parse::<f64>().map_err(|_| (i, v)))
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
    })
}

/// Splits one CSV line into trimmed fields, honouring double quotes (`""` inside quotes is
/// a quote). Returns the reason on an unterminated quote.
fn split_fields(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut cur = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut was_quoted = false;
    while let Some(c) = chars.next() {
        if quoted {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    chars.next();
                    cur.push('"');
                } else {
                    quoted = false;
                }
            } else {
                cur.push(c);
            }
        } else if c == '"' && cur.trim().is_empty() && !was_quoted {
            cur.clear();
            quoted = true;
            was_quoted = true;
        } else if c == ',' {
            fields.push(finish(&cur, was_quoted));
            cur.clear();
            was_quoted = false;
        } else {
            cur.push(c);
        }
    }
    if quoted {
        return Err("unterminated quoted field".to_string());
    }
    fields.push(finish(&cur, was_quoted));
    Ok(fields)
}

fn finish(cur: &str, was_quoted: bool) -> String {
    if was_quoted {
        // Inside quotes the text is kept; only what follows the closing quote is trimmed.
        cur.trim_end().to_string()
    } else {
        cur.trim().to_string()
    }
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
    fn quoted_fields() {
        assert_eq!(
            split_fields(r#" a , "b,c" ,"d""e" "#).unwrap(),
            vec!["a", "b,c", "d\"e"]
        );
        assert!(split_fields("\"abc").is_err());
    }
}
