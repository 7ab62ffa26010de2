//! Where a CSV row is in its file, and what the csv crate's error of a row
//! says, as a user reads them: the file's line counted from its bytes (the
//! crate's own line numbers drift after CRLF endings and blank lines), and
//! the message without the crate's position. Shared by the readers of
//! user CSV files (the manifest, a risk inventory).

/// The 1-based line of `bytes` at which the record starting at byte `byte`
/// begins (a position may point at the line breaks before the record).
pub fn line_at(bytes: &[u8], byte: u64) -> u64 {
    line_of_byte(bytes, record_start(bytes, byte))
}

/// Where the record at byte `byte` starts: past the line breaks before it.
fn record_start(bytes: &[u8], byte: u64) -> usize {
    let mut at = usize::try_from(byte).map_or(bytes.len(), |b| b.min(bytes.len()));
    while at < bytes.len() && matches!(bytes[at], b'\n' | b'\r') {
        at += 1;
    }
    at
}

/// [`line_at`] for every row of one file: its line breaks found once, each
/// row's line by bisection (a count from the file's start for every row
/// made reading a manifest or an inventory quadratic: 10 s for 16,000 rows).
pub struct Lines<'a> {
    bytes: &'a [u8],
    /// The byte offsets of the file's '\n's, ascending.
    breaks: Vec<usize>,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        let breaks = (bytes.iter().enumerate())
            .filter(|(_, &b)| b == b'\n')
            .map(|(i, _)| i)
            .collect();
        Lines { bytes, breaks }
    }

    /// [`line_at`] of this file.
    pub fn line_at(&self, byte: u64) -> u64 {
        let at = record_start(self.bytes, byte);
        1 + self.breaks.partition_point(|&b| b < at) as u64
    }
}

/// The 1-based line of `bytes` that holds byte `at`.
fn line_of_byte(bytes: &[u8], at: usize) -> u64 {
    1 + bytes[..at].iter().filter(|&&b| b == b'\n').count() as u64
}

/// The line of the row `e` is about, if it is about one ([`line_at`]); for
/// a cell that is not UTF-8, the line of the file's first bad byte (the
/// crate gives such an error the position of the file's start).
pub fn error_line(bytes: &[u8], e: &csv::Error) -> Option<u64> {
    if let csv::ErrorKind::Utf8 { .. } = e.kind() {
        if let Err(bad) = std::str::from_utf8(bytes) {
            return Some(line_of_byte(bytes, bad.valid_up_to()));
        }
    }
    e.position().map(|p| line_at(bytes, p.byte()))
}

/// What a row's error says, without the crate's own position (the line
/// goes before it, from [`error_line`]).
pub fn message(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields where the header has {expected_len}"),
        csv::ErrorKind::Utf8 { err, .. } => format!("field {} is not UTF-8", err.field() + 1),
        _ => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lines counted by hand in each text: the record `b,2,extra` is on
    /// line 3 whatever the endings, and after a blank line on line 4.
    #[test]
    fn the_line_of_a_bad_row_whatever_the_line_endings() {
        for (text, line) in [
            ("n,x\na,1\nb,2,extra\n", 3),
            ("n,x\r\na,1\r\nb,2,extra\r\n", 3),
            ("n,x\n\na,1\nb,2,extra\n", 4),
            ("n,x\r\n\r\na,1\r\nb,2,extra\r\n", 4),
        ] {
            let mut csv = csv::ReaderBuilder::new().from_reader(text.as_bytes());
            let e = csv
                .records()
                .find_map(Result::err)
                .expect("the third field is refused");
            assert_eq!(error_line(text.as_bytes(), &e), Some(line), "{text:?}");
            assert_eq!(message(&e), "3 fields where the header has 2");
        }
        let bad = b"n,x\na,1\nb,\xff\n";
        let mut csv = csv::ReaderBuilder::new().from_reader(&bad[..]);
        let e = csv.records().find_map(Result::err).expect("not UTF-8");
        assert_eq!(error_line(bad, &e), Some(3));
        assert_eq!(message(&e), "field 2 is not UTF-8");
    }

    /// Every row's line by the index is its line counted by hand: a quoted
    /// cell over two lines, CRLF endings, blank lines between rows.
    #[test]
    fn each_row_s_line_by_the_index() {
        let text = "n,x\r\na,1\r\n\r\nb,\"two\r\nlines\"\r\nc,3\n\n\nd,4";
        let lines = Lines::new(text.as_bytes());
        let mut csv = csv::ReaderBuilder::new().from_reader(text.as_bytes());
        let found: Vec<(String, u64)> = csv
            .records()
            .map(|r| {
                let r = r.unwrap();
                let byte = r.position().unwrap().byte();
                assert_eq!(lines.line_at(byte), line_at(text.as_bytes(), byte));
                (r[0].to_string(), lines.line_at(byte))
            })
            .collect();
        let want = [("a", 2), ("b", 4), ("c", 6), ("d", 9)];
        let want: Vec<(String, u64)> = want.iter().map(|(n, l)| (n.to_string(), *l)).collect();
        assert_eq!(found, want);
    }
}
