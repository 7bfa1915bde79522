//! Gmsh `.msh` reading (ASCII 2.2 and 4.1) and writing (ASCII 4.1).
//!
//! Written files have a minimal `$Entities` section: one volume entity per distinct tet
//! reference (its physical tag is the reference; a single untagged volume when the mesh
//! has no references) and likewise one surface entity per distinct triangle reference.
//! All nodes sit in one block on the first volume. Elements are written in their order,
//! one block per run of equal references: triangles (type 2) then tets (type 4).
//!
//! The reader keeps tets (type 4) and triangles (type 2) and skips other element types
//! and unknown sections. A reference is the element's physical tag (2.2: first tag; 4.1:
//! first physical tag of its entity), else its elementary (entity) tag. Node tags may be
//! sparse. Binary 2.2 files are read by `gmsh_binary` (through [`parse_bytes`]); binary
//! 4.1 and format 4.0 are refused.

use super::error::IoError;
use super::text::{Lines, Tokens};
use crate::geom::{Aabb, Point};
use crate::volume::VolumeMesh;
use std::collections::{BTreeMap, HashMap};
use std::io::Write;

/// Caps pre-allocation from counts read in a file.
const MAX_PREALLOC: usize = 1 << 22;

/// Parses a Gmsh file held in memory: binary 2.2 (as fTetWild writes by default), or
/// ASCII 2.2 / 4.1.
pub fn parse_bytes(name: &str, bytes: &[u8]) -> Result<VolumeMesh, IoError> {
    let head = String::from_utf8_lossy(bytes.get(..64).unwrap_or(bytes));
    let mut lines = head.lines().map(str::trim).filter(|l| !l.is_empty());
    if lines.next() == Some("$MeshFormat") {
        let f: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
        if f.len() >= 2 && f[0].starts_with("2.") && f[1] == "1" {
            return super::gmsh_binary::parse(name, bytes);
        }
    }
    parse(name, &super::text::utf8_text(bytes))
}

/// Parses an ASCII Gmsh mesh.
pub fn parse(name: &str, text: &str) -> Result<VolumeMesh, IoError> {
    let mut r = Reader {
        lines: Lines::new(name, text, None),
        v4: None,
        nodes: NodeMap::default(),
        entity_phys: HashMap::new(),
        mesh: VolumeMesh::default(),
    };
    while let Some(mut l) = r.lines.next_line() {
        let key = l.next_token().unwrap_or("");
        match key {
            "$MeshFormat" => r.format()?,
            "$Entities" if r.v4 == Some(true) => r.entities()?,
            "$Nodes" | "$Elements" | "$NOD" | "$ELM" => {
                let v4 = r.v4.ok_or_else(|| l.error("section before $MeshFormat"))?;
                match (key, v4) {
                    ("$Nodes", true) => r.nodes_v4()?,
                    ("$Nodes", false) => r.nodes_v2()?,
                    ("$Elements", true) => r.elements_v4()?,
                    ("$Elements", false) => r.elements_v2()?,
                    _ => return Err(IoError::unsupported(name, "Gmsh 1 format")),
                }
                r.end_section(&key[1..])?;
            }
            _ if key.starts_with('$') && !key.starts_with("$End") => r.skip(&key[1..])?,
            _ => return Err(l.error(format!("expected a '$' section, found '{key}'"))),
        }
    }
    if r.v4.is_none() {
        return Err(IoError::invalid(name, "no $MeshFormat section"));
    }
    Ok(r.mesh)
}

/// Node tags to vertex indices: a dense table for the usual small tags, a hash map for
/// the others.
#[derive(Default)]
struct NodeMap {
    dense: Vec<u32>,
    sparse: HashMap<u64, u32>,
    len: usize,
}

impl NodeMap {
    /// Tags below this go to the dense table.
    const DENSE_LIMIT: u64 = 1 << 26;

