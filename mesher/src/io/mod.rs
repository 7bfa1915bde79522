//! File formats: surface readers and volume-mesh writers and readers. All file IO of the
//! library lives here.
//!
//! * Surfaces ([`read_surface`], [`write_surface`]): Wavefront `.obj` (via `tobj`), `.off`, `.stl` (ASCII
//!   and binary), Medit `.mesh`. Exactly coincident vertices are welded and unused
//!   vertices dropped; [`SurfaceRead`] reports how many.
//! * Volume meshes ([`write_volume`], [`read_volume`]): Medit `.mesh` (+ `.sol` sizes),
//!   VTK `.vtu` (XML, ASCII; legacy `.vtk` ASCII read only), Gmsh `.msh` (4.1 written;
//!   2.2 and 4.1 ASCII and 2.2 binary read), TetGen `.node`/`.ele`/`.face`.
//!
//! Every reader also exists as a `parse` function over text or bytes with a file name for
//! messages, so nothing needs a file system. Readers never panic: malformed input gives an
//! [`IoError`] naming the file, the line (or byte offset) and the problem.

mod error;
pub mod gmsh;
mod gmsh_binary;
pub mod medit;
pub mod obj;
pub mod off;
pub mod stl;
pub mod tetgen;
mod text;
pub mod vtk;

pub use error::IoError;

use crate::geom::Point;
use crate::surface::Surface;
use crate::volume::VolumeMesh;
use std::collections::HashMap;
use std::io::{BufWriter, Write};
use std::path::Path;

/// A surface read from a file, after welding coincident vertices and dropping unused ones.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceRead {
    /// The indexed surface.
    pub surface: Surface,
    /// Vertices merged into an earlier vertex with bitwise-equal coordinates.
    pub welded_vertices: usize,
    /// Vertices (after welding) that no triangle uses, removed.
    pub dropped_unused_vertices: usize,
}

/// Surface file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceFormat {
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// Stereolithography, ASCII or binary.
    Stl,
    /// Medit `.mesh` (its Vertices and Triangles).
    Medit,
}

impl SurfaceFormat {
    /// The format named by a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<SurfaceFormat> {
        match extension(path).as_str() {
            "obj" => Some(SurfaceFormat::Obj),
            "off" => Some(SurfaceFormat::Off),
            "stl" => Some(SurfaceFormat::Stl),
            "mesh" => Some(SurfaceFormat::Medit),
            _ => None,
        }
    }
}

/// Lower-case extension of a path, or "".
fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// Reads a whole file.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    std::fs::read(path).map_err(|e| IoError::os(path, e))
}

/// Reads a surface, choosing the format from the extension (`.obj`, `.off`, `.stl`,
/// `.mesh`), welds exactly coincident vertices and drops unused ones.
pub fn read_surface(path: &Path) -> Result<SurfaceRead, IoError> {
    let format = surface_format(path)?;
    let bytes = read_bytes(path)?;
    parse_surface(&path.display().to_string(), &bytes, format)
}

/// Parses a surface held in memory; `name` is used in error messages.
pub fn parse_surface(
    name: &str,
    bytes: &[u8],
    format: SurfaceFormat,
) -> Result<SurfaceRead, IoError> {
    Ok(weld(parse_surface_unwelded(name, bytes, format)?))
}

/// Reads a surface as the file has it: no welding, unused vertices kept (e.g. to read
/// the points of a point cloud stored as `.off`/`.obj` without faces).
pub fn read_surface_unwelded(path: &Path) -> Result<Surface, IoError> {
    let format = surface_format(path)?;
    let bytes = read_bytes(path)?;
    parse_surface_unwelded(&path.display().to_string(), &bytes, format)
}

/// Parses a surface held in memory without welding; `name` is used in error messages.
pub fn parse_surface_unwelded(
    name: &str,
    bytes: &[u8],
    format: SurfaceFormat,
) -> Result<Surface, IoError> {
    Ok(match format {
        SurfaceFormat::Stl => stl::parse(name, bytes)?,
        _ => {
            let text = text::utf8_text(bytes);
            match format {
                SurfaceFormat::Obj => obj::parse(name, &text)?,
                SurfaceFormat::Off => off::parse(name, &text)?,
                _ => medit::parse_surface(name, &text)?,
            }
        }
    })
}

