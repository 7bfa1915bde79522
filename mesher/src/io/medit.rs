//! Medit `.mesh` (ASCII, `MeshVersionFormatted` 1, 2 or 3, `Dimension 3`) and `.sol`
//! (`SolAtVertices`, one scalar per vertex) reading and writing.
//!
//! The reader keeps `Vertices`, `Triangles` and `Tetrahedra` with their references and
//! skips every other section (`Edges`, `Corners`, `Normals`, ...) by jumping to the next
//! keyword. Indices are 1-based in the file and 0-based in memory. `#` starts a comment.

use super::error::IoError;
use super::text::{check_indices, utf8_text, NumLine, Tokens};
use super::{read_bytes, write_with};
use crate::surface::Surface;
use crate::volume::VolumeMesh;
use std::io::Write;
use std::path::Path;

/// Caps pre-allocation from counts read in a file.
const MAX_PREALLOC: usize = 1 << 22;

/// Parses a Medit mesh (vertices, triangles, tetrahedra and their references).
pub fn parse_mesh(name: &str, text: &str) -> Result<VolumeMesh, IoError> {
    let mut t = Tokens::new(name, text, Some('#'));
    let mut m = VolumeMesh::default();
    while let Some(key) = t.next_token() {
        let k = key.to_ascii_lowercase();
        match k.as_str() {
            "meshversionformatted" => {
                let v = t.i64("mesh version")?;
                if !(1..=3).contains(&v) {
                    return Err(t.error(format!("unsupported MeshVersionFormatted {v}")));
                }
            }
            "dimension" => {
                let d = t.i64("dimension")?;
                if d != 3 {
                    return Err(t.error(format!("only Dimension 3 is supported, found {d}")));
                }
            }
            "vertices" => read_vertices(&mut t, &mut m)?,
            "triangles" => {
                let nv = Some(m.vertices.len()).filter(|&n| n > 0);
                read_elements::<3>(
                    &mut t,
                    "triangle",
                    nv,
                    &mut m.triangles,
                    &mut m.triangle_refs,
                )?
            }
            "tetrahedra" => {
                let nv = Some(m.vertices.len()).filter(|&n| n > 0);
                read_elements::<4>(&mut t, "tetrahedron", nv, &mut m.tets, &mut m.tet_refs)?
            }
            "end" => break,
            _ if key.starts_with(|c: char| c.is_ascii_alphabetic()) => skip_section(&mut t),
            _ => return Err(t.error(format!("expected a section keyword, found '{key}'"))),
        }
    }
    let nv = m.vertices.len();
    check_indices(name, "triangle", &m.triangles, nv, 1)?;
    check_indices(name, "tetrahedron", &m.tets, nv, 1)?;
    Ok(m)
}

/// Parses the vertices and triangles of a Medit mesh as a surface.
pub fn parse_surface(name: &str, text: &str) -> Result<Surface, IoError> {
    let m = parse_mesh(name, text)?;
    Ok(Surface {
        vertices: m.vertices,
        triangles: m.triangles,
    })
}

/// Reads `n` then `n` lines `x y z ref`.
fn read_vertices(t: &mut Tokens, m: &mut VolumeMesh) -> Result<(), IoError> {
    let n = t.count("number of vertices")?;
    m.vertices.reserve(n.min(MAX_PREALLOC));
    for _ in 0..n {
        m.vertices.push(t.point()?);
        t.i64("vertex reference")?;
    }
    Ok(())
}

/// Reads `n` then `n` records of `K` 1-based indices and a reference.
fn read_elements<const K: usize>(
    t: &mut Tokens,
    what: &str,
    nv: Option<usize>,
    elems: &mut Vec<[u32; K]>,
    refs: &mut Vec<i32>,
) -> Result<(), IoError> {
    let n = t.count(&format!("number of {what}s"))?;
    elems.reserve(n.min(MAX_PREALLOC));
    refs.reserve(n.min(MAX_PREALLOC));
    let ref_what = format!("{what} reference");
    for _ in 0..n {
        elems.push(t.indices::<K>(what, 1, nv)?);
        refs.push(t.i32(&ref_what)?);
    }
    Ok(())
}

