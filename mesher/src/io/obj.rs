//! Wavefront OBJ surface reader, through the `tobj` crate (with `f64` positions).
//!
//! All objects and groups are merged into one surface; polygons are fan-triangulated by
//! `tobj`; lines, points, normals, texture coordinates and materials are ignored. Before
//! handing the text to `tobj`, a light pass over `v` and `f` lines locates the common
//! errors (bad coordinates, too few face vertices, indices out of range) so that they are
//! reported with their line number.

use super::error::IoError;
use super::text::{to_index, Lines, Tokens};
use crate::geom::Point;
use crate::surface::Surface;

/// Parses OBJ text; `name` is used in error messages.
pub fn parse(name: &str, text: &str) -> Result<Surface, IoError> {
    validate(name, text)?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let mut reader = std::io::BufReader::new(text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut reader, &opts, |_| {
        Err(tobj::LoadError::OpenFileFailed) // materials are not needed
    })
    .map_err(|e| IoError::invalid(name, format!("OBJ: {e}")))?;
    let mut s = Surface::default();
    for m in &models {
        let mesh = &m.mesh;
        let base = s.vertices.len();
        for p in mesh.positions.chunks_exact(3) {
            s.vertices.push(Point::new(p[0], p[1], p[2]));
        }
        let n = s.vertices.len();
        for t in mesh.indices.chunks_exact(3) {
            let mut tri = [0u32; 3];
            for (slot, &i) in tri.iter_mut().zip(t) {
                let v = base + i as usize;
                if v >= n {
                    return Err(IoError::invalid(
                        name,
                        format!("object '{}': index {i} out of range", m.name),
                    ));
                }
                *slot = v as u32;
            }
            s.triangles.push(tri);
        }
    }
    Ok(s)
}

/// Checks `v` and `f` lines, reporting errors with line numbers.
fn validate(name: &str, text: &str) -> Result<(), IoError> {
    let total = text
        .lines()
        .filter(|l| l.trim_start().starts_with("v ") || l.trim_start().starts_with("v\t"))
        .count();
    let mut lines = Lines::new(name, text, Some('#'));
    let mut seen = 0usize;
    while let Some(mut l) = lines.next_line() {
        match l.next_token() {
            Some("v") => {
                l.point()?;
                seen += 1;
            }
            Some("f") => check_face(&mut l, seen, total)?,
            _ => {}
        }
    }
    Ok(())
}

/// Checks one face line: at least 3 corners, each vertex index in range.
fn check_face(l: &mut Tokens, seen: usize, total: usize) -> Result<(), IoError> {
    let mut k = 0;
    while let Some(corner) = l.next_token() {
        let first = corner.split('/').next().unwrap_or("");
        let raw: i64 = first
            .parse()
            .map_err(|_| l.error(format!("expected a vertex index, found '{corner}'")))?;
        let checked = if raw < 0 {
            // relative to the vertices defined so far: -1 is the last one
            to_index(seen as i64 + raw, 0, Some(seen))
                .map_err(|_| format!("refers to vertex {raw} but only {seen} vertices precede it"))
        } else {
            to_index(raw, 1, Some(total))
        };
        checked.map_err(|m| l.error(format!("face {m}")))?;
        k += 1;
    }
    if k < 3 {
        return Err(l.error(format!("a face needs at least 3 vertices, found {k}")));
    }
    Ok(())
}

/// Writes a surface as OBJ (`v` and `f` lines, 1-based).
pub fn write<W: std::io::Write>(w: &mut W, s: &Surface) -> std::io::Result<()> {
    for p in &s.vertices {
        writeln!(w, "v {:?} {:?} {:?}", p.x, p.y, p.z)?;
    }
    for t in &s.triangles {
        writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_negative_indices_and_groups() {
        let text = "# cube part\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.1\n\
            vn 0 0 1\nf 1//1 2//1 3//1 4//1\no b\nv 0 0 1\nf -1 1 2\n";
        let s = parse("t.obj", text).unwrap();
        assert_eq!(s.triangles.len(), 3);
        let r = super::super::weld(s);
        assert_eq!(r.surface.vertices.len(), 5);
        assert_eq!(r.surface.vertices[3], Point::new(0.0, 1.0, 0.1));
    }

    #[test]
    fn errors_have_lines() {
        let e = parse("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.obj:4: face refers to vertex 9 but there are 3"),
            "{e}"
        );
        let e = parse("t.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "t.obj:3: a face needs at least 3 vertices, found 2");
        let e = parse("t.obj", "v 0 0\n").unwrap_err().to_string();
        assert!(
            e.starts_with("t.obj:1: unexpected end of line, expected z"),
            "{e}"
        );
        let e = parse("t.obj", "v 0 0 0\nf -2 1 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.obj:2: face refers to vertex -2"), "{e}");
        let e = parse("t.obj", "v 0 0 0\nf a 1 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.obj:2: expected a vertex index"), "{e}");
    }
}
