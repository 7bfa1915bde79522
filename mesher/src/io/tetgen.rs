//! TetGen `.node` / `.ele` / `.face` reading and writing.
//!
//! Written files are 1-based: `.node` (`n 3 0 0`), `.ele` (`n 4 1` with the region as
//! attribute when the mesh has tet references, else `n 4 0`) and, when the mesh has
//! boundary triangles, `.face` (`n 1` with the triangle reference as boundary marker, else
//! `n 0`). The reader accepts 0- or 1-based numbering (taken from the first node's index,
//! element indices follow it), `#` comments, extra attributes and markers, 10-node
//! (quadratic) tets of which the 4 corners are kept, and reads `.face` when present. The
//! first `.ele` attribute becomes the tet reference.

use super::error::IoError;
use super::text::Lines;
use super::{read_bytes, write_with};
use crate::volume::VolumeMesh;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Caps pre-allocation from counts read in a file.
const MAX_PREALLOC: usize = 1 << 22;

/// A file's name (for messages) and text.
pub type NamedText<'a> = (&'a str, &'a str);

/// The base of a TetGen file set: the path without a `.node`, `.ele` or `.face` extension
/// (any other path is already a base).
pub fn base_path(path: &Path) -> PathBuf {
    match path.extension().and_then(|e| e.to_str()) {
        Some("node" | "ele" | "face") => path.with_extension(""),
        _ => path.to_path_buf(),
    }
}

/// `base` with `ext` appended (`cube.1` + `node` = `cube.1.node`).
fn sibling(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Parses a `.node` / `.ele` pair and an optional `.face`.
pub fn parse(
    node: NamedText,
    ele: NamedText,
    face: Option<NamedText>,
) -> Result<VolumeMesh, IoError> {
    let mut m = VolumeMesh::default();
    let base = parse_node(node.0, node.1, &mut m)?;
    parse_ele(ele.0, ele.1, base, &mut m)?;
    if let Some((name, text)) = face {
        parse_face(name, text, base, &mut m)?;
    }
    Ok(m)
}

/// Parses a `.node` file alone: the point set of `mesher delaunay`.
pub fn parse_points(name: &str, text: &str) -> Result<Vec<crate::geom::Point>, IoError> {
    let mut m = VolumeMesh::default();
    parse_node(name, text, &mut m)?;
    Ok(m.vertices)
}

/// Reads a `.node` file alone (see [`parse_points`]).
pub fn read_points(path: &Path) -> Result<Vec<crate::geom::Point>, IoError> {
    let bytes = read_bytes(path)?;
    parse_points(&path.display().to_string(), &super::text::utf8_text(&bytes))
}

/// Reads the nodes; returns the numbering base (index of the first node).
fn parse_node(name: &str, text: &str, m: &mut VolumeMesh) -> Result<i64, IoError> {
    let mut lines = Lines::new(name, text, Some('#'));
    let mut head = lines.expect_line("the header 'points 3 attributes markers'")?;
    let n = head.count("number of points")?;
    let dim = head.i64("dimension")?;
    if dim != 3 {
        return Err(head.error(format!("only dimension 3 is supported, found {dim}")));
    }
    m.vertices.reserve(n.min(MAX_PREALLOC));
    let mut base = 0;
    for i in 0..n {
        let mut l = lines.expect_line("a node line")?;
        let idx = l.i64("node index")?;
        if i == 0 {
            base = idx;
            if base != 0 && base != 1 {
                return Err(l.error(format!("first node index is {idx}, expected 0 or 1")));
            }
        } else if idx != base + i as i64 {
            return Err(l.error(format!(
                "node index {idx} out of sequence, expected {}",
                base + i as i64
            )));
        }
        m.vertices.push(l.point()?);
    }
    Ok(base)
}

/// Reads the tets and their first attribute.
fn parse_ele(name: &str, text: &str, base: i64, m: &mut VolumeMesh) -> Result<(), IoError> {
    let mut lines = Lines::new(name, text, Some('#'));
    let mut head = lines.expect_line("the header 'tetrahedra nodes attributes'")?;
    let n = head.count("number of tetrahedra")?;
    let per = head.count("nodes per tetrahedron")?;
    if per != 4 && per != 10 {
        return Err(head.error(format!(
            "nodes per tetrahedron must be 4 or 10, found {per}"
        )));
    }
    let nattr = match head.peek() {
        Some(_) => head.count("number of attributes")?,
        None => 0,
    };
    let nv = Some(m.vertices.len());
    m.tets.reserve(n.min(MAX_PREALLOC));
    for i in 0..n {
        let mut l = lines.expect_line("a tetrahedron line")?;
        let idx = l.i64("tetrahedron index")?;
        if idx != base + i as i64 {
            return Err(l.error(format!(
                "tetrahedron index {idx} out of sequence, expected {}",
                base + i as i64
            )));
        }
        m.tets.push(l.indices::<4>("tetrahedron", base, nv)?);
        for _ in 4..per {
            l.index("tetrahedron", base, nv)?;
        }
        if nattr > 0 {
            let a = l.f64("region attribute")?;
            m.tet_refs.push(
                attribute_to_ref(a)
                    .ok_or_else(|| l.error(format!("region attribute {a} is not an integer")))?,
            );
        }
    }
    Ok(())
}

/// An integral attribute value as an `i32`.
fn attribute_to_ref(a: f64) -> Option<i32> {
    (a.fract() == 0.0 && a.abs() <= i32::MAX as f64).then_some(a as i32)
}

/// Reads boundary triangles and their markers.
fn parse_face(name: &str, text: &str, base: i64, m: &mut VolumeMesh) -> Result<(), IoError> {
    let mut lines = Lines::new(name, text, Some('#'));
    let mut head = lines.expect_line("the header 'faces markers'")?;
    let n = head.count("number of faces")?;
    let markers = match head.peek() {
        Some(_) => head.count("number of boundary markers")?,
        None => 0,
    };
    let nv = Some(m.vertices.len());
    m.triangles.reserve(n.min(MAX_PREALLOC));
    for _ in 0..n {
        let mut l = lines.expect_line("a face line")?;
        l.i64("face index")?;
        m.triangles.push(l.indices::<3>("face", base, nv)?);
        if markers > 0 {
            m.triangle_refs.push(l.i32("boundary marker")?);
        }
    }
    Ok(())
}

/// Writes the `.node` file (1-based, no attributes, no markers).
pub fn write_node<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    writeln!(w, "{} 3 0 0", m.vertices.len())?;
    for (i, p) in m.vertices.iter().enumerate() {
        writeln!(w, "{} {:?} {:?} {:?}", i + 1, p.x, p.y, p.z)?;
    }
    writeln!(w, "# written by mesher")
}