/// Skips the body of a section this reader does not use: up to the next keyword.
fn skip_section(t: &mut Tokens) {
    while let Some(next) = t.peek() {
        if next.starts_with(|c: char| c.is_ascii_alphabetic()) {
            return;
        }
        t.next_token();
    }
}

/// Parses a `.sol` file holding one scalar per vertex (`SolAtVertices` with one field of
/// type 1); `nv` is the expected number of vertices.
pub fn parse_sol(name: &str, text: &str, nv: usize) -> Result<Vec<f64>, IoError> {
    let mut t = Tokens::new(name, text, Some('#'));
    let mut out = None;
    while let Some(key) = t.next_token() {
        match key.to_ascii_lowercase().as_str() {
            "meshversionformatted" | "dimension" => {
                t.i64("a number")?;
            }
            "solatvertices" => {
                let n = t.count("number of vertices")?;
                if n != nv {
                    return Err(t.error(format!("{n} values but the mesh has {nv} vertices")));
                }
                let types = t.count("number of solution types")?;
                let kind = t.i64("solution type")?;
                if types != 1 || kind != 1 {
                    return Err(IoError::unsupported(
                        name,
                        "only one scalar per vertex is read",
                    ));
                }
                let mut v = Vec::with_capacity(n.min(MAX_PREALLOC));
                for _ in 0..n {
                    v.push(t.f64("size value")?);
                }
                out = Some(v);
            }
            "end" => break,
            _ if key.starts_with(|c: char| c.is_ascii_alphabetic()) => skip_section(&mut t),
            _ => return Err(t.error(format!("expected a section keyword, found '{key}'"))),
        }
    }
    out.ok_or_else(|| IoError::invalid(name, "no SolAtVertices section"))
}

/// Writes a mesh as Medit `.mesh`, version 2, 1-based, vertex references 0, missing
/// element references written as 0.
pub fn write_mesh<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n{}",
        m.vertices.len()
    )?;
    let mut nums = NumLine::default();
    for p in &m.vertices {
        nums.float(p.x).float(p.y).float(p.z).int(0).end(w)?;
    }
    if !m.triangles.is_empty() {
        writeln!(w, "\nTriangles\n{}", m.triangles.len())?;
        for (i, t) in m.triangles.iter().enumerate() {
            let r = m.triangle_refs.get(i).copied().unwrap_or(0);
            nums.ids(t, 1).int(r).end(w)?;
        }
    }
    writeln!(w, "\nTetrahedra\n{}", m.tets.len())?;
    for (i, t) in m.tets.iter().enumerate() {
        let r = m.tet_refs.get(i).copied().unwrap_or(0);
        nums.ids(t, 1).int(r).end(w)?;
    }
    writeln!(w, "\nEnd")
}

