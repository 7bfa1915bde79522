//! VTK unstructured grids: XML `.vtu` (ASCII data) written and read, legacy `.vtk`
//! (ASCII, versions 2 to 5.1) read.
//!
//! Written `.vtu` files hold the tets as cells of type 10 (boundary triangles are not
//! written) and, when the mesh has tet references, a cell data array `region`. Readers
//! keep cells of type 10 (tet) and 5 (triangle) and the first present cell data array
//! among [`REF_NAMES`] as references. Binary, appended and compressed data are refused
//! with an "unsupported" error.

use super::error::IoError;
use super::text::{NumLine, Tokens};
use crate::geom::Point;
use crate::volume::VolumeMesh;
use quick_xml::events::{BytesStart, Event};
use std::io::Write;

/// Cell data arrays taken as references, in order of preference.
pub const REF_NAMES: [&str; 6] = [
    "region",
    "medit:ref",
    "gmsh:physical",
    "CellEntityIds",
    "gmsh:geometrical",
    "tetgen:ref",
];

/// Caps pre-allocation from counts read in a file.
const MAX_PREALLOC: usize = 1 << 22;

/// Writes the tets of a mesh as an ASCII `.vtu`.
pub fn write_vtu<W: Write>(w: &mut W, m: &VolumeMesh) -> std::io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n<UnstructuredGrid>"
    )?;
    writeln!(
        w,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        m.vertices.len(),
        m.tets.len()
    )?;
    writeln!(w, "<Points>\n<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">")?;
    let mut line = NumLine::default();
    for p in &m.vertices {
        line.float(p.x).float(p.y).float(p.z).end(w)?;
    }
    writeln!(w, "</DataArray>\n</Points>\n<Cells>")?;
    writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    )?;
    for t in &m.tets {
        line.ids(t, 0).end(w)?;
    }
    writeln!(
        w,
        "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    )?;
    for i in 1..=m.tets.len() {
        line.int(4 * i).end(w)?;
    }
    writeln!(
        w,
        "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    )?;
    for _ in &m.tets {
        w.write_all(b"10\n")?;
    }
    writeln!(w, "</DataArray>\n</Cells>")?;
    if !m.tet_refs.is_empty() {
        writeln!(w, "<CellData Scalars=\"region\">")?;
        writeln!(
            w,
            "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">"
        )?;
        for i in 0..m.tets.len() {
            line.int(m.tet_refs.get(i).copied().unwrap_or(0)).end(w)?;
        }
        writeln!(w, "</DataArray>\n</CellData>")?;
    }
    writeln!(w, "</Piece>\n</UnstructuredGrid>\n</VTKFile>")
}

/// Cells of one piece (or of a legacy file) before conversion.
#[derive(Default)]
struct Cells {
    points: Vec<Point>,
    connectivity: Vec<i64>,
    /// End offset of each cell in `connectivity`.
    offsets: Vec<i64>,
    types: Vec<i64>,
    /// References with the priority of their name in [`REF_NAMES`].
    refs: Option<(usize, Vec<i32>)>,
}

impl Cells {
    /// Keeps `values` as references if `name` is preferred to the current ones.
    fn offer_refs(&mut self, name: &str, values: Vec<i32>) {
        if let Some(rank) = REF_NAMES.iter().position(|&n| n == name) {
            if !matches!(&self.refs, Some((r, _)) if *r <= rank) {
                self.refs = Some((rank, values));
            }
        }
    }

    /// Appends the tets and triangles to `m` (vertex indices shifted past its vertices).
    fn append_to(self, file: &str, m: &mut VolumeMesh) -> Result<(), IoError> {
        let n = self.types.len();
        if self.offsets.len() != n {
            let msg = format!("{} cell offsets but {n} cell types", self.offsets.len());
            return Err(IoError::invalid(file, msg));
        }
        let refs = self.refs.map(|r| r.1).unwrap_or_default();
        if !refs.is_empty() && refs.len() != n {
            let msg = format!("{} cell references but {n} cells", refs.len());
            return Err(IoError::invalid(file, msg));
        }
        let np = self.points.len();
        let shift = m.vertices.len();
        let mut start = 0i64;
        for (c, (&end, &ty)) in self.offsets.iter().zip(&self.types).enumerate() {
            let cell = usize::try_from(start)
                .ok()
                .zip(usize::try_from(end).ok())
                .and_then(|(s, e)| self.connectivity.get(s..e))
                .ok_or_else(|| IoError::invalid(file, format!("cell {c}: bad offset {end}")))?;
            start = end;
            let mut ids = Vec::with_capacity(cell.len());
            for &v in cell {
                match usize::try_from(v).ok().filter(|&v| v < np) {
                    Some(v) => ids.push((v + shift) as u32),
                    None => {
                        let msg = format!("cell {c} refers to point {v} but there are {np} points");
                        return Err(IoError::invalid(file, msg));
                    }
                }
            }
            let r = refs.get(c).copied();
            let bad = |k: usize| {
                let msg = format!(
                    "cell {c} of type {ty} has {} points, expected {k}",
                    ids.len()
                );
                IoError::invalid(file, msg)
            };
            match ty {
                10 | 24 => {
                    let t = ids.get(..4).ok_or_else(|| bad(4))?;
                    m.tets.push([t[0], t[1], t[2], t[3]]);
                    m.tet_refs.extend(r);
                }
                5 | 22 => {
                    let t = ids.get(..3).ok_or_else(|| bad(3))?;
                    m.triangles.push([t[0], t[1], t[2]]);
                    m.triangle_refs.extend(r);
                }
                _ => {}
            }
        }
        m.vertices.extend(self.points);
        Ok(())
    }
}

/// An integral value as an `i32` reference.
fn to_ref(t: &Tokens, v: f64) -> Result<i32, IoError> {
    if v.fract() == 0.0 && v.abs() <= i32::MAX as f64 {
        Ok(v as i32)
    } else {
        Err(t.error(format!("reference {v} is not an integer")))
    }
}

/// Reads `n` values with `read`.
fn read_n<T>(
    t: &mut Tokens,
    n: usize,
    mut read: impl FnMut(&mut Tokens) -> Result<T, IoError>,
) -> Result<Vec<T>, IoError> {
    let mut out = Vec::with_capacity(n.min(MAX_PREALLOC));
    for _ in 0..n {
        out.push(read(t)?);
    }
    Ok(out)
}

/// The attributes of a `<DataArray>` this reader uses.
struct ArrayInfo {
    name: String,
    components: usize,
    /// Byte offset of the array's content in the file.
    start: usize,
}

/// Section a `<DataArray>` belongs to.
#[derive(Clone, Copy, PartialEq)]
enum Section {
    Points,
    Cells,
    CellData,
    Other,
}

/// Reads the attribute `key` of an element.
fn attr(e: &BytesStart, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key)
        .map(|a| a.value.trim().to_string())
}