/// Writes the `.ele` file (1-based, the region as attribute when there are references).
pub fn write_ele<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    let with_refs = !m.tet_refs.is_empty();
    writeln!(w, "{} 4 {}", m.tets.len(), u8::from(with_refs))?;
    for (i, t) in m.tets.iter().enumerate() {
        write!(
            w,
            "{} {} {} {} {}",
            i + 1,
            t[0] + 1,
            t[1] + 1,
            t[2] + 1,
            t[3] + 1
        )?;
        if with_refs {
            write!(w, " {}", m.tet_refs.get(i).copied().unwrap_or(0))?;
        }
        writeln!(w)?;
    }
    writeln!(w, "# written by mesher")
}

/// Writes the `.face` file (1-based, the reference as boundary marker when present).
pub fn write_face<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    let with_refs = !m.triangle_refs.is_empty();
    writeln!(w, "{} {}", m.triangles.len(), u8::from(with_refs))?;
    for (i, t) in m.triangles.iter().enumerate() {
        write!(w, "{} {} {} {}", i + 1, t[0] + 1, t[1] + 1, t[2] + 1)?;
        if with_refs {
            write!(w, " {}", m.triangle_refs.get(i).copied().unwrap_or(0))?;
        }
        writeln!(w)?;
    }
    writeln!(w, "# written by mesher")
}

/// Writes `base.node`, `base.ele` and, when there are triangles, `base.face`, where
/// `base` is [`base_path`] of `path`.
pub(crate) fn write_files(path: &Path, m: &VolumeMesh) -> Result<(), IoError> {
    let base = base_path(path);
    write_with(&sibling(&base, "node"), |w| write_node(w, m))?;
    write_with(&sibling(&base, "ele"), |w| write_ele(w, m))?;
    if !m.triangles.is_empty() {
        write_with(&sibling(&base, "face"), |w| write_face(w, m))?;
    }
    Ok(())
}

