//! Robustness: every reader, fed random bytes or randomly damaged valid files, returns
//! (an error or a mesh) without panicking, and its errors name the file.

use mesher::io::{gmsh, medit, obj, off, parse_surface, stl, tetgen, vtk, SurfaceFormat};
use proptest::prelude::*;

const OFF: &str = "OFF\n# c\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 3 2\n";
const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1//1 2//1 3//1\nf -1 -2 -3 1\n";
const STL: &str = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
    vertex 0 1 0\nendloop\nendfacet\nendsolid a\n";
const MESH: &str = "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n\
    0 1 0 0\n0 0 1 0\nTriangles\n1\n1 2 3 1\nTetrahedra\n1\n1 2 3 4 1\nEnd\n";
const SOL: &str = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n2\n1 1\n0.5\n1.5\nEnd\n";
const MSH41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n\
    1 0 0 0 1 1 1 1 7 0\n$EndEntities\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n\
    1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";
const MSH22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n\
    3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n";
const VTU: &str = "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\
    <Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points>\
    <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0 1 0 0\n\
    0 1 0 0 0 1\n</DataArray></Points><Cells>\
    <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\
    <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\
    <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>\
    <CellData><DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">3</DataArray>\
    </CellData></Piece></UnstructuredGrid></VTKFile>\n";
const VTK: &str = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n\
    POINTS 4 double\n0 0 0 1 0 0\n0 1 0 0 0 1\nCELLS 2 4\nOFFSETS vtktypeint64\n0 4\n\
    CONNECTIVITY vtktypeint64\n0 1 2 3\nCELL_TYPES 1\n10\nCELL_DATA 1\n\
    SCALARS region int 1\nLOOKUP_TABLE default\n2\n";
const NODE: &str = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
const ELE: &str = "1 4 1\n1 1 2 3 4 -2\n";
const FACE: &str = "1 1\n1 1 2 3 5\n";

/// Runs every reader on `text` (and `bytes`); any error must name the file.
fn all_readers(text: &str, bytes: &[u8]) {
    let check = |r: Result<(), mesher::io::IoError>| {
        if let Err(e) = r {
            assert!(e.to_string().starts_with('f'), "{e}");
        }
    };
    for f in [
        SurfaceFormat::Off,
        SurfaceFormat::Obj,
        SurfaceFormat::Stl,
        SurfaceFormat::Medit,
    ] {
        check(parse_surface("f", bytes, f).map(|_| ()));
    }
    check(off::parse("f", text).map(|_| ()));
    check(obj::parse("f", text).map(|_| ()));
    check(stl::parse("f", bytes).map(|_| ()));
    check(medit::parse_mesh("f", text).map(|_| ()));
    check(medit::parse_sol("f", text, 2).map(|_| ()));
    check(gmsh::parse("f", text).map(|_| ()));
    check(gmsh::parse_bytes("f", bytes).map(|_| ()));
    check(vtk::parse_vtu("f", text).map(|_| ()));
    check(vtk::parse_legacy("f", text).map(|_| ()));
    check(tetgen::parse(("f", text), ("f", ELE), Some(("f", FACE))).map(|_| ()));
    check(tetgen::parse(("f", NODE), ("f", text), Some(("f", text))).map(|_| ()));
}

const SAMPLES: [&str; 11] = [OFF, OBJ, STL, MESH, SOL, MSH41, MSH22, VTU, VTK, NODE, ELE];

/// Tokens that make damaged files interesting.
const VOCAB: [&str; 16] = [
    "0",
    "1",
    "-1",
    "3",
    "4",
    "99999999999",
    "nan",
    "1e308",
    "-0",
    "$EndNodes",
    "End",
    "Vertices",
    "\n",
    "#",
    "<DataArray format=\"ascii\">",
    "</DataArray>",
];

/// `sample` with a few tokens replaced, deleted or inserted.
fn damage(sample: &str, edits: &[(usize, usize, u8)]) -> String {
    let mut toks: Vec<String> = sample.split(' ').map(str::to_string).collect();
    for &(at, v, kind) in edits {
        let i = at % (toks.len() + 1);
        let w = VOCAB[v % VOCAB.len()].to_string();
        match kind % 3 {
            0 if i < toks.len() => toks[i] = w,
            1 if i < toks.len() => {
                toks.remove(i);
            }
            _ => toks.insert(i, w),
        }
    }
    toks.join(" ")
}

#[test]
fn valid_samples_parse() {
    off::parse("f", OFF).unwrap();
    obj::parse("f", OBJ).unwrap();
    stl::parse("f", STL.as_bytes()).unwrap();
    medit::parse_mesh("f", MESH).unwrap();
    medit::parse_sol("f", SOL, 2).unwrap();
    gmsh::parse("f", MSH41).unwrap();
    gmsh::parse("f", MSH22).unwrap();
    vtk::parse_vtu("f", VTU).unwrap();
    vtk::parse_legacy("f", VTK).unwrap();
    tetgen::parse(("f", NODE), ("f", ELE), Some(("f", FACE))).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        all_readers(&String::from_utf8_lossy(&bytes), &bytes);
    }

    #[test]
    fn damaged_files_never_panic(
        which in 0usize..SAMPLES.len(),
        edits in proptest::collection::vec((0usize..200, 0usize..64, any::<u8>()), 1..6),
        cut in 0usize..400,
    ) {
        let text = damage(SAMPLES[which], &edits);
        all_readers(&text, text.as_bytes());
        let cut = text.char_indices().map(|(i, _)| i).find(|&i| i >= cut).unwrap_or(text.len());
        all_readers(&text[..cut], &text.as_bytes()[..cut]);
    }

    #[test]
    fn binary_gmsh_never_panics(body in proptest::collection::vec(any::<u8>(), 0..300)) {
        let mut b = b"$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n$Nodes\n2\n".to_vec();
        b.extend_from_slice(&body);
        let _ = gmsh::parse_bytes("f", &b);
        b.extend_from_slice(b"\n$EndNodes\n$Elements\n1\n");
        b.extend_from_slice(&body);
        let _ = gmsh::parse_bytes("f", &b);
    }

    #[test]
    fn binary_stl_never_panics(n in 0u32..4, body in proptest::collection::vec(any::<u8>(), 0..220)) {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&n.to_le_bytes());
        b.extend_from_slice(&body);
        b.resize(84 + 50 * n as usize, 0xff);
        let _ = stl::parse("f", &b);
    }
}
