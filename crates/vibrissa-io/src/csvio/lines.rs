//! The CSV reader one line at a time ([`LineReader`]), for a log that arrives on standard
//! input: the dialect of [`read_table`](super::read_table) (its delimiter detection, header
//! check and reading of required values), each line one record.

use super::read::{
    check_header, csv_reason, detect_delimiter, reader_of, required_number, CellProblem,
    HeaderProblem,
};

/// What is wrong with a line read by a [`LineReader`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LineProblem {
    /// The header line (field index or column name, see [`HeaderProblem`]).
    Header(String, HeaderProblemKind),
    /// A row with another number of fields than the header.
    Fields {
        /// Fields found.
        found: usize,
        /// Fields of the header.
        expected: usize,
    },
    /// A value of a required column (its index in `required`, the value as given).
    Cell(usize, String, CellProblem),
    /// The line is no CSV record (the csv crate's reason).
    Csv(String),
}

/// The kind of a [`HeaderProblem`], owned (for [`LineProblem::Header`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeaderProblemKind {
    /// A field is empty (the name is its 1-based index).
    Empty,
    /// The column appears twice.
    Twice,
    /// A required column is missing.
    Missing,
}

/// A CSV text read one line at a time (standard input as it comes), in the dialect of
/// [`read_table`](super::read_table): the delimiter detected from the header, fields trimmed and unquoted by
/// the `csv` crate, decimal commas in semicolon files, the required columns numeric and
/// finite. Lines that are blank or `#` comments are for the caller to skip
/// ([`LineReader::skips`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineReader {
    delimiter: u8,
    width: usize,
    required: Vec<usize>,
}

impl LineReader {
    /// Whether a line carries no record: blank, or a `#` comment.
    pub fn skips(line: &str) -> bool {
        line.trim().is_empty() || line.trim_start().starts_with('#')
    }

    /// Reads the header line, which must name the `required` columns.
    pub fn header(line: &str, required: &[&str]) -> Result<Self, LineProblem> {
        let line = line.trim_start_matches('\u{feff}');
        let delimiter = detect_delimiter(line);
        let names = split_line(line, delimiter)?;
        check_header(&names, required).map_err(|p| match p {
            HeaderProblem::Empty(i) => {
                LineProblem::Header((i + 1).to_string(), HeaderProblemKind::Empty)
            }
            HeaderProblem::Twice(h) => LineProblem::Header(h.to_string(), HeaderProblemKind::Twice),
            HeaderProblem::Missing(r) => {
                LineProblem::Header(r.to_string(), HeaderProblemKind::Missing)
            }
        })?;
        let required = required
            .iter()
            .filter_map(|r| names.iter().position(|h| h == r))
            .collect();
        Ok(LineReader {
            delimiter,
            width: names.len(),
            required,
        })
    }

    /// The values of the required columns of a data line, in the order they were required.
    pub fn values(&self, line: &str) -> Result<Vec<f64>, LineProblem> {
        let fields = split_line(line, self.delimiter)?;
        if fields.len() != self.width {
            return Err(LineProblem::Fields {
                found: fields.len(),
                expected: self.width,
            });
        }
        self.required
            .iter()
            .enumerate()
            .map(|(j, &c)| {
                required_number(&fields[c], self.delimiter)
                    .map_err(|p| LineProblem::Cell(j, fields[c].clone(), p))
            })
            .collect()
    }
}

/// The fields of one line (one record; trimmed, unquoted).
fn split_line(line: &str, delimiter: u8) -> Result<Vec<String>, LineProblem> {
    let mut reader = reader_of(line.as_bytes(), delimiter);
    match reader.records().next() {
        None => Ok(Vec::new()),
        Some(Err(e)) => Err(LineProblem::Csv(csv_reason(&e))),
        Some(Ok(rec)) => Ok(rec.iter().map(str::to_string).collect()),
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::csvio::parse_table;
    use std::path::Path;

    #[test]
    fn a_line_reader_reads_as_the_table_reader() {
        let r = LineReader::header("\u{feff}b; a ;c", &["a", "c"]).unwrap();
        assert_eq!(r.values("1;2,5;\"3\"").unwrap(), vec![2.5, 3.0]);
        assert_eq!(
            r.values("1;2"),
            Err(LineProblem::Fields {
                found: 2,
                expected: 3
            })
        );
        assert_eq!(
            r.values("1;x;inf"),
            Err(LineProblem::Cell(
                0,
                "x".to_string(),
                CellProblem::NotANumber
            ))
        );
        assert_eq!(
            r.values("1;2;inf"),
            Err(LineProblem::Cell(
                1,
                "inf".to_string(),
                CellProblem::NotFinite
            ))
        );
        assert_eq!(
            LineReader::header("a,b", &["c"]),
            Err(LineProblem::Header(
                "c".to_string(),
                HeaderProblemKind::Missing
            ))
        );
        assert!(LineReader::skips("  # note") && LineReader::skips(" ") && !LineReader::skips("1"));
        let t = parse_table("b;a;c\n1;2,5;3\n", Path::new("t.csv"), &["a", "c"], 1).unwrap();
        assert_eq!(t.column("a").unwrap(), &[2.5]);
    }
}