    /// Maps `tag` to `index`; false when `tag` was already mapped.
    fn insert(&mut self, tag: u64, index: u32) -> bool {
        if self.get(tag).is_some() {
            return false;
        }
        if tag < Self::DENSE_LIMIT && tag as usize <= 4 * self.len + 1024 {
            let t = tag as usize;
            if t >= self.dense.len() {
                self.dense.resize(t + 1, u32::MAX);
            }
            self.dense[t] = index;
        } else {
            self.sparse.insert(tag, index);
        }
        self.len += 1;
        true
    }

    /// The index of `tag`.
    fn get(&self, tag: u64) -> Option<u32> {
        match usize::try_from(tag).ok().and_then(|t| self.dense.get(t)) {
            Some(&i) if i != u32::MAX => Some(i),
            _ => self.sparse.get(&tag).copied(),
        }
    }

    /// Number of nodes.
    fn len(&self) -> usize {
        self.len
    }
}

/// Parsing state.
struct Reader<'a> {
    lines: Lines<'a>,
    /// `Some(true)` for 4.1, `Some(false)` for 2.x, once `$MeshFormat` is read.
    v4: Option<bool>,
    /// Node tag to 0-based vertex index.
    nodes: NodeMap,
    /// (dimension, entity tag) to first physical tag.
    entity_phys: HashMap<(i64, i64), i32>,
    mesh: VolumeMesh,
}

impl<'a> Reader<'a> {
    /// `$MeshFormat`: version, file type, data size.
    fn format(&mut self) -> Result<(), IoError> {
        let mut l = self.lines.expect_line("'version file-type data-size'")?;
        let version = l.expect("format version")?;
        let file_type = l.i64("file type")?;
        if file_type != 0 {
            let msg = "binary .msh other than 2.2 (ASCII 2.2/4.1 and binary 2.2 are read)";
            return Err(IoError::unsupported(l.file(), msg));
        }
        self.v4 = match version {
            "4.1" => Some(true),
            v if v.starts_with("2.") => Some(false),
            v => {
                let msg = format!("Gmsh format {v} (2.x and 4.1 are read)");
                return Err(IoError::unsupported(l.file(), msg));
            }
        };
        self.end_section("MeshFormat")
    }

    /// Expects `$End<name>` as the next line.
    fn end_section(&mut self, name: &str) -> Result<(), IoError> {
        let want = format!("$End{name}");
        let mut l = self.lines.expect_line(&want)?;
        match l.next_token() {
            Some(t) if t == want => Ok(()),
            t => Err(l.error(format!("expected {want}, found '{}'", t.unwrap_or("")))),
        }
    }

    /// Skips an unknown section up to `$End<name>`.
    fn skip(&mut self, name: &str) -> Result<(), IoError> {
        let want = format!("$End{name}");
        while let Some(mut l) = self.lines.next_line() {
            if l.next_token() == Some(want.as_str()) {
                return Ok(());
            }
        }
        Err(self
            .lines
            .error(format!("unexpected end of file, expected {want}")))
    }

