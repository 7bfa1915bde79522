//! Gmsh 2.2 *binary* `.msh` reader (the default output of fTetWild, written by PyMesh's
//! saver): little-endian `int` / `double` records between ASCII section lines.
//!
//! Kept: nodes, tets (type 4) and triangles (type 2) with their first tag (physical) as
//! reference. Other element types are skipped using their node count; other sections
//! (`$NodeData`, `$ElementData`, ...) are skipped up to their `$End` line. Errors name
//! the byte offset.

use super::error::IoError;
use crate::geom::Point;
use crate::volume::VolumeMesh;
use std::collections::HashMap;

/// Caps pre-allocation from counts read in a file.
const MAX_PREALLOC: usize = 1 << 22;

/// A cursor over the file's bytes.
struct Cursor<'a> {
    name: &'a str,
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn error(&self, at: usize, msg: impl Into<String>) -> IoError {
        IoError::Binary {
            file: self.name.to_string(),
            offset: at as u64,
            msg: msg.into(),
        }
    }

    /// The next `n` bytes.
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], IoError> {
        let s = self
            .pos
            .checked_add(n)
            .and_then(|end| self.bytes.get(self.pos..end))
            .ok_or_else(|| {
                self.error(self.pos, format!("unexpected end of file, expected {what}"))
            })?;
        self.pos += n;
        Ok(s)
    }

    fn i32(&mut self, what: &str) -> Result<i32, IoError> {
        let b = self.take(4, what)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// A non-negative `i32` as a count.
    fn count(&mut self, what: &str) -> Result<usize, IoError> {
        let at = self.pos;
        let v = self.i32(what)?;
        usize::try_from(v).map_err(|_| self.error(at, format!("negative {what} {v}")))
    }

    fn f64(&mut self, what: &str) -> Result<f64, IoError> {
        let at = self.pos;
        let b = self.take(8, what)?;
        let v = f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(at, format!("{what} {v} is not finite")))
        }
    }

    /// The next text line (without its `\n`), or `None` at the end of the file.
    fn line(&mut self) -> Option<&'a str> {
        let rest = self.bytes.get(self.pos..)?;
        if rest.is_empty() {
            return None;
        }
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += (end + 1).min(rest.len());
        Some(
            std::str::from_utf8(&rest[..end])
                .unwrap_or("\u{fffd}")
                .trim(),
        )
    }

    /// The next non-empty text line, which must be `want`.
    fn expect_line(&mut self, want: &str) -> Result<(), IoError> {
        let at = self.pos;
        loop {
            match self.line() {
                Some("") => continue,
                Some(l) if l == want => return Ok(()),
                Some(l) => return Err(self.error(at, format!("expected {want}, found '{l}'"))),
                None => {
                    return Err(self.error(at, format!("unexpected end of file, expected {want}")))
                }
            }
        }
    }

    /// A text line holding one count.
    fn count_line(&mut self, what: &str) -> Result<usize, IoError> {
        let at = self.pos;
        let l = self.line().unwrap_or("");
        l.parse()
            .map_err(|_| self.error(at, format!("expected {what}, found '{l}'")))
    }
}

/// Number of nodes of Gmsh element types 1 to 19.
fn nodes_per_element(ty: i32) -> Option<usize> {
    const N: [usize; 19] = [
        2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20, 15, 13,
    ];
    usize::try_from(ty - 1).ok().and_then(|i| N.get(i).copied())
}

/// Parses a binary Gmsh 2.2 file (the caller has seen `2.2 1 8` in `$MeshFormat`).
pub(crate) fn parse(name: &str, bytes: &[u8]) -> Result<VolumeMesh, IoError> {
    let mut c = Cursor {
        name,
        bytes,
        pos: 0,
    };
    c.expect_line("$MeshFormat")?;
    c.line();
    let at = c.pos;
    if c.i32("endianness marker")? != 1 {
        return Err(c.error(at, "big-endian binary .msh is not supported"));
    }
    c.expect_line("$EndMeshFormat")?;
    let mut m = VolumeMesh::default();
    let mut tags: HashMap<i32, u32> = HashMap::new();
    while let Some(l) = c.line() {
        match l {
            "" => {}
            "$Nodes" => {
                read_nodes(&mut c, &mut m, &mut tags)?;
                c.expect_line("$EndNodes")?;
            }
            "$Elements" => {
                read_elements(&mut c, &mut m, &tags)?;
                c.expect_line("$EndElements")?;
            }
            s if s.starts_with('$') => skip_section(&mut c, &s[1..])?,
            s => return Err(c.error(c.pos, format!("expected a '$' section, found '{s}'"))),
        }
    }
    Ok(m)
}