/// 1-based line of byte offset `pos` in `text`.
fn line_of(text: &str, pos: usize) -> usize {
    1 + text.as_bytes()[..pos.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// State of the `.vtu` reader.
struct Vtu<'a> {
    name: &'a str,
    text: &'a str,
    mesh: VolumeMesh,
    piece: Option<Cells>,
    section: Section,
    array: Option<ArrayInfo>,
    seen_grid: bool,
}

/// Parses an ASCII `.vtu` file (one or more pieces).
pub fn parse_vtu(name: &str, text: &str) -> Result<VolumeMesh, IoError> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut v = Vtu {
        name,
        text,
        mesh: VolumeMesh::default(),
        piece: None,
        section: Section::Other,
        array: None,
        seen_grid: false,
    };
    loop {
        let before = reader.buffer_position() as usize;
        let ev = reader.read_event().map_err(|e| {
            let pos = reader.error_position() as usize;
            IoError::parse(name, line_of(text, pos), format!("XML error: {e}"))
        })?;
        let after = reader.buffer_position() as usize;
        match ev {
            Event::Start(e) => v.start(&e, before, after, false)?,
            Event::Empty(e) => v.start(&e, before, after, true)?,
            Event::End(e) => v.end(e.name().as_ref(), before)?,
            Event::Eof => break,
            _ => {}
        }
    }
    if !v.seen_grid {
        return Err(IoError::invalid(name, "no <UnstructuredGrid> element"));
    }
    Ok(v.mesh)
}