/// Reads `base.node`, `base.ele` and, if it exists, `base.face`.
pub(crate) fn read_files(path: &Path) -> Result<VolumeMesh, IoError> {
    let base = base_path(path);
    let load = |ext: &str| -> Result<(String, String), IoError> {
        let p = sibling(&base, ext);
        let bytes = read_bytes(&p)?;
        Ok((
            p.display().to_string(),
            super::text::utf8_text(&bytes).into_owned(),
        ))
    };
    let node = load("node")?;
    let ele = load("ele")?;
    let face = if sibling(&base, "face").is_file() {
        Some(load("face")?)
    } else {
        None
    };
    parse(
        (&node.0, &node.1),
        (&ele.0, &ele.1),
        face.as_ref().map(|(a, b)| (a.as_str(), b.as_str())),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;

    const NODE: &str = "# Node count, 3 dim, no attribute, no boundary marker\n4  3  0  0\n\
        0  0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n# Generated by tetgen -pq1.414Q cube.off\n";
    const ELE: &str = "1  4  1\n    0     0  1  2  3  2\n# Generated by tetgen\n";
    const FACE: &str = "1  1\n    0   0 2 1  -1\n";

    #[test]
    fn reads_zero_based_with_comments() {
        let m = parse(("t.node", NODE), ("t.ele", ELE), Some(("t.face", FACE))).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.vertices[3], Point::new(0.0, 0.0, 1.0));
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(m.tet_refs, vec![2]);
        assert_eq!(m.triangles, vec![[0, 2, 1]]);
        assert_eq!(m.triangle_refs, vec![-1]);
    }

    #[test]
    fn write_then_parse_is_identical() {
        let m = parse(("t.node", NODE), ("t.ele", ELE), Some(("t.face", FACE))).unwrap();
        let (mut n, mut e, mut f) = (Vec::new(), Vec::new(), Vec::new());
        write_node(&mut n, &m).unwrap();
        write_ele(&mut e, &m).unwrap();
        write_face(&mut f, &m).unwrap();
        let s = |b: &Vec<u8>| String::from_utf8(b.clone()).unwrap();
        let back = parse(("n", &s(&n)), ("e", &s(&e)), Some(("f", &s(&f)))).unwrap();
        assert_eq!(back, m);
    }

    #[test]
    fn errors() {
        let e = parse(("t.node", NODE), ("t.ele", "1 4 0\n0 0 1 2 4\n"), None)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.ele:2: tetrahedron refers to vertex 4 but there are 4"),
            "{e}"
        );
        let e = parse(
            ("t.node", "2 3 0 0\n1 0 0 0\n3 0 0 0\n"),
            ("t.ele", ELE),
            None,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, "t.node:3: node index 3 out of sequence, expected 2");
        let e = parse(("t.node", NODE), ("t.ele", "2 4 0\n0 0 1 2 3\n"), None)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.ele:3: unexpected end of file"), "{e}");
        let e = parse(("t.node", "1 2 0 0\n"), ("t.ele", ELE), None)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.node:1: only dimension 3"), "{e}");
    }

    #[test]
    fn base_paths() {
        assert_eq!(base_path(Path::new("a/cube.1.node")), Path::new("a/cube.1"));
        assert_eq!(base_path(Path::new("a/cube.1")), Path::new("a/cube.1"));
        assert_eq!(
            sibling(Path::new("a/cube.1"), "ele"),
            Path::new("a/cube.1.ele")
        );
    }

    #[test]
    fn points_alone_with_comments_and_line_errors() {
        let p = parse_points(
            "a.node",
            "# pts\n3 3 1 0\n1 0 0 0 7\n2 1 0 0 7 # x\n\n3 0 1.5e0 0 7\n",
        )
        .unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!(p[2], crate::geom::Point::new(0.0, 1.5, 0.0));
        let e = parse_points("b.node", "2 3 0 0\n1 0 0 0\n2 0 x 0\n").unwrap_err();
        assert!(e.to_string().contains("b.node:3"), "{e}");
        assert!(parse_points("c.node", "3 3 0 0\n1 0 0 0\n").is_err());
        assert!(parse_points("d.node", "2 2 0 0\n").is_err());
        assert!(parse_points("e.node", "").is_err());
    }
}
