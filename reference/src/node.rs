//! TetGen `.node` point files.
//!
//! Format: a header `N dim nattr nmarker`, then `N` lines
//! `index x y z [attributes...] [marker]`. Indices start at 0 or 1 (the first
//! line decides) and must be consecutive. `#` starts a comment that runs to
//! the end of the line; blank lines are ignored. Only `dim = 3` is accepted.

use std::io::Write;
use std::path::Path;

/// Why a `.node` file could not be read. Line numbers are 1-based.
#[derive(Debug, thiserror::Error)]
pub enum NodeError {
    #[error("cannot read {path}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("line {line}: {msg}")]
    Parse { line: usize, msg: String },
}

fn err(line: usize, msg: impl Into<String>) -> NodeError {
    NodeError::Parse {
        line,
        msg: msg.into(),
    }
}

/// Reads the points of a `.node` file.
pub fn read_node(path: &Path) -> Result<Vec<[f64; 3]>, NodeError> {
    let text = std::fs::read_to_string(path).map_err(|source| NodeError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_node(&text)
}

fn parse_count(tok: &str, line: usize, what: &str) -> Result<usize, NodeError> {
    tok.parse::<usize>().map_err(|_| {
        err(
            line,
            format!("{what}: expected a non-negative integer, found {tok:?}"),
        )
    })
}

/// Parses the text of a `.node` file.
pub fn parse_node(text: &str) -> Result<Vec<[f64; 3]>, NodeError> {
    // Non-empty lines with comments removed, with their 1-based line numbers.
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());

    let (hline, header) = lines
        .next()
        .ok_or_else(|| err(1, "empty file: no header"))?;
    let h: Vec<&str> = header.split_whitespace().collect();
    if h.is_empty() || h.len() > 4 {
        return Err(err(
            hline,
            format!("header: expected `N dim nattr nmarker`, found {header:?}"),
        ));
    }
    let n = parse_count(h[0], hline, "header: point count")?;
    let dim = match h.get(1) {
        Some(t) => parse_count(t, hline, "header: dimension")?,
        None => 3,
    };
    if dim != 3 {
        return Err(err(
            hline,
            format!("header: dimension {dim}, only 3 is supported"),
        ));
    }
    let nattr = match h.get(2) {
        Some(t) => parse_count(t, hline, "header: attribute count")?,
        None => 0,
    };
    let nmarker = match h.get(3) {
        Some(t) => parse_count(t, hline, "header: boundary marker flag")?,
        None => 0,
    };
    if nmarker > 1 {
        return Err(err(
            hline,
            format!("header: boundary marker flag {nmarker}, expected 0 or 1"),
        ));
    }
    if n == 0 {
        return Err(err(
            hline,
            "header: point count 0 (points in a .poly file are not supported)",
        ));
    }
    let max_fields = 4 + nattr + nmarker;

    // Cap the reservation so that a bogus header cannot allocate gigabytes.
    let mut pts = Vec::with_capacity(n.min(text.len() / 8 + 1));
    let mut first_index = 0usize;
    for (lineno, l) in lines.by_ref() {
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() < 4 {
            return Err(err(
                lineno,
                format!("expected `index x y z`, found {} field(s): {l:?}", f.len()),
            ));
        }
        if f.len() > max_fields {
            return Err(err(
                lineno,
                format!("{} fields, the header allows at most {max_fields}", f.len()),
            ));
        }
        let idx = f[0].parse::<usize>().map_err(|_| {
            err(
                lineno,
                format!("index: expected an integer, found {:?}", f[0]),
            )
        })?;
        if pts.is_empty() {
            if idx > 1 {
                return Err(err(
                    lineno,
                    format!("first index is {idx}, expected 0 or 1"),
                ));
            }
            first_index = idx;
        }
        let want = first_index + pts.len();
        if idx != want {
            return Err(err(lineno, format!("index {idx}, expected {want}")));
        }
        let mut p = [0.0; 3];
        for (k, c) in p.iter_mut().enumerate() {
            let tok = f[1 + k];
            let v = tok.parse::<f64>().map_err(|_| {
                err(
                    lineno,
                    format!("coordinate {}: not a number: {tok:?}", k + 1),
                )
            })?;
            if !v.is_finite() {
                return Err(err(
                    lineno,
                    format!("coordinate {}: not finite: {tok:?}", k + 1),
                ));
            }
            *c = v;
        }
        pts.push(p);
        if pts.len() == n {
            break;
        }
    }
    if pts.len() < n {
        return Err(err(
            text.lines().count().max(1),
            format!("header announces {n} points, file has {}", pts.len()),
        ));
    }
    if let Some((lineno, l)) = lines.next() {
        return Err(err(
            lineno,
            format!("unexpected content after the {n} announced points: {l:?}"),
        ));
    }
    Ok(pts)
}

