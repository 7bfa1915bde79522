//! Point sets: TetGen `.node` files (the input of `mesher delaunay`).
//!
//! Format: comments start with `#`; the first line is `<count> <dim=3> <#attributes>
//! <boundary marker 0|1>`, then one line per point `<index> <x> <y> <z> [attributes]
//! [marker]`, indices starting at 0 or 1.

use crate::geom::Point;
use std::path::Path;

/// A malformed point file: the file, the 1-based line and what is wrong.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{file}:{line}: {message}")]
pub struct PointsError {
    /// The file name as given.
    pub file: String,
    /// 1-based line number (0 for errors about the whole file).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads a TetGen `.node` file.
pub fn read_node_points(path: &Path) -> Result<Vec<Point>, PointsError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| PointsError {
        file: name.clone(),
        line: 0,
        message: e.to_string(),
    })?;
    parse_node_points(&text, &name)
}

/// Parses the text of a `.node` file; `name` is used in error messages.
pub fn parse_node_points(text: &str, name: &str) -> Result<Vec<Point>, PointsError> {
    let err = |line: usize, message: String| PointsError {
        file: name.to_string(),
        line,
        message,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let (hl, header) = lines
        .next()
        .ok_or_else(|| err(0, "empty file, expected a header line".into()))?;
    let h: Vec<&str> = header.split_whitespace().collect();
    let count: usize = h.first().and_then(|s| s.parse().ok()).ok_or_else(|| {
        err(
            hl,
            format!("expected the number of points, found {header:?}"),
        )
    })?;
    if let Some(dim) = h.get(1) {
        if *dim != "3" {
            return Err(err(hl, format!("dimension must be 3, found {dim}")));
        }
    }
    let mut points = Vec::with_capacity(count.min(1 << 26));
    for (ln, l) in lines.by_ref().take(count) {
        let mut f = l.split_whitespace().skip(1);
        let mut c = [0.0f64; 3];
        for (k, slot) in c.iter_mut().enumerate() {
            let tok = f.next().ok_or_else(|| {
                err(
                    ln,
                    format!("expected index and 3 coordinates, found {} values", k + 1),
                )
            })?;
            *slot = tok
                .parse()
                .map_err(|_| err(ln, format!("bad coordinate {tok:?}")))?;
        }
        points.push(Point::from_array(c));
    }
    if points.len() != count {
        return Err(err(
            0,
            format!("header announces {count} points, file has {}", points.len()),
        ));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_with_comments_and_attributes() {
        let t = "# pts\n3 3 1 0\n1 0 0 0 7\n2 1 0 0 7 # x\n\n3 0 1.5e0 0 7\n";
        let p = parse_node_points(t, "a.node").unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!(p[2], Point::new(0.0, 1.5, 0.0));
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_node_points("2 3 0 0\n1 0 0 0\n2 0 x 0\n", "b.node").unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.to_string().starts_with("b.node:3:"), "{e}");
        let e = parse_node_points("3 3 0 0\n1 0 0 0\n", "c.node").unwrap_err();
        assert!(e.message.contains("announces 3"));
        let e = parse_node_points("2 2 0 0\n", "d.node").unwrap_err();
        assert_eq!(e.line, 1);
        assert!(parse_node_points("", "e.node").is_err());
        assert!(parse_node_points("1 3\n1 0 0\n", "f.node").is_err());
    }
}