/// Writes a surface as Medit `.mesh` (vertices and triangles, references 0).
pub fn write_surface<W: Write>(w: &mut W, s: &Surface) -> std::io::Result<()> {
    writeln!(
        w,
        "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n{}",
        s.vertices.len()
    )?;
    for p in &s.vertices {
        writeln!(w, "{:?} {:?} {:?} 0", p.x, p.y, p.z)?;
    }
    writeln!(w, "\nTriangles\n{}", s.triangles.len())?;
    for t in &s.triangles {
        writeln!(w, "{} {} {} 0", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    writeln!(w, "\nEnd")
}

/// Writes one scalar per vertex as a Medit `.sol`.
pub fn write_sol<W: Write>(w: &mut W, values: &[f64]) -> std::io::Result<()> {
    writeln!(
        w,
        "MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n{}\n1 1\n",
        values.len()
    )?;
    for v in values {
        writeln!(w, "{v:?}")?;
    }
    writeln!(w, "\nEnd")
}

/// Writes `path` (`.mesh`) and, when the mesh has vertex sizes, the `.sol` beside it.
pub(crate) fn write_files(path: &Path, m: &VolumeMesh) -> Result<(), IoError> {
    // The sizes first: the file under the requested name appears last.
    if let Some(sizes) = &m.vertex_sizes {
        write_with(&path.with_extension("sol"), |w| write_sol(w, sizes))?;
    }
    write_with(path, |w| write_mesh(w, m))
}

/// Reads `path` (`.mesh`) and, when a `.sol` exists beside it, its vertex sizes.
pub(crate) fn read_files(path: &Path) -> Result<VolumeMesh, IoError> {
    let bytes = read_bytes(path)?;
    let mut m = parse_mesh(&path.display().to_string(), &utf8_text(&bytes))?;
    let sol = path.with_extension("sol");
    if sol.is_file() {
        let bytes = read_bytes(&sol)?;
        let text = utf8_text(&bytes);
        m.vertex_sizes = Some(parse_sol(
            &sol.display().to_string(),
            &text,
            m.vertices.len(),
        )?);
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;

    const TET: &str = "MeshVersionFormatted 1\nDimension\n3\n# comment\nVertices\n4\n\
        0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\nEdges\n1\n1 2 0\nCorners 1 1\n\
        Triangles\n1\n1 2 3 7\nTetrahedra\n1\n1 2 3 4 3\nEnd\n";

    #[test]
    fn reads_and_skips_sections() {
        let m = parse_mesh("t.mesh", TET).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.triangle_refs, vec![7]);
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(m.tet_refs, vec![3]);
        let s = parse_surface("t.mesh", TET).unwrap();
        assert_eq!(s.triangles.len(), 1);
    }

    #[test]
    fn write_then_parse() {
        let m = VolumeMesh {
            vertices: vec![
                Point::new(0.1, -0.0, 1e-300),
                Point::new(1.0 / 3.0, 0.0, 0.0),
                Point::new(0.0, 1e20, 0.0),
                Point::new(0.0, 0.0, 1.0),
            ],
            tets: vec![[0, 1, 2, 3]],
            tet_refs: vec![5],
            triangles: vec![[0, 1, 2]],
            triangle_refs: vec![2],
            vertex_sizes: None,
        };
        let mut buf = Vec::new();
        write_mesh(&mut buf, &m).unwrap();
        let back = parse_mesh("t.mesh", std::str::from_utf8(&buf).unwrap()).unwrap();
        assert_eq!(back, m);
        let mut buf = Vec::new();
        write_sol(&mut buf, &[0.5, 1.0 / 7.0]).unwrap();
        let s = parse_sol("t.sol", std::str::from_utf8(&buf).unwrap(), 2).unwrap();
        assert_eq!(s, vec![0.5, 1.0 / 7.0]);
    }

    #[test]
    fn errors() {
        let bad = TET.replace("1 2 3 4 3", "1 2 3 9 3");
        let e = parse_mesh("t.mesh", &bad).unwrap_err().to_string();
        assert!(
            e.starts_with("t.mesh:20: tetrahedron refers to vertex 9 but there are 4"),
            "{e}"
        );
        let late = "Triangles\n1\n1 2 5 0\nVertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\n";
        let e = parse_mesh("t.mesh", late).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.mesh: triangle 1 refers to vertex 5 but there are 3 vertices"
        );
        let e = parse_mesh("t.mesh", "Vertices\n2\n0 0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.mesh:4: unexpected end of file, expected x"),
            "{e}"
        );
        let e = parse_mesh("t.mesh", "Dimension 2\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.mesh:1: only Dimension 3"), "{e}");
        let e = parse_mesh("t.mesh", "12 Vertices\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.mesh:1: expected a section keyword"), "{e}");
        let e = parse_sol("t.sol", "SolAtVertices 2 1 2\n", 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unsupported"), "{e}");
    }
}