    /// Next line, or an error naming what was expected.
    fn line(&mut self, what: &str) -> Result<Tokens<'a>, IoError> {
        self.lines.expect_line(what)
    }

    /// `$Entities` (4.1): records the first physical tag of each entity.
    fn entities(&mut self) -> Result<(), IoError> {
        let mut l = self.line("entity counts")?;
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            *c = l.count(&format!("number of {d}-dimensional entities"))?;
        }
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let mut l = self.line("an entity line")?;
                let tag = l.i64("entity tag")?;
                let coords = if dim == 0 { 3 } else { 6 };
                for _ in 0..coords {
                    l.f64("bounding box coordinate")?;
                }
                if l.count("number of physical tags")? > 0 {
                    let phys = l.i32("physical tag")?;
                    self.entity_phys.insert((dim as i64, tag), phys);
                }
            }
        }
        self.end_section("Entities")
    }

    /// Registers node `tag` at `p`.
    fn add_node(&mut self, l: &Tokens, tag: i64, p: Point) -> Result<(), IoError> {
        let index = self.mesh.vertices.len() as u32;
        let key = u64::try_from(tag).map_err(|_| l.error(format!("invalid node tag {tag}")))?;
        if !self.nodes.insert(key, index) {
            return Err(l.error(format!("node {tag} defined twice")));
        }
        self.mesh.vertices.push(p);
        Ok(())
    }

    /// `$Nodes` in 2.x: `n`, then `tag x y z` lines.
    fn nodes_v2(&mut self) -> Result<(), IoError> {
        let n = self.line("number of nodes")?.count("number of nodes")?;
        self.mesh.vertices.reserve(n.min(MAX_PREALLOC));
        for _ in 0..n {
            let mut l = self.line("a node line")?;
            let tag = l.i64("node tag")?;
            let p = l.point()?;
            self.add_node(&l, tag, p)?;
        }
        Ok(())
    }

    /// `$Nodes` in 4.1: entity blocks of tags then coordinates.
    fn nodes_v4(&mut self) -> Result<(), IoError> {
        let mut h = self.line("'blocks nodes min-tag max-tag'")?;
        let blocks = h.count("number of entity blocks")?;
        let n = h.count("number of nodes")?;
        self.mesh.vertices.reserve(n.min(MAX_PREALLOC));
        for _ in 0..blocks {
            let mut b = self.line("'dim entity parametric count'")?;
            let dim = b.i64("entity dimension")?;
            b.i64("entity tag")?;
            let parametric = b.i64("parametric flag")? != 0;
            let count = b.count("number of nodes in block")?;
            let mut tags = Vec::with_capacity(count.min(MAX_PREALLOC));
            for _ in 0..count {
                tags.push(self.line("a node tag")?.i64("node tag")?);
            }
            for tag in tags {
                let mut l = self.line("a node coordinate line")?;
                let p = l.point()?;
                if parametric {
                    for _ in 0..dim.clamp(0, 3) {
                        l.f64("parametric coordinate")?;
                    }
                }
                self.add_node(&l, tag, p)?;
            }
        }
        Ok(())
    }

    /// Reads `K` node tags from `l` as 0-based vertex indices.
    fn node_refs<const K: usize>(&self, l: &mut Tokens) -> Result<[u32; K], IoError> {
        let mut out = [0u32; K];
        for slot in out.iter_mut() {
            let tag = l.i64("node tag")?;
            *slot = u64::try_from(tag)
                .ok()
                .and_then(|t| self.nodes.get(t))
                .ok_or_else(|| {
                    l.error(format!(
                        "element refers to node {tag} but it is not among the {} nodes",
                        self.nodes.len()
                    ))
                })?;
        }
        Ok(out)
    }

    /// Adds a triangle or tet read from `l` (positioned at its nodes) with reference `r`.
    fn add_element(&mut self, ty: i64, l: &mut Tokens, r: i32) -> Result<(), IoError> {
        match ty {
            2 => {
                let t = self.node_refs::<3>(l)?;
                self.mesh.triangles.push(t);
                self.mesh.triangle_refs.push(r);
            }
            4 => {
                let t = self.node_refs::<4>(l)?;
                self.mesh.tets.push(t);
                self.mesh.tet_refs.push(r);
            }
            _ => {}
        }
        Ok(())
    }

    /// `$Elements` in 2.x: `tag type ntags tags.. nodes..` lines.
    fn elements_v2(&mut self) -> Result<(), IoError> {
        let n = self
            .line("number of elements")?
            .count("number of elements")?;
        for _ in 0..n {
            let mut l = self.line("an element line")?;
            l.i64("element tag")?;
            let ty = l.i64("element type")?;
            let ntags = l.count("number of tags")?;
            let mut r = 0;
            for k in 0..ntags {
                let t = l.i32("element tag value")?;
                if k == 0 {
                    r = t;
                }
            }
            self.add_element(ty, &mut l, r)?;
        }
        Ok(())
    }

    /// `$Elements` in 4.1: entity blocks of `tag nodes..` lines.
    fn elements_v4(&mut self) -> Result<(), IoError> {
        let blocks = self
            .line("'blocks elements min-tag max-tag'")?
            .count("number of blocks")?;
        for _ in 0..blocks {
            let mut b = self.line("'dim entity type count'")?;
            let dim = b.i64("entity dimension")?;
            let entity = b.i64("entity tag")?;
            let ty = b.i64("element type")?;
            let count = b.count("number of elements in block")?;
            let r = match self.entity_phys.get(&(dim, entity)) {
                Some(&p) => p,
                None => i32::try_from(entity)
                    .map_err(|_| b.error(format!("entity tag {entity} out of range")))?,
            };
            for _ in 0..count {
                let mut l = self.line("an element line")?;
                l.i64("element tag")?;
                self.add_element(ty, &mut l, r)?;
            }
        }
        Ok(())
    }
}

