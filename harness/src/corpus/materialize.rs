//! Resolving a model to a readable surface file in `corpus/cache/`, with its checksum
//! verified. Fetched files are only looked up (`scripts/fetch-corpus.sh` fetches them);
//! generated, combined and refined models are written to `corpus/cache/generated/ID.off`
//! on demand, deterministically.

use super::generate;
use super::manifest::{Model, Source};
use super::{load_manifest, CorpusError};
use mesher::io::{off, read_surface};
use mesher::Surface;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The cache folder of a repository.
pub fn cache_dir(repo_root: &Path) -> PathBuf {
    repo_root.join("corpus").join("cache")
}

/// Where a model's file lives (whether or not it exists yet).
pub fn cache_path(repo_root: &Path, model: &Model) -> PathBuf {
    let cache = cache_dir(repo_root);
    match &model.source {
        Source::Cgal(p) => cache.join("cgal").join(p),
        Source::Netgen(p) => cache.join("netgen").join(p),
        Source::Gmsh(p) => cache.join("gmsh").join(p),
        Source::Local(p) => PathBuf::from(p),
        _ => cache.join("generated").join(format!("{}.off", model.id)),
    }
}

/// Hex SHA-256 of bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The path of `model`'s surface file, checksum verified. Fetches nothing: a missing
/// Debian-sourced file is an error that says to run `scripts/fetch-corpus.sh`.
/// Generated models are (re)written when absent or stale.
pub fn materialize(repo_root: &Path, model: &Model) -> Result<PathBuf, CorpusError> {
    let path = cache_path(repo_root, model);
    if model.source.is_fetched() {
        let bytes = std::fs::read(&path).map_err(|_| CorpusError::Missing {
            model: model.id.clone(),
            path: path.clone(),
        })?;
        verify(model, &path, &bytes)?;
        return Ok(path);
    }
    if let Ok(bytes) = std::fs::read(&path) {
        if sha256_hex(&bytes) == model.sha256 {
            return Ok(path);
        }
    }
    let bytes = render(repo_root, model)?;
    verify(model, &path, &bytes)?;
    write_atomic(&path, &bytes)?;
    Ok(path)
}

/// Compares `bytes`' checksum with the manifest's.
fn verify(model: &Model, path: &Path, bytes: &[u8]) -> Result<(), CorpusError> {
    let actual = sha256_hex(bytes);
    if actual != model.sha256 {
        return Err(CorpusError::Checksum {
            model: model.id.clone(),
            path: path.to_path_buf(),
            expected: model.sha256.clone(),
            actual,
        });
    }
    Ok(())
}

/// Writes through a temporary file and a rename, so a reader never sees half a file.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CorpusError> {
    let io = |e| CorpusError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let tmp = path.with_extension(format!("off.tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// The OFF bytes of a generated, combined or refined model (not verified).
pub fn render(repo_root: &Path, model: &Model) -> Result<Vec<u8>, CorpusError> {
    if let Source::Generated(name) = &model.source {
        if let Some(bytes) = generate::raw_bytes(name) {
            return Ok(bytes);
        }
    }
    let surface = build(repo_root, model)?;
    Ok(off_bytes(&surface))
}

/// A surface as OFF bytes (shortest round-trip coordinates: deterministic).
pub fn off_bytes(surface: &Surface) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = off::write(&mut out, surface);
    out
}

/// The surface of a non-fetched model.
fn build(repo_root: &Path, model: &Model) -> Result<Surface, CorpusError> {
    match &model.source {
        Source::Generated(name) => {
            generate::by_name(name).ok_or_else(|| CorpusError::UnknownModel(name.clone()))
        }
        Source::Combine(parts) => {
            let models = load_manifest(repo_root)?;
            let mut out = Surface::default();
            for (id, reverse) in parts {
                let part = read_model(repo_root, &models, id)?;
                let part = if *reverse {
                    generate::reversed(part)
                } else {
                    part
                };
                generate::append(&mut out, &part);
            }
            Ok(out)
        }
        Source::Refine(id, n) => {
            let models = load_manifest(repo_root)?;
            let part = read_model(repo_root, &models, id)?;
            Ok(generate::refine(&part, *n).0)
        }
        _ => read_surface(&materialize(repo_root, model)?)
            .map(|r| r.surface)
            .map_err(|e| CorpusError::Surface(model.id.clone(), e)),
    }
}

/// Materialises model `id` of `models` and reads it (welded).
fn read_model(repo_root: &Path, models: &[Model], id: &str) -> Result<Surface, CorpusError> {
    let m = models
        .iter()
        .find(|m| m.id == id)
        .ok_or_else(|| CorpusError::UnknownModel(id.to_string()))?;
    load_surface(repo_root, m)
}

/// Materialises a model and reads its surface (welded, as every consumer reads it).
pub fn load_surface(repo_root: &Path, model: &Model) -> Result<Surface, CorpusError> {
    let path = materialize(repo_root, model)?;
    read_surface(&path)
        .map(|r| r.surface)
        .map_err(|e| CorpusError::Surface(model.id.clone(), e))
}
