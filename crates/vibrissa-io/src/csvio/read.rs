//! The one reader of the CSV files of the command line ([`read_table`] -> [`Table`]): the
//! delimiter detected from the header, lenient about what other programs write, strict
//! about the required columns, every problem named by file, line and column. The header
//! check and the reading of a required value are shared with [`super::LineReader`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::IoError;

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
pub fn read_table(path: &Path, required: &[&str], min_rows: usize) -> Result<Table, IoError> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
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

pub(super) fn delimiter_name(d: u8) -> &'static str {
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

/// What is wrong with a header: an empty field (its 0-based index), a column named twice,
/// a required column missing. Each reader words it for its source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeaderProblem<'h> {
    /// Field `i` (0-based) is empty.
    Empty(usize),
    /// The column appears twice.
    Twice(&'h str),
    /// A required column is missing.
    Missing(&'h str),
}

/// Checks a header (fields trimmed): no empty field, no column twice, every `required`
/// column present, in this order.
pub fn check_header<'h>(
    header: &'h [String],
    required: &[&'h str],
) -> Result<(), HeaderProblem<'h>> {
    for (i, h) in header.iter().enumerate() {
        if h.is_empty() {
            return Err(HeaderProblem::Empty(i));
        }
        if header[..i].contains(h) {
            return Err(HeaderProblem::Twice(h));
        }
    }
    match required.iter().find(|r| !header.iter().any(|h| h == *r)) {
        Some(r) => Err(HeaderProblem::Missing(r)),
        None => Ok(()),
    }
}

/// What is wrong with a value of a required column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellProblem {
    /// The value does not parse as a number.
    NotANumber,
    /// The value is NaN or infinite.
    NotFinite,
}

impl CellProblem {
    /// The message of the problem for `value`, as both readers give it.
    pub fn reason(self, value: &str) -> String {
        match self {
            CellProblem::NotANumber => {
                let shown = if value.is_empty() { "(empty)" } else { value };
                format!("`{shown}` is not a number")
            }
            CellProblem::NotFinite => format!("value `{value}` is not finite"),
        }
    }
}

/// A value of a required column: a number as [`parse_f64`] reads it, and finite.
pub fn required_number(value: &str, delimiter: u8) -> Result<f64, CellProblem> {
    match parse_f64(value, delimiter) {
        None => Err(CellProblem::NotANumber),
        Some(v) if !v.is_finite() => Err(CellProblem::NotFinite),
        Some(v) => Ok(v),
    }
}

/// The 1-based file lines of a CSV text: the line of the record whose reading began at a
/// byte (the csv crate reports where a record's reading began, right after the previous
/// record, before skipped blank and comment lines: this steps over those).
struct LineIndex<'t> {
    bytes: &'t [u8],
    newlines: Vec<usize>,
}

impl<'t> LineIndex<'t> {
    fn new(text: &'t str) -> Self {
        let bytes = text.as_bytes();
        let newlines = (0..bytes.len()).filter(|&i| bytes[i] == b'\n').collect();
        LineIndex { bytes, newlines }
    }

    fn line_at(&self, byte: u64) -> usize {
        let bytes = self.bytes;
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
        self.newlines.partition_point(|&k| k < i) + 1
    }

    fn of_record(&self, rec: &csv::StringRecord) -> Option<usize> {
        rec.position().map(|p| self.line_at(p.byte()))
    }

    fn of_error(&self, e: &csv::Error) -> usize {
        e.position().map_or(1, |p| self.line_at(p.byte()))
    }
}

/// The csv crate's reader of this module's dialect: `delimiter`, no header handling,
/// records of any length, `#` comments, fields trimmed.
pub(super) fn reader_of(bytes: &[u8], delimiter: u8) -> csv::Reader<&[u8]> {
    csv::ReaderBuilder::new()
        .delimiter(delimiter)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(bytes)
}

/// The columns of a table, split into numeric and text ones: a column is numeric when every
/// value parses; a required column must be numeric and finite (else the 0-based row and
/// the problem of its first bad value, a value that is no number first).
fn split_columns(
    header: &[String],
    raw: Vec<Vec<String>>,
    required: &[&str],
    delimiter: u8,
) -> Result<Columns, (usize, String, String)> {
    let mut numeric = BTreeMap::new();
    let mut text_cols = BTreeMap::new();
    for (name, values) in header.iter().zip(raw) {
        let is_required = required.contains(&name.as_str());
        let parsed: Result<Vec<f64>, usize> = values
            .iter()
            .enumerate()
            .map(|(i, v)| parse_f64(v, delimiter).ok_or(i))
            .collect();
        let bad = |i: usize, p: CellProblem| (i, name.clone(), p.reason(&values[i]));
        match parsed {
            Ok(nums) => {
                if let Some(i) = nums.iter().position(|v| is_required && !v.is_finite()) {
                    return Err(bad(i, CellProblem::NotFinite));
                }
                numeric.insert(name.clone(), nums);
            }
            Err(i) if is_required => return Err(bad(i, CellProblem::NotANumber)),
            Err(_) => {
                text_cols.insert(name.clone(), values);
            }
        }
    }
    Ok((numeric, text_cols))
}

