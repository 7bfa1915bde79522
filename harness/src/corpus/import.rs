//! `harness corpus import DIR`: a user's own surfaces as corpus models. Every surface
//! file under DIR (`.off`, `.obj`, `.stl`, `.mesh`, recursively) is read, checked with
//! `Surface::check()` and written to the git-ignored local manifest
//! (`corpus/local.toml`, the format of `corpus/manifest.toml`) with a `file:` source, its
//! SHA-256 and triangle count: tier `local` when clean, `dirty` (category from the worst
//! defect) when not. `harness run --corpus local` then runs them; [`super::load_manifest`]
//! reads the local manifest beside the shared one.

use super::manifest::{parse_manifest, to_manifest_text, Category, Model, Source, Tier};
use super::{load_shared_manifest, sha256_hex, CorpusError};
use mesher::surface::CheckReport;
use std::path::{Path, PathBuf};

/// The local manifest of a repository.
pub fn local_manifest_path(repo_root: &Path) -> PathBuf {
    repo_root.join("corpus").join("local.toml")
}

/// Reads a local manifest (absent = empty).
pub fn load_local(path: &Path) -> Result<Vec<Model>, CorpusError> {
    match std::fs::read_to_string(path) {
        Ok(text) => parse_manifest(path, &text),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(source) => Err(CorpusError::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

const EXTENSIONS: &[&str] = &["off", "obj", "stl", "mesh"];

/// Surface files under `dir`, sorted (deterministic ids).
fn surface_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), CorpusError> {
    let io = |source| CorpusError::Io {
        path: dir.to_path_buf(),
        source,
    };
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            surface_files(&p, out)?;
        } else if p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
        {
            out.push(p);
        }
    }
    Ok(())
}

/// Tier and category from a check report.
fn classify(r: &CheckReport) -> (Tier, Category) {
    if r.is_clean() {
        (Tier::Local, Category::User)
    } else if r.self_intersections.count > 0 {
        (Tier::Dirty, Category::SelfIntersecting)
    } else if !r.non_manifold_edges.is_empty() {
        (Tier::Dirty, Category::NonManifold)
    } else if !r.open_edges.is_empty() {
        (Tier::Dirty, Category::Open)
    } else {
        (Tier::Dirty, Category::User)
    }
}

/// A model id from a file stem, unique among `taken`.
fn unique_id(path: &Path, taken: &[String]) -> String {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    let base: String = stem
        .unwrap_or_else(|| "model".into())
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let base = if taken.contains(&base) {
        format!("local-{base}")
    } else {
        base
    };
    let mut id = base.clone();
    let mut n = 2;
    while taken.contains(&id) {
        id = format!("{base}-{n}");
        n += 1;
    }
    id
}

/// One imported (or refused) file.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The file.
    pub path: PathBuf,
    /// The model, or why the file was left out.
    pub model: Result<Model, String>,
    /// `clean` or the defects found.
    pub defects: String,
}

/// Imports the surfaces under `dir` into the local manifest `manifest` (entries of the
/// same file are replaced) and lists what happened per file.
pub fn import(repo_root: &Path, dir: &Path, manifest: &Path) -> Result<Vec<Imported>, CorpusError> {
    let mut local = load_local(manifest)?;
    let shared = load_shared_manifest(repo_root)?;
    let mut files = Vec::new();
    surface_files(dir, &mut files)?;
    let mut out = Vec::new();
    for path in files {
        let abs = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
        let source = abs.to_string_lossy().into_owned();
        local.retain(|m| m.source != Source::Local(source.clone()));
        let imported = import_one(&abs, &source, &shared, &local);
        if let Ok(m) = &imported.model {
            local.push(m.clone());
        }
        out.push(imported);
    }
    let text = to_manifest_text(&local).map_err(|e| CorpusError::Manifest {
        path: manifest.to_path_buf(),
        msg: e.to_string(),
    })?;
    let header = "# A user's own models (`harness corpus import DIR`); git-ignored.\n\
                  # `harness run --corpus local` runs the clean ones.\n\n";
    std::fs::write(manifest, format!("{header}{text}")).map_err(|source| CorpusError::Io {
        path: manifest.to_path_buf(),
        source,
    })?;
    Ok(out)
}

fn import_one(path: &Path, source: &str, shared: &[Model], local: &[Model]) -> Imported {
    let fail = |msg: String| Imported {
        path: path.to_path_buf(),
        model: Err(msg),
        defects: String::new(),
    };
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return fail(e.to_string()),
    };
    let surface = match mesher::io::read_surface(path) {
        Ok(r) => r.surface,
        Err(e) => return fail(format!("not a readable surface: {e}")),
    };
    let report = surface.check();
    let (tier, category) = classify(&report);
    let defects = super::defect_summary(&report);
    let taken: Vec<String> = shared.iter().chain(local).map(|m| m.id.clone()).collect();
    Imported {
        path: path.to_path_buf(),
        model: Ok(Model {
            id: unique_id(path, &taken),
            source: Source::Local(source.to_string()),
            sha256: sha256_hex(&bytes),
            triangles: surface.triangles.len(),
            tier,
            category,
            licence: "the user's own".into(),
            note: format!("imported from {source}: {defects}"),
        }),
        defects,
    }
}