/// The surface format of `path`, or an error listing the supported extensions.
fn surface_format(path: &Path) -> Result<SurfaceFormat, IoError> {
    SurfaceFormat::from_path(path).ok_or_else(|| IoError::UnknownFormat {
        path: path.to_path_buf(),
        kind: "surface",
        supported: ".obj .off .stl .mesh",
    })
}

/// Writes a surface, choosing the format from the extension: `.off`, `.obj`, `.stl`
/// (ASCII, full precision) or `.mesh` (Medit).
pub fn write_surface(path: &Path, surface: &Surface) -> Result<(), IoError> {
    match surface_format(path)? {
        SurfaceFormat::Off => write_with(path, |w| off::write(w, surface)),
        SurfaceFormat::Obj => write_with(path, |w| obj::write(w, surface)),
        SurfaceFormat::Stl => write_with(path, |w| stl::write_ascii(w, surface)),
        SurfaceFormat::Medit => write_with(path, |w| medit::write_surface(w, surface)),
    }
}

/// Merges vertices with bitwise-equal coordinates (-0.0 counted as 0.0), then removes
/// vertices no triangle uses. Triangles keep their order; degenerate ones are kept.
pub fn weld(surface: Surface) -> SurfaceRead {
    let Surface {
        vertices,
        triangles,
    } = surface;
    let n = vertices.len();
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(n);
    let mut unique: Vec<Point> = Vec::with_capacity(n);
    let mut to_unique: Vec<u32> = Vec::with_capacity(n);
    for p in &vertices {
        let q = *p + Point::ZERO; // -0.0 + 0.0 == +0.0
        let key = [q.x.to_bits(), q.y.to_bits(), q.z.to_bits()];
        let id = *first.entry(key).or_insert_with(|| {
            unique.push(q);
            (unique.len() - 1) as u32
        });
        to_unique.push(id);
    }
    let welded = n - unique.len();
    let mut new_id = vec![u32::MAX; unique.len()];
    let mut kept = Vec::with_capacity(unique.len());
    let mut out_tris = Vec::with_capacity(triangles.len());
    for t in &triangles {
        let mut o = [0u32; 3];
        for (slot, &v) in o.iter_mut().zip(t) {
            // Readers validate indices; an out-of-range one maps to vertex 0 rather than
            // panicking (cannot happen for surfaces built by this module).
            let u = to_unique.get(v as usize).copied().unwrap_or(0) as usize;
            let id = new_id.get_mut(u).map(|x| {
                if *x == u32::MAX {
                    *x = kept.len() as u32;
                    kept.push(unique[u]);
                }
                *x
            });
            *slot = id.unwrap_or(0);
        }
        out_tris.push(o);
    }
    let dropped = unique.len() - kept.len();
    SurfaceRead {
        surface: Surface {
            vertices: kept,
            triangles: out_tris,
        },
        welded_vertices: welded,
        dropped_unused_vertices: dropped,
    }
}

/// Volume mesh file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeFormat {
    /// Medit `.mesh` (and `.sol` for vertex sizes).
    Medit,
    /// VTK XML unstructured grid `.vtu`.
    Vtu,
    /// Legacy VTK `.vtk` (read only).
    LegacyVtk,
    /// Gmsh `.msh`.
    Gmsh,
    /// TetGen `.node`/`.ele`/`.face`.
    TetGen,
}

impl VolumeFormat {
    /// The format named by a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<VolumeFormat> {
        match extension(path).as_str() {
            "mesh" => Some(VolumeFormat::Medit),
            "vtu" => Some(VolumeFormat::Vtu),
            "vtk" => Some(VolumeFormat::LegacyVtk),
            "msh" => Some(VolumeFormat::Gmsh),
            "node" | "ele" | "face" => Some(VolumeFormat::TetGen),
            _ => None,
        }
    }
}

/// Writes a volume mesh, choosing the format from the extension: `.mesh` (plus a `.sol`
/// beside it when the mesh has vertex sizes), `.vtu`, `.msh`, or `.node`/`.ele` (TetGen:
/// writes `.node`, `.ele` and `.face` with the same base name).
pub fn write_volume(path: &Path, mesh: &VolumeMesh) -> Result<(), IoError> {
    match VolumeFormat::from_path(path) {
        Some(VolumeFormat::Medit) => medit::write_files(path, mesh),
        Some(VolumeFormat::Vtu) => write_with(path, |w| vtk::write_vtu(w, mesh)),
        Some(VolumeFormat::Gmsh) => write_with(path, |w| gmsh::write(w, mesh)),
        Some(VolumeFormat::TetGen) => tetgen::write_files(path, mesh),
        _ => Err(IoError::UnknownFormat {
            path: path.to_path_buf(),
            kind: "volume mesh output",
            supported: ".mesh .vtu .msh .node .ele",
        }),
    }
}