/// Maps each distinct reference to an entity tag 1, 2, ... (sorted by reference).
fn entity_tags(refs: &[i32]) -> BTreeMap<i32, usize> {
    let mut m: BTreeMap<i32, usize> = refs.iter().map(|&r| (r, 0)).collect();
    for (i, v) in m.values_mut().enumerate() {
        *v = i + 1;
    }
    m
}

/// Runs of equal references: (start, end, reference); one run when `refs` is empty.
fn runs(n: usize, refs: &[i32]) -> Vec<(usize, usize, Option<i32>)> {
    if refs.len() != n {
        return if n == 0 { vec![] } else { vec![(0, n, None)] };
    }
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=n {
        if i == n || refs[i] != refs[start] {
            out.push((start, i, Some(refs[start])));
            start = i;
        }
    }
    out
}

/// Writes a mesh as Gmsh 4.1 ASCII.
pub fn write<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    let tet_runs = runs(m.tets.len(), &m.tet_refs);
    let tri_runs = runs(m.triangles.len(), &m.triangle_refs);
    let vol_tags = entity_tags(if tet_runs.iter().any(|r| r.2.is_some()) {
        &m.tet_refs
    } else {
        &[]
    });
    let sur_tags = entity_tags(if tri_runs.iter().any(|r| r.2.is_some()) {
        &m.triangle_refs
    } else {
        &[]
    });
    let b = Aabb::of_points(&m.vertices).unwrap_or(Aabb {
        min: Point::ZERO,
        max: Point::ZERO,
    });
    let bbox = format!(
        "{:?} {:?} {:?} {:?} {:?} {:?}",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    );
    let n_sur = if m.triangles.is_empty() {
        0
    } else {
        sur_tags.len().max(1)
    };
    writeln!(w, "$Entities\n0 0 {n_sur} {}", vol_tags.len().max(1))?;
    write_entities(w, &sur_tags, n_sur, &bbox)?;
    write_entities(w, &vol_tags, 1, &bbox)?;
    writeln!(w, "$EndEntities")?;
    let nv = m.vertices.len();
    writeln!(w, "$Nodes\n1 {nv} {} {nv}\n3 1 0 {nv}", nv.min(1))?;
    for i in 1..=nv {
        writeln!(w, "{i}")?;
    }
    for p in &m.vertices {
        writeln!(w, "{:?} {:?} {:?}", p.x, p.y, p.z)?;
    }
    writeln!(w, "$EndNodes")?;
    let ne = m.tets.len() + m.triangles.len();
    writeln!(
        w,
        "$Elements\n{} {ne} {} {ne}",
        tet_runs.len() + tri_runs.len(),
        ne.min(1)
    )?;
    let mut tag = 0;
    for &(s, e, r) in &tri_runs {
        let ent = r.and_then(|r| sur_tags.get(&r).copied()).unwrap_or(1);
        writeln!(w, "2 {ent} 2 {}", e - s)?;
        for t in &m.triangles[s..e] {
            tag += 1;
            writeln!(w, "{tag} {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
    }
    for &(s, e, r) in &tet_runs {
        let ent = r.and_then(|r| vol_tags.get(&r).copied()).unwrap_or(1);
        writeln!(w, "3 {ent} 4 {}", e - s)?;
        for t in &m.tets[s..e] {
            tag += 1;
            writeln!(
                w,
                "{tag} {} {} {} {}",
                t[0] + 1,
                t[1] + 1,
                t[2] + 1,
                t[3] + 1
            )?;
        }
    }
    writeln!(w, "$EndElements")
}

/// Writes entity lines: one per reference (physical tag = reference), or `n` untagged.
fn write_entities<W: Write>(
    w: &mut W,
    tags: &BTreeMap<i32, usize>,
    n: usize,
    bbox: &str,
) -> std::io::Result<()> {
    if tags.is_empty() {
        for t in 1..=n {
            writeln!(w, "{t} {bbox} 0 0")?;
        }
    } else {
        for (r, t) in tags {
            writeln!(w, "{t} {bbox} 1 {r} 0")?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// As written by Gmsh 4.x (`-3 -format msh41`), trimmed: a point and a surface
    /// entity, parametric nodes, a line element block that must be skipped.
    const V41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 7 \"vol\"\n\
        $EndPhysicalNames\n$Entities\n1 0 1 1\n1 0 0 0 0\n1 0 0 0 1 1 0 0 0\n\
        1 0 0 0 1 1 1 1 7 1 1\n$EndEntities\n$Nodes\n3 5 1 5\n0 1 0 1\n1\n0 0 0\n\
        2 1 1 2\n2\n3\n1 0 0 0.5 0\n0 1 0 0 0.5\n3 1 0 2\n4\n9\n0 0 1\n1 1 1\n$EndNodes\n\
        $Elements\n3 4 1 4\n0 1 15 1\n1 1\n2 1 2 1\n2 1 2 3\n3 1 4 2\n3 1 2 3 4\n\
        4 2 3 4 9\n$EndElements\n";

    #[test]
    fn reads_41() {
        let m = parse("t.msh", V41).unwrap();
        assert_eq!(m.vertices.len(), 5);
        assert_eq!(m.vertices[2], Point::new(0.0, 1.0, 0.0));
        assert_eq!(m.tets, vec![[0, 1, 2, 3], [1, 2, 3, 4]]);
        assert_eq!(m.tet_refs, vec![7, 7]);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.triangle_refs, vec![1]);
    }

    #[test]
    fn reads_22() {
        let t = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n\
            3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n3\n1 15 2 0 1 1\n2 2 2 3 1 1 2 3\n\
            3 4 2 5 1 1 2 3 4\n$EndElements\n";
        let m = parse("t.msh", t).unwrap();
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(m.tet_refs, vec![5]);
        assert_eq!(m.triangle_refs, vec![3]);
    }

    #[test]
    fn write_then_parse() {
        let mut m = parse("t.msh", V41).unwrap();
        m.tet_refs = vec![3, -1];
        for refs in [vec![3, -1], vec![]] {
            m.tet_refs = refs;
            let mut buf = Vec::new();
            write(&mut buf, &m).unwrap();
            let back = parse("t.msh", std::str::from_utf8(&buf).unwrap()).unwrap();
            assert_eq!(back.vertices, m.vertices);
            assert_eq!(back.tets, m.tets);
            assert_eq!(back.triangles, m.triangles);
            assert_eq!(back.triangle_refs, m.triangle_refs);
            if m.tet_refs.is_empty() {
                assert_eq!(back.tet_refs, vec![1, 1]);
            } else {
                assert_eq!(back.tet_refs, m.tet_refs);
            }
        }
    }

    #[test]
    fn errors() {
        let bad = V41.replace("4 2 3 4 9", "4 2 3 4 99");
        let e = parse("t.msh", &bad).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.msh:38: element refers to node 99 but it is not among the 5 nodes"
        );
        let bad = V41.replace("4.1 0 8", "4.1 1 8");
        let e = parse("t.msh", &bad).unwrap_err().to_string();
        assert!(e.contains("unsupported: binary"), "{e}");
        let bad = V41.replace("$EndNodes\n", "");
        let e = parse("t.msh", &bad).unwrap_err().to_string();
        assert_eq!(e, "t.msh:29: expected $EndNodes, found '$Elements'");
        let e = parse("t.msh", "$Nodes\n").unwrap_err().to_string();
        assert_eq!(e, "t.msh:1: section before $MeshFormat");
    }
}
