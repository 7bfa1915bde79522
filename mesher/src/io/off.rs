//! Object File Format (`.off`) surface reader.
//!
//! Accepted: an `OFF` header (or the variants `COFF`, `NOFF`, `CNOFF`, `STOFF`, ... whose
//! extra per-vertex values are ignored; a missing header is tolerated), the counts line
//! `nv nf ne` (on the header line or the next), one vertex per line, one face per line as
//! `n i1 .. in [colour]` with 0-based indices. Polygons are fan-triangulated. `#` starts
//! a comment; blank lines are ignored. `4OFF`/`nOFF` (other dimensions) and binary OFF
//! are refused.

use super::error::IoError;
use super::text::{Lines, Tokens};
use crate::surface::Surface;

/// Parses OFF text; `name` is used in error messages.
pub fn parse(name: &str, text: &str) -> Result<Surface, IoError> {
    let mut lines = Lines::new(name, text, Some('#'));
    let mut counts = read_header(&mut lines)?;
    let nv = counts.count("number of vertices")?;
    let nf = counts.count("number of faces")?;
    let mut surface = Surface {
        vertices: Vec::with_capacity(nv.min(1 << 24)),
        triangles: Vec::with_capacity(nf.min(1 << 24)),
    };
    for _ in 0..nv {
        let mut l = lines.expect_line("a vertex line")?;
        surface.vertices.push(l.point()?);
    }
    for _ in 0..nf {
        let mut l = lines.expect_line("a face line")?;
        read_face(&mut l, nv, &mut surface.triangles)?;
    }
    Ok(surface)
}

/// Reads the header line(s) and returns the tokens positioned at the counts.
fn read_header<'a>(lines: &mut Lines<'a>) -> Result<Tokens<'a>, IoError> {
    let mut first = lines.expect_line("the OFF header")?;
    let head = first.peek().unwrap_or("");
    if head.parse::<usize>().is_ok() {
        return Ok(first); // no header keyword: the counts come first
    }
    let _ = first.next_token();
    if !head.ends_with("OFF") {
        return Err(first.error(format!("expected an OFF header, found '{head}'")));
    }
    let prefix = &head[..head.len() - 3];
    if prefix.contains('4') || prefix.contains('n') {
        return Err(IoError::unsupported(
            first.file(),
            format!("OFF variant '{head}' (only 3D OFF is read)"),
        ));
    }
    if first.peek() == Some("BINARY") {
        return Err(IoError::unsupported(first.file(), "binary OFF"));
    }
    if first.peek().is_some() {
        return Ok(first);
    }
    lines.expect_line("the counts line 'vertices faces edges'")
}

/// Reads `n i1 .. in` and appends its fan triangulation.
fn read_face(l: &mut Tokens, nv: usize, out: &mut Vec<[u32; 3]>) -> Result<(), IoError> {
    let k = l.count("number of face vertices")?;
    if k < 3 {
        return Err(l.error(format!("a face needs at least 3 vertices, found {k}")));
    }
    // The fan from the first vertex, built as the indices come.
    let (mut first, mut prev) = (0, 0);
    for found in 0..k {
        let Some(t) = l.next_token() else {
            return Err(l.error(format!("expected {k} vertex indices, found {found}")));
        };
        let i = l.index_of(t, "face", 0, Some(nv))?;
        match found {
            0 => first = i,
            1 => {}
            _ => out.push([first, prev, i]),
        }
        prev = i;
    }
    Ok(())
}

/// Writes a surface as OFF (shortest round-trip coordinates).
pub fn write<W: std::io::Write>(w: &mut W, s: &Surface) -> std::io::Result<()> {
    writeln!(w, "OFF\n{} {} 0", s.vertices.len(), s.triangles.len())?;
    for p in &s.vertices {
        writeln!(w, "{:?} {:?} {:?}", p.x, p.y, p.z)?;
    }
    for t in &s.triangles {
        writeln!(w, "3 {} {} {}", t[0], t[1], t[2])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE_QUADS: &str = "OFF\n# a cube\n8 6 12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
        0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n\
        4 2 3 7 6\n4 3 0 4 7 255 0 0\n";

    #[test]
    fn reads_quads_with_comments_and_colours() {
        let s = parse("cube.off", CUBE_QUADS).unwrap();
        assert_eq!(s.vertices.len(), 8);
        assert_eq!(s.triangles.len(), 12);
        assert_eq!(s.triangles[0], [0, 3, 2]);
        assert_eq!(s.triangles[1], [0, 2, 1]);
    }

    #[test]
    fn header_variants() {
        let s = parse("t.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(s.triangles.len(), 1);
        let s = parse(
            "t.off",
            "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n",
        )
        .unwrap();
        assert_eq!(s.vertices.len(), 3);
        let s = parse("t.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(s.triangles.len(), 1);
        let e = parse("t.off", "4OFF\n1 0 0\n0 0 0 0\n").unwrap_err();
        assert!(e.to_string().contains("unsupported"), "{e}");
    }

    #[test]
    fn errors_name_file_and_line() {
        let text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n\n3 0 1\n";
        let e = parse("cube.off", text).unwrap_err().to_string();
        assert_eq!(e, "cube.off:7: expected 3 vertex indices, found 2");
        let text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99\n";
        let e = parse("cube.off", text).unwrap_err().to_string();
        assert!(
            e.starts_with("cube.off:6: face refers to vertex 99 but there are 3"),
            "{e}"
        );
        let e = parse("cube.off", "OFF\n3 1 0\n0 0 0\n1 x 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("cube.off:4: expected y coordinate"), "{e}");
        let e = parse("cube.off", "OFF\n3 1 0\n0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("cube.off:4: unexpected end of file"), "{e}");
        let e = parse("cube.off", "PLY\n").unwrap_err().to_string();
        assert!(e.starts_with("cube.off:1: expected an OFF header"), "{e}");
        let e = parse("cube.off", "").unwrap_err().to_string();
        assert!(e.starts_with("cube.off:1: unexpected end of file"), "{e}");
        let e = parse("c.off", "OFF\n1 0 0\nnan 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not finite"), "{e}");
    }
}
