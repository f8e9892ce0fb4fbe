//! CSV fields as RFC 4180 writes them: the one quoting rule of every file the bench writes
//! (results.csv, scaling.csv, scaling_points.csv, motion.csv, motion_frames.csv). Invariant: a
//! field holding a comma, a double quote or a line break is quoted with its quotes doubled, so
//! every row has its header's column count whatever a scene file, a glTF camera or a parameter
//! set is named.

/// `s` as one CSV field: unchanged when it needs no quoting, else quoted with `"` doubled.
pub fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One CSV line split into its fields, quotes undone (RFC 4180): how a spreadsheet reads what
/// [`field`] writes. For the tests of every writer.
pub fn split_row(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        let current = fields.last_mut().expect("fields starts non-empty");
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                current.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(String::new()),
            _ => current.push(c),
        }
    }
    fields
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_field_is_written_as_is() {
        assert_eq!(field("columns"), "columns");
        assert_eq!(field("levels=4 directions=8"), "levels=4 directions=8");
    }

    #[test]
    fn commas_quotes_and_line_breaks_are_quoted_and_read_back() {
        let awkward = ["scenes/a,b.gltf", "say \"hi\"", "two\nlines", "", "x"];
        let line: Vec<String> = awkward.iter().map(|s| field(s)).collect();
        let line = line.join(",");
        assert_eq!(
            line,
            "\"scenes/a,b.gltf\",\"say \"\"hi\"\"\",\"two\nlines\",,x"
        );
        assert_eq!(split_row(&line), awkward);
    }
}