/// Numeric and text columns by name.
type Columns = (BTreeMap<String, Vec<f64>>, BTreeMap<String, Vec<String>>);

/// Parses CSV `text` as [`read_table`] does; `path` only names the source in errors.
pub fn parse_table(
    text: &str,
    path: &Path,
    required: &[&str],
    min_rows: usize,
) -> Result<Table, IoError> {
    let err = |line: usize, column: Option<&str>, reason: String| IoError::Csv {
        path: path.to_path_buf(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let delimiter = detect_delimiter(text);
    let mut reader = reader_of(text.as_bytes(), delimiter);
    let mut records = reader.records().filter(|r| match r {
        Ok(rec) => rec.iter().any(|f| !f.is_empty()),
        Err(_) => true,
    });
    let index = LineIndex::new(text);
    let (header_line, header) = match records.next() {
        None => {
            return Err(err(
                1,
                None,
                "the file is empty: no header line".to_string(),
            ))
        }
        Some(Err(e)) => return Err(err(index.of_error(&e), None, csv_reason(&e))),
        Some(Ok(rec)) => (
            index.of_record(&rec).unwrap_or(1),
            rec.iter().map(str::to_string).collect::<Vec<_>>(),
        ),
    };
    check_header(&header, required).map_err(|p| match p {
        HeaderProblem::Empty(i) => err(
            header_line,
            None,
            format!("header field {} is empty", i + 1),
        ),
        HeaderProblem::Twice(h) => err(
            header_line,
            Some(h),
            "the column appears twice in the header".to_string(),
        ),
        HeaderProblem::Missing(r) => err(
            header_line,
            Some(r),
            format!(
                "missing required column (the header has: {}; {} separated)",
                header.join(","),
                delimiter_name(delimiter)
            ),
        ),
    })?;
    let mut raw: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    let mut lines = Vec::new();
    let mut last_line = header_line;
    for rec in records {
        let rec = rec.map_err(|e| err(index.of_error(&e), None, csv_reason(&e)))?;
        let line = index.of_record(&rec).unwrap_or(last_line + 1);
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
    let (numeric, text_cols) = split_columns(&header, raw, required, delimiter)
        .map_err(|(i, name, reason)| err(lines[i], Some(&name), reason))?;
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

/// The csv crate's reason for an error, without the position it repeats.
pub(super) fn csv_reason(e: &csv::Error) -> String {
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
#[cfg(test)]
mod tests {
    use super::*;

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
    fn headers_and_required_values_are_checked_alike() {
        let h = |s: &str| s.split(',').map(str::to_string).collect::<Vec<_>>();
        assert_eq!(check_header(&h("x,y"), &["y"]), Ok(()));
        assert_eq!(check_header(&h("x,,y"), &[]), Err(HeaderProblem::Empty(1)));
        assert_eq!(check_header(&h("x,x"), &[]), Err(HeaderProblem::Twice("x")));
        assert_eq!(
            check_header(&h("x,y"), &["z"]),
            Err(HeaderProblem::Missing("z"))
        );
        assert_eq!(required_number(" 1,5", b';'), Ok(1.5));
        assert_eq!(required_number("NaN", b','), Err(CellProblem::NotFinite));
        assert_eq!(required_number("", b','), Err(CellProblem::NotANumber));
        assert_eq!(
            CellProblem::NotANumber.reason(""),
            "`(empty)` is not a number"
        );
    }

    #[test]
    fn quoted_fields_are_read() {
        let t = parse_table(" a , b \n x ,\"b,c\"\n", Path::new("q.csv"), &[], 1).unwrap();
        assert_eq!(t.text_column("b").unwrap(), &["b,c"]);
        let e = parse_table("a,b\n1\n", Path::new("r.csv"), &["a"], 1).unwrap_err();
        assert!(
            e.to_string()
                .contains("expected 2 fields as in the header, found 1"),
            "{e}"
        );
    }
}