/// Writes points as a 1-based `.node` file. Coordinates use Rust's shortest
/// round-trip formatting, so reading the file back gives the same bits.
pub fn write_node<W: Write>(mut w: W, pts: &[[f64; 3]]) -> std::io::Result<()> {
    writeln!(w, "{} 3 0 0", pts.len())?;
    for (i, p) in pts.iter().enumerate() {
        writeln!(w, "{} {} {} {}", i + 1, p[0], p[1], p[2])?;
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_err(text: &str) -> (usize, String) {
        match parse_node(text) {
            Err(NodeError::Parse { line, msg }) => (line, msg),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn reads_one_based_with_comments_attributes_and_markers() {
        let text = "# a comment\n\n3 3 1 1  # header\n1 0 0 0 7.5 1\n2 1.5 -2 3e-3 0 0\n# mid\n3 0.25 0.5 0.75 1 0\n";
        let pts = parse_node(text).unwrap();
        assert_eq!(
            pts,
            vec![[0.0, 0.0, 0.0], [1.5, -2.0, 3e-3], [0.25, 0.5, 0.75]]
        );
    }

    #[test]
    fn reads_zero_based_and_short_header() {
        let pts = parse_node("2\n0 1 2 3\n1 4 5 6\n").unwrap();
        assert_eq!(pts, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
    }

    #[test]
    fn round_trips_bits() {
        let pts = crate::rng::unit_cube_points(500, 7);
        let mut buf = Vec::new();
        write_node(&mut buf, &pts).unwrap();
        let back = parse_node(std::str::from_utf8(&buf).unwrap()).unwrap();
        assert_eq!(pts, back);
    }

    #[test]
    fn malformed_coordinate_names_its_line() {
        let (line, msg) = parse_err("3 3 0 0\n1 0 0 0\n2 0 x 0\n3 1 1 1\n");
        assert_eq!(line, 3);
        assert!(msg.contains("coordinate 2"), "{msg}");
        let shown = parse_node("3 3 0 0\n1 0 0 0\n2 0 x 0\n")
            .unwrap_err()
            .to_string();
        assert!(shown.starts_with("line 3:"), "{shown}");
    }

    #[test]
    fn other_malformations_are_errors_not_panics() {
        assert_eq!(parse_err("").0, 1);
        assert_eq!(parse_err("# only a comment\n").0, 1);
        assert_eq!(parse_err("abc 3 0 0\n").0, 1);
        assert_eq!(parse_err("2 2 0 0\n1 0 0\n2 1 1\n").0, 1); // 2D
        assert_eq!(parse_err("0 3 0 0\n").0, 1);
        assert_eq!(parse_err("1 3 0 0 0 0\n1 0 0 0\n").0, 1); // header too long
        assert_eq!(parse_err("2 3 0 0\n1 0 0\n2 0 0 0\n").0, 2); // too few fields
        assert_eq!(parse_err("2 3 0 0\n1 0 0 0 9\n2 0 0 0\n").0, 2); // too many fields
        assert_eq!(parse_err("2 3 0 0\n5 0 0 0\n6 0 0 0\n").0, 2); // bad first index
        assert_eq!(parse_err("2 3 0 0\n1 0 0 0\n3 0 0 0\n").0, 3); // index gap
        assert_eq!(parse_err("2 3 0 0\n1 0 0 0\n2 nan 0 0\n").0, 3);
        assert_eq!(parse_err("2 3 0 0\n1 0 0 0\n2 0 inf 0\n").0, 3);
        assert_eq!(parse_err("2 3 0 0\n-1 0 0 0\n").0, 2);
        assert_eq!(parse_err("3 3 0 0\n1 0 0 0\n2 1 1 1\n").0, 3); // too few points
        assert_eq!(parse_err("1 3 0 0\n1 0 0 0\n2 1 1 1\n").0, 3); // trailing points
                                                                   // A huge announced count must not allocate or panic.
        assert_eq!(parse_err("18446744073709551615 3 0 0\n1 0 0 0\n").0, 2);
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let e = read_node(Path::new("/nonexistent/dir/p.node")).unwrap_err();
        assert!(matches!(e, NodeError::Io { .. }));
    }
}