/// Reads a volume mesh, choosing the format from the extension: `.mesh` (with sizes from
/// a `.sol` beside it, if any), `.vtu`, `.vtk`, `.msh`, `.node`/`.ele`/`.face` (TetGen).
pub fn read_volume(path: &Path) -> Result<VolumeMesh, IoError> {
    match VolumeFormat::from_path(path) {
        Some(VolumeFormat::Medit) => medit::read_files(path),
        Some(VolumeFormat::Vtu) => {
            let bytes = read_bytes(path)?;
            vtk::parse_vtu(&path.display().to_string(), &text::utf8_text(&bytes))
        }
        Some(VolumeFormat::LegacyVtk) => {
            let bytes = read_bytes(path)?;
            vtk::parse_legacy(&path.display().to_string(), &text::utf8_text(&bytes))
        }
        Some(VolumeFormat::Gmsh) => {
            let bytes = read_bytes(path)?;
            gmsh::parse_bytes(&path.display().to_string(), &bytes)
        }
        Some(VolumeFormat::TetGen) => tetgen::read_files(path),
        None => Err(IoError::UnknownFormat {
            path: path.to_path_buf(),
            kind: "volume mesh",
            supported: ".mesh .vtu .vtk .msh .node .ele .face",
        }),
    }
}

/// Writes `path` atomically: runs `f` on a buffered writer to a temporary file in the
/// same directory, flushes it, then renames it to `path`. A failed write (in `f`, the
/// flush or the rename) removes the temporary file and leaves whatever `path` held
/// before, so no half-written file ever appears under the requested name. OS errors
/// name the path.
pub fn write_with(
    path: &Path,
    f: impl FnOnce(&mut BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let os = |e| IoError::os(path, e);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // Created with 0666 minus the umask, as `File::create` would.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let (file, tmp) = builder.tempfile_in(dir).map_err(os)?.into_parts();
    let mut w = BufWriter::with_capacity(1 << 16, file);
    f(&mut w).and_then(|_| w.flush()).map_err(os)?;
    drop(w);
    tmp.persist(path).map_err(|e| os(e.error))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weld_merges_bitwise_equal_and_negative_zero() {
        let s = Surface {
            vertices: vec![
                Point::new(0.0, 0.0, 0.0),
                Point::new(1.0, 0.0, 0.0),
                Point::new(0.0, 1.0, 0.0),
                Point::new(-0.0, 0.0, -0.0),
                Point::new(5.0, 5.0, 5.0),
                Point::new(1.0, 0.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [3, 5, 2]],
        };
        let r = weld(s);
        assert_eq!(r.welded_vertices, 2);
        assert_eq!(r.dropped_unused_vertices, 1);
        assert_eq!(r.surface.vertices.len(), 3);
        assert_eq!(r.surface.triangles, vec![[0, 1, 2], [0, 1, 2]]);
        assert!(r.surface.vertices[0].x.is_sign_positive());
    }

    #[test]
    fn unknown_extension_is_an_error() {
        let e = read_surface(Path::new("x.ply")).unwrap_err();
        assert!(e.to_string().contains("x.ply"), "{e}");
        let e = write_volume(Path::new("x.abc"), &VolumeMesh::default()).unwrap_err();
        assert!(e.to_string().contains("x.abc"), "{e}");
    }

    #[test]
    fn a_failed_write_leaves_no_half_written_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.mesh");
        let fail = |w: &mut BufWriter<std::fs::File>| -> std::io::Result<()> {
            w.write_all(b"partial")?;
            Err(std::io::Error::other("disk full"))
        };
        let e = write_with(&path, fail).unwrap_err();
        assert!(e.to_string().contains("out.mesh"), "{e}");
        assert!(!path.exists());
        write_with(&path, |w| w.write_all(b"old")).unwrap();
        write_with(&path, fail).unwrap_err();
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("out.mesh")]);
    }
}
