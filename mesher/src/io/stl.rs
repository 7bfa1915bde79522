//! STL surface reader, ASCII and binary.
//!
//! A file is binary when its size is exactly `84 + 50 n` where `n` is the little-endian
//! triangle count at byte 80 (the `solid` prefix is not trusted: many binary files start
//! with it). Otherwise it is read as ASCII: `solid`, then `facet` / `outer loop` / three
//! `vertex x y z` / `endloop` / `endfacet` blocks, `endsolid`; several solids may follow
//! each other. Vertices are not shared: the caller welds them.

use super::error::IoError;
use super::text::Lines;
use crate::geom::Point;
use crate::surface::Surface;

/// Parses an STL file held in memory; `name` is used in error messages.
pub fn parse(name: &str, bytes: &[u8]) -> Result<Surface, IoError> {
    if let Some(n) = binary_count(bytes) {
        return parse_binary(name, bytes, n);
    }
    let text = super::text::utf8_text(bytes);
    let start = text.trim_start().get(..5).unwrap_or("");
    if !start.eq_ignore_ascii_case("solid") {
        let expected = match bytes.get(80..84) {
            Some(b) => format!(
                "84 + 50 * {} bytes",
                u32::from_le_bytes([b[0], b[1], b[2], b[3]])
            ),
            None => "at least 84 bytes".to_string(),
        };
        return Err(IoError::invalid(
            name,
            format!(
                "not a binary STL (size {} but the header announces {expected}) and not an \
                 ASCII STL (does not start with 'solid')",
                bytes.len()
            ),
        ));
    }
    parse_ascii(name, &text)
}

/// The triangle count when the size matches a binary STL.
fn binary_count(bytes: &[u8]) -> Option<usize> {
    let b = bytes.get(80..84)?;
    let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64;
    (84 + 50 * n == bytes.len() as u64).then_some(n as usize)
}

/// Reads `n` 50-byte records after the 84-byte header (size already checked).
fn parse_binary(name: &str, bytes: &[u8], n: usize) -> Result<Surface, IoError> {
    let mut s = Surface {
        vertices: Vec::with_capacity(3 * n),
        triangles: Vec::with_capacity(n),
    };
    for (t, rec) in bytes[84..].chunks_exact(50).enumerate() {
        for k in 0..3 {
            let at = 12 + 12 * k;
            let mut c = [0.0f64; 3];
            for (j, cj) in c.iter_mut().enumerate() {
                let o = at + 4 * j;
                let v = f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]);
                if !v.is_finite() {
                    return Err(IoError::Binary {
                        file: name.to_string(),
                        offset: (84 + 50 * t + o) as u64,
                        msg: format!("triangle {t}: coordinate {v} is not finite"),
                    });
                }
                *cj = v as f64;
            }
            s.vertices.push(Point::from_array(c));
        }
        let b = (3 * t) as u32;
        s.triangles.push([b, b + 1, b + 2]);
    }
    Ok(s)
}

/// Reads ASCII STL.
fn parse_ascii(name: &str, text: &str) -> Result<Surface, IoError> {
    let mut s = Surface::default();
    let mut lines = Lines::new(name, text, None);
    let mut in_loop: Option<usize> = None; // vertices seen in the current loop
    while let Some(mut l) = lines.next_line() {
        let key = l.next_token().unwrap_or("").to_ascii_lowercase();
        match (key.as_str(), in_loop) {
            ("vertex", Some(k)) => {
                s.vertices.push(l.point()?);
                in_loop = Some(k + 1);
            }
            ("vertex", None) => return Err(l.error("'vertex' outside 'outer loop'")),
            ("outer", None) => in_loop = Some(0),
            ("endloop", Some(3)) => {
                let b = (s.vertices.len() - 3) as u32;
                s.triangles.push([b, b + 1, b + 2]);
                in_loop = None;
            }
            ("endloop", Some(k)) => {
                return Err(l.error(format!("facet has {k} vertices, expected 3")))
            }
            ("solid" | "facet" | "endfacet" | "endsolid", None) => {}
            (other, Some(_)) => {
                return Err(l.error(format!("expected 'vertex' or 'endloop', found '{other}'")))
            }
            (other, None) => return Err(l.error(format!("unexpected '{other}' in ASCII STL"))),
        }
    }
    if in_loop.is_some() {
        return Err(lines.error("unexpected end of file inside a facet"));
    }
    Ok(s)
}

/// Writes a surface as ASCII STL with full-precision coordinates (binary STL would round
/// them to `f32`); normals are computed, zero for degenerate triangles.
pub fn write_ascii<W: std::io::Write>(w: &mut W, s: &Surface) -> std::io::Result<()> {
    writeln!(w, "solid mesher")?;
    for t in &s.triangles {
        let p = t.map(|i| s.vertices.get(i as usize).copied().unwrap_or(Point::ZERO));
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        writeln!(w, "facet normal {:?} {:?} {:?}\nouter loop", n.x, n.y, n.z)?;
        for q in p {
            writeln!(w, "vertex {:?} {:?} {:?}", q.x, q.y, q.z)?;
        }
        writeln!(w, "endloop\nendfacet")?;
    }
    writeln!(w, "endsolid mesher")
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: &str = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n\
        vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";

    #[test]
    fn ascii() {
        let s = parse("t.stl", TRI.as_bytes()).unwrap();
        assert_eq!(s.vertices.len(), 3);
        assert_eq!(s.triangles, vec![[0, 1, 2]]);
        let upper = parse("t.stl", TRI.to_ascii_uppercase().as_bytes()).unwrap();
        assert_eq!(upper, s);
    }

    fn binary(tris: &[[[f32; 3]; 3]], header: &[u8]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b[..header.len()].copy_from_slice(header);
        b.extend_from_slice(&(tris.len() as u32).to_le_bytes());
        for t in tris {
            b.extend_from_slice(&[0u8; 12]);
            for v in t {
                for c in v {
                    b.extend_from_slice(&c.to_le_bytes());
                }
            }
            b.extend_from_slice(&[0u8; 2]);
        }
        b
    }

    #[test]
    fn binary_starting_with_solid() {
        let t = [[[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 1.0, 0.25]]; 2];
        let b = binary(&t, b"solid but binary");
        let s = parse("b.stl", &b).unwrap();
        assert_eq!(s.triangles.len(), 2);
        assert_eq!(s.vertices[2], Point::new(0.0, 1.0, 0.25));
    }

    #[test]
    fn errors() {
        let t = [[[0.0, f32::NAN, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
        let e = parse("b.stl", &binary(&t, b"x")).unwrap_err().to_string();
        assert_eq!(
            e,
            "b.stl: byte 100: triangle 0: coordinate NaN is not finite"
        );
        let mut b = binary(&t, b"x");
        b.pop();
        let e = parse("b.stl", &b).unwrap_err().to_string();
        assert!(e.contains("not a binary STL (size 133"), "{e}");
        let bad = TRI.replace("   vertex 0 1 0\n", "");
        let e = parse("t.stl", bad.as_bytes()).unwrap_err().to_string();
        assert_eq!(e, "t.stl:6: facet has 2 vertices, expected 3");
        let bad = TRI.replace("vertex 1 0 0", "vertex 1 0");
        let e = parse("t.stl", bad.as_bytes()).unwrap_err().to_string();
        assert!(
            e.starts_with("t.stl:5: unexpected end of line, expected z"),
            "{e}"
        );
        let e = parse("t.stl", b"solid\nouter loop\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.stl:2: unexpected end of file"), "{e}");
    }
}