impl Vtu<'_> {
    /// An error at byte offset `pos`.
    fn err_at(&self, pos: usize, msg: &str) -> IoError {
        IoError::parse(self.name, line_of(self.text, pos), msg)
    }

    /// An opening (or empty) element spanning `before..after`.
    fn start(
        &mut self,
        e: &BytesStart,
        before: usize,
        after: usize,
        empty: bool,
    ) -> Result<(), IoError> {
        match e.name().as_ref() {
            "VTKFile" => check_vtkfile(self.name, e)?,
            "UnstructuredGrid" => self.seen_grid = true,
            "Piece" => self.piece = Some(Cells::default()),
            "Points" => self.section = Section::Points,
            "Cells" => self.section = Section::Cells,
            "CellData" => self.section = Section::CellData,
            "PointData" | "FieldData" => self.section = Section::Other,
            "AppendedData" => return Err(IoError::unsupported(self.name, "VTU appended data")),
            "DataArray" => {
                let info = array_info(e, after).map_err(|m| self.err_at(before, &m))?;
                let info = info.ok_or_else(|| {
                    let msg = "binary or appended VTU data arrays (only format=\"ascii\")";
                    IoError::unsupported(self.name, msg)
                })?;
                if empty {
                    self.take(&info, "", before)?;
                } else {
                    self.array = Some(info);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// A closing element starting at `before`.
    fn end(&mut self, tag: &str, before: usize) -> Result<(), IoError> {
        match tag {
            "DataArray" => {
                if let Some(info) = self.array.take() {
                    let content = self.text.get(info.start..before).unwrap_or("");
                    self.take(&info, content, info.start)?;
                }
            }
            "Points" | "Cells" | "CellData" | "PointData" | "FieldData" => {
                self.section = Section::Other
            }
            "Piece" => {
                if let Some(cells) = self.piece.take() {
                    cells.append_to(self.name, &mut self.mesh)?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Hands a data array's content (starting at byte `start`) to the current piece.
    fn take(&mut self, info: &ArrayInfo, content: &str, start: usize) -> Result<(), IoError> {
        let line = line_of(self.text, start);
        let Some(cells) = self.piece.as_mut() else {
            return Err(self.err_at(start, "DataArray outside a Piece"));
        };
        take_array(self.name, content, line, self.section, info, cells)
    }
}

/// Refuses non-UnstructuredGrid and compressed files.
fn check_vtkfile(name: &str, e: &BytesStart) -> Result<(), IoError> {
    match attr(e, "type").as_deref() {
        Some("UnstructuredGrid") | None => {}
        Some(t) => return Err(IoError::unsupported(name, format!("VTK file type {t}"))),
    }
    if attr(e, "compressor").is_some() {
        return Err(IoError::unsupported(name, "compressed VTU"));
    }
    Ok(())
}

/// The attributes of a `<DataArray>`; `None` when its data is not ASCII.
fn array_info(e: &BytesStart, start: usize) -> Result<Option<ArrayInfo>, String> {
    if attr(e, "format").as_deref() != Some("ascii") {
        return Ok(None);
    }
    let components = match attr(e, "NumberOfComponents") {
        Some(c) => c
            .trim()
            .parse::<usize>()
            .map_err(|_| format!("bad NumberOfComponents '{c}'"))?,
        None => 1,
    };
    Ok(Some(ArrayInfo {
        name: attr(e, "Name").unwrap_or_default(),
        components,
        start,
    }))
}

/// Parses the content of a `<DataArray>` into the piece, according to its section.
fn take_array(
    file: &str,
    content: &str,
    line: usize,
    section: Section,
    info: &ArrayInfo,
    cells: &mut Cells,
) -> Result<(), IoError> {
    let mut t = Tokens::starting_at(file, content, line, None, "DataArray");
    match (section, info.name.as_str()) {
        (Section::Points, _) => {
            if info.components != 3 {
                let msg = format!("points have {} components, expected 3", info.components);
                return Err(t.error(msg));
            }
            let c = t.rest_f64("coordinate")?;
            if c.len() % 3 != 0 {
                let msg = format!("{} point coordinates, not a multiple of 3", c.len());
                return Err(IoError::parse(file, line, msg));
            }
            let pts = c.chunks_exact(3).map(|p| Point::new(p[0], p[1], p[2]));
            cells.points.extend(pts);
        }
        (Section::Cells, "connectivity") => cells.connectivity = t.rest_i64("point index")?,
        (Section::Cells, "offsets") => cells.offsets = t.rest_i64("cell offset")?,
        (Section::Cells, "types") => cells.types = t.rest_i64("cell type")?,
        (Section::CellData, n) if REF_NAMES.contains(&n) && info.components == 1 => {
            let v = t.rest_f64("cell reference")?;
            let refs = v
                .into_iter()
                .map(|x| to_ref(&t, x))
                .collect::<Result<_, _>>()?;
            cells.offer_refs(n, refs);
        }
        _ => {}
    }
    Ok(())
}

/// Parses a legacy ASCII `.vtk` file holding an `UNSTRUCTURED_GRID` (cells as `n i1 ..
/// in` records before version 5, or `OFFSETS`/`CONNECTIVITY` arrays from 5.1).
pub fn parse_legacy(name: &str, text: &str) -> Result<VolumeMesh, IoError> {
    let mut header = text.splitn(4, '\n');
    let magic = header.next().unwrap_or("");
    if !magic.trim_start().starts_with("# vtk DataFile") {
        let msg = format!(
            "expected '# vtk DataFile Version x.y', found '{}'",
            magic.trim()
        );
        return Err(IoError::parse(name, 1, msg));
    }
    let _title = header.next();
    let encoding = header.next().unwrap_or("").trim();
    if encoding.eq_ignore_ascii_case("BINARY") {
        return Err(IoError::unsupported(
            name,
            "binary legacy VTK (only ASCII is read)",
        ));
    }
    if !encoding.eq_ignore_ascii_case("ASCII") {
        return Err(IoError::parse(
            name,
            3,
            format!("expected ASCII, found '{encoding}'"),
        ));
    }
    let mut t = Tokens::starting_at(name, header.next().unwrap_or(""), 4, None, "file");
    let mut cells = Cells::default();
    let mut data_len = 0usize; // values per array in the current CELL_DATA / POINT_DATA
    let mut in_cell_data = false;
    while let Some(key) = t.next_token() {
        match key.to_ascii_uppercase().as_str() {
            "DATASET" => {
                let kind = t.expect("dataset type")?;
                if !kind.eq_ignore_ascii_case("UNSTRUCTURED_GRID") {
                    return Err(IoError::unsupported(name, format!("VTK dataset {kind}")));
                }
            }
            "POINTS" => {
                let n = t.count("number of points")?;
                t.expect("point data type")?;
                cells.points = read_n(&mut t, n, |t| t.point())?;
            }
            "CELLS" => legacy_cells(&mut t, &mut cells)?,
            "CELL_TYPES" => {
                let n = t.count("number of cell types")?;
                cells.types = read_n(&mut t, n, |t| t.i64("cell type"))?;
            }
            "CELL_DATA" | "POINT_DATA" => {
                in_cell_data = key.eq_ignore_ascii_case("CELL_DATA");
                data_len = t.count("number of data values")?;
            }
            "SCALARS" => legacy_scalars(&mut t, data_len, in_cell_data, &mut cells)?,
            "FIELD" => legacy_field(&mut t, in_cell_data, &mut cells)?,
            "VECTORS" | "NORMALS" => skip_values(&mut t, 2, 3 * data_len)?,
            "TENSORS" => skip_values(&mut t, 2, 9 * data_len)?,
            "METADATA" | "INFORMATION" | "NAME" | "DATA" | "COMPONENT_NAMES" => {
                skip_metadata(&mut t)
            }
            _ => return Err(t.error(format!("unexpected '{key}' in legacy VTK"))),
        }
    }
    let mut m = VolumeMesh::default();
    cells.append_to(name, &mut m)?;
    Ok(m)
}

/// `CELLS`: legacy records, or (5.1) `OFFSETS` and `CONNECTIVITY` arrays.
fn legacy_cells(t: &mut Tokens, cells: &mut Cells) -> Result<(), IoError> {
    let a = t.count("number of cells")?;
    let b = t.count("cell list size")?;
    if t.peek().is_some_and(|k| k.eq_ignore_ascii_case("OFFSETS")) {
        t.next_token();
        t.expect("offsets data type")?;
        let offsets = read_n(t, a, |t| t.i64("cell offset"))?;
        let kw = t.expect("CONNECTIVITY")?;
        if !kw.eq_ignore_ascii_case("CONNECTIVITY") {
            return Err(t.error(format!("expected CONNECTIVITY, found '{kw}'")));
        }
        t.expect("connectivity data type")?;
        cells.connectivity = read_n(t, b, |t| t.i64("point index"))?;
        cells.offsets = offsets.into_iter().skip(1).collect();
        return Ok(());
    }
    cells.connectivity.reserve(b.min(MAX_PREALLOC));
    for _ in 0..a {
        let k = t.count("number of cell points")?;
        for _ in 0..k {
            cells.connectivity.push(t.i64("point index")?);
        }
        cells.offsets.push(cells.connectivity.len() as i64);
    }
    Ok(())
}

/// `SCALARS name type [components]` with an optional `LOOKUP_TABLE`.
fn legacy_scalars(t: &mut Tokens, n: usize, cell: bool, cells: &mut Cells) -> Result<(), IoError> {
    let name = t.expect("array name")?;
    t.expect("data type")?;
    let mut comps = 1;
    if t.peek().is_some_and(|k| k.parse::<usize>().is_ok()) {
        comps = t.count("number of components")?;
    }
    if t.peek()
        .is_some_and(|k| k.eq_ignore_ascii_case("LOOKUP_TABLE"))
    {
        t.next_token();
        t.expect("lookup table name")?;
    }
    legacy_values(t, name, comps, n, cell, cells)
}

/// `FIELD name k` then `k` arrays `name components tuples type values..`.
fn legacy_field(t: &mut Tokens, cell: bool, cells: &mut Cells) -> Result<(), IoError> {
    t.expect("field name")?;
    let k = t.count("number of arrays")?;
    for _ in 0..k {
        let name = t.expect("array name")?;
        let comps = t.count("number of components")?;
        let tuples = t.count("number of tuples")?;
        t.expect("data type")?;
        legacy_values(t, name, comps, tuples, cell, cells)?;
        if t.peek().is_some_and(|k| k.eq_ignore_ascii_case("METADATA")) {
            t.next_token();
            skip_metadata(t);
        }
    }
    Ok(())
}

/// Reads `n` tuples of an array; keeps them as references when they qualify.
fn legacy_values(
    t: &mut Tokens,
    name: &str,
    comps: usize,
    n: usize,
    cell: bool,
    cells: &mut Cells,
) -> Result<(), IoError> {
    if cell && comps == 1 && REF_NAMES.contains(&name) {
        let v = read_n(t, n, |t| {
            let x = t.f64("cell reference")?;
            to_ref(t, x)
        })?;
        cells.offer_refs(name, v);
        Ok(())
    } else {
        skip_values(t, 0, comps.saturating_mul(n))
    }
}

/// Skips `words` header words then `n` values.
fn skip_values(t: &mut Tokens, words: usize, n: usize) -> Result<(), IoError> {
    for _ in 0..words.saturating_add(n) {
        t.expect("a value")?;
    }
    Ok(())
}

/// Skips a `METADATA` block: up to the next token that starts a data section.
fn skip_metadata(t: &mut Tokens) {
    const KEYS: [&str; 8] = [
        "POINTS",
        "CELLS",
        "CELL_TYPES",
        "CELL_DATA",
        "POINT_DATA",
        "SCALARS",
        "FIELD",
        "VECTORS",
    ];
    while let Some(k) = t.peek() {
        if KEYS.iter().any(|key| k.eq_ignore_ascii_case(key)) {
            return;
        }
        t.next_token();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tet_mesh() -> VolumeMesh {
        VolumeMesh {
            vertices: vec![
                Point::new(0.0, 0.0, 0.0),
                Point::new(1.0 / 3.0, -0.0, 0.0),
                Point::new(0.0, 1e-300, 0.0),
                Point::new(0.0, 0.0, 7e22),
                Point::new(1.0, 1.0, 1.0),
            ],
            tets: vec![[0, 1, 2, 3], [1, 2, 3, 4]],
            tet_refs: vec![4, -2],
            ..Default::default()
        }
    }

    #[test]
    fn vtu_write_then_parse() {
        let m = tet_mesh();
        let mut buf = Vec::new();
        write_vtu(&mut buf, &m).unwrap();
        let back = parse_vtu("t.vtu", std::str::from_utf8(&buf).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    /// As meshio writes it with `binary=False`: mixed cells, several cell data arrays.
    const MESHIO_VTU: &str = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<!--This file was created by meshio v5.3.5-->
<UnstructuredGrid>
<Piece NumberOfPoints="4" NumberOfCells="2">
<Points>
<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">
0.0 0.0 0.0 1.0 0.0 0.0
0.0 1.0 0.0 0.0 0.0 1.0
</DataArray>
</Points>
<Cells>
<DataArray type="Int64" Name="connectivity" format="ascii">
0 1 2 0 1 2 3
</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">
3 7
</DataArray>
<DataArray type="Int64" Name="types" format="ascii">
5 10
</DataArray>
</Cells>
<CellData>
<DataArray type="Int64" Name="gmsh:geometrical" format="ascii">
1 1
</DataArray>
<DataArray type="Int64" Name="medit:ref" format="ascii">
3 5
</DataArray>
</CellData>
</Piece>
</UnstructuredGrid>
</VTKFile>
"#;

    #[test]
    fn vtu_as_meshio_writes_it() {
        let m = parse_vtu("m.vtu", MESHIO_VTU).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(m.tet_refs, vec![5]);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.triangle_refs, vec![3]);
    }

    #[test]
    fn vtu_errors() {
        let bad = MESHIO_VTU.replace("0 1 2 0 1 2 3", "0 1 2 0 1 2 x");
        let e = parse_vtu("m.vtu", &bad).unwrap_err().to_string();
        assert!(e.starts_with("m.vtu:14: expected point index"), "{e}");
        let bad = MESHIO_VTU.replace("0 1 2 0 1 2 3", "0 1 2 0 1 2 9");
        let e = parse_vtu("m.vtu", &bad).unwrap_err().to_string();
        assert_eq!(e, "m.vtu: cell 1 refers to point 9 but there are 4 points");
        let bad = MESHIO_VTU.replace("3 7", "3 8");
        let e = parse_vtu("m.vtu", &bad).unwrap_err().to_string();
        assert_eq!(e, "m.vtu: cell 1: bad offset 8");
        let bad = MESHIO_VTU.replace("format=\"ascii\"", "format=\"binary\"");
        let e = parse_vtu("m.vtu", &bad).unwrap_err().to_string();
        assert!(e.contains("unsupported"), "{e}");
        let e = parse_vtu("m.vtu", "<VTKFile><Unstr")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.vtu:1: XML error"), "{e}");
    }

    const LEGACY4: &str = "# vtk DataFile Version 4.2\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n\
        POINTS 4 double\n0 0 0 1 0 0\n0 1 0 0 0 1\nCELLS 2 9\n3 0 1 2\n4 0 1 2 3\n\
        CELL_TYPES 2\n5\n10\nCELL_DATA 2\nSCALARS region int 1\nLOOKUP_TABLE default\n7 8\n";

    const LEGACY51: &str = "# vtk DataFile Version 5.1\nmeshio\nASCII\nDATASET UNSTRUCTURED_GRID\n\
        POINTS 4 double\n0 0 0 1 0 0\n0 1 0 0 0 1\nCELLS 3 7\nOFFSETS vtktypeint64\n0 3 7\n\
        CONNECTIVITY vtktypeint64\n0 1 2 0 1 2 3\nCELL_TYPES 2\n5\n10\n\n\
        CELL_DATA 2\nFIELD FieldData 2\nfoo 3 2 double\n1 2 3 4 5 6\n\
        medit:ref 1 2 int\n7 8\n";

    #[test]
    fn legacy_both_cell_layouts() {
        for (text, r) in [(LEGACY4, 8), (LEGACY51, 8)] {
            let m = parse_legacy("l.vtk", text).unwrap();
            assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
            assert_eq!(m.tet_refs, vec![r]);
            assert_eq!(m.triangles, vec![[0, 1, 2]]);
        }
    }

    #[test]
    fn legacy_errors() {
        let bad = LEGACY4.replace("4 0 1 2 3", "4 0 1 2");
        let e = parse_legacy("l.vtk", &bad).unwrap_err().to_string();
        assert!(e.starts_with("l.vtk:11: expected point index"), "{e}");
        let e = parse_legacy("l.vtk", "hello\n").unwrap_err().to_string();
        assert!(e.starts_with("l.vtk:1: expected '# vtk DataFile"), "{e}");
        let bad = LEGACY4.replace("DATASET UNSTRUCTURED_GRID", "DATASET POLYDATA");
        let e = parse_legacy("l.vtk", &bad).unwrap_err().to_string();
        assert!(e.contains("unsupported"), "{e}");
    }
}