/// Skips a section up to its `$End` line.
fn skip_section(c: &mut Cursor, section: &str) -> Result<(), IoError> {
    let end = format!("\n$End{section}");
    let rest = c.bytes.get(c.pos..).unwrap_or(&[]);
    match rest.windows(end.len()).position(|w| w == end.as_bytes()) {
        Some(i) => {
            c.pos += i + 1;
            c.line();
            Ok(())
        }
        None => Err(c.error(
            c.pos,
            format!("unexpected end of file, expected $End{section}"),
        )),
    }
}

fn read_nodes(
    c: &mut Cursor,
    m: &mut VolumeMesh,
    tags: &mut HashMap<i32, u32>,
) -> Result<(), IoError> {
    let n = c.count_line("number of nodes")?;
    m.vertices.reserve(n.min(MAX_PREALLOC));
    for _ in 0..n {
        let at = c.pos;
        let tag = c.i32("node tag")?;
        let p = Point::new(c.f64("x")?, c.f64("y")?, c.f64("z")?);
        if tags.insert(tag, m.vertices.len() as u32).is_some() {
            return Err(c.error(at, format!("node {tag} defined twice")));
        }
        m.vertices.push(p);
    }
    Ok(())
}

fn read_elements(
    c: &mut Cursor,
    m: &mut VolumeMesh,
    tags: &HashMap<i32, u32>,
) -> Result<(), IoError> {
    let n = c.count_line("number of elements")?;
    let mut done = 0;
    while done < n {
        let at = c.pos;
        let ty = c.i32("element type")?;
        let count = c.count("element count")?;
        let ntags = c.count("number of tags")?;
        let k = nodes_per_element(ty)
            .ok_or_else(|| c.error(at, format!("unsupported element type {ty}")))?;
        for _ in 0..count {
            c.i32("element tag")?;
            let mut r = 0;
            for j in 0..ntags {
                let t = c.i32("element tag value")?;
                if j == 0 {
                    r = t;
                }
            }
            let mut ids = [0u32; 4];
            for j in 0..k {
                let at = c.pos;
                let tag = c.i32("node tag")?;
                let id = tags.get(&tag).copied().ok_or_else(|| {
                    c.error(
                        at,
                        format!(
                            "element refers to node {tag} but it is not among the {} nodes",
                            tags.len()
                        ),
                    )
                })?;
                if let Some(slot) = ids.get_mut(j) {
                    *slot = id;
                }
            }
            match ty {
                2 => {
                    m.triangles.push([ids[0], ids[1], ids[2]]);
                    m.triangle_refs.push(r);
                }
                4 => {
                    m.tets.push(ids);
                    m.tet_refs.push(r);
                }
                _ => {}
            }
        }
        done += count.max(1);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A binary file as fTetWild writes it: nodes, one tet block, an element data field.
    pub(crate) fn sample() -> Vec<u8> {
        let mut b = b"$MeshFormat\n2.2 1 8\n".to_vec();
        b.extend_from_slice(&1i32.to_le_bytes());
        b.extend_from_slice(b"\n$EndMeshFormat\n$Nodes\n4\n");
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0 / 3.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        for (i, p) in pts.iter().enumerate() {
            b.extend_from_slice(&(i as i32 + 1).to_le_bytes());
            for x in p {
                b.extend_from_slice(&f64::to_le_bytes(*x));
            }
        }
        b.extend_from_slice(b"\n$EndNodes\n$Elements\n1\n");
        for v in [4i32, 1, 2, 1, 6, 0, 1, 2, 3, 4] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(b"\n$EndElements\n$ElementData\n1\n\"q\"\n1\n0.0\n3\n0\n1\n1\n");
        b.extend_from_slice(&1i32.to_le_bytes());
        b.extend_from_slice(&0.5f64.to_le_bytes());
        b.extend_from_slice(b"\n$EndElementData\n");
        b
    }

    #[test]
    fn reads_ftetwild_like_binary() {
        let m = parse("b.msh", &sample()).unwrap();
        assert_eq!(m.vertices[2], Point::new(0.0, 1.0 / 3.0, 0.0));
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(m.tet_refs, vec![6]);
    }

    #[test]
    fn errors_have_offsets() {
        let b = sample();
        let e = parse("b.msh", &b[..60]).unwrap_err().to_string();
        assert!(
            e.starts_with("b.msh: byte 53: unexpected end of file, expected x"),
            "{e}"
        );
        let mut bad = b.clone();
        let el = b.windows(12).position(|w| w == b"$Elements\n1\n").unwrap();
        let at = el + 12 + 4 * 9; // last node tag of the tet
        bad[at..at + 4].copy_from_slice(&9i32.to_le_bytes());
        let e = parse("b.msh", &bad).unwrap_err().to_string();
        assert!(e.contains("refers to node 9"), "{e}");
    }
}
