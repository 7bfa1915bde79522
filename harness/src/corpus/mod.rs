//! The corpus of models (issue "harness", section Corpus): the manifest
//! (`corpus/manifest.toml`), resolving models to checksum-verified files in the
//! git-ignored `corpus/cache/`, generated models, and the `harness corpus` command.
//!
//! Public API for the other harness parts: [`load_manifest`], [`select`],
//! [`materialize`] (a readable surface file per model; fetches nothing), [`Model`].
//!
//! Submodules: [`manifest`] (types, parsing, tiers), [`materialize`] (cache paths,
//! checksums, writing generated models), [`generate`] (our own surfaces and midpoint
//! refinement), [`import`] (a user's own models into the git-ignored
//! `corpus/local.toml`), `cli` (list, check, refine, import).

mod cli;
pub mod generate;
pub mod import;
pub mod manifest;
pub mod materialize;

pub use cli::{check_model, cli, defect_summary, CorpusAction, CorpusArgs};
pub use manifest::{select, Category, Model, Source, Tier, TIER_SELECTIONS};
pub use materialize::{cache_path, load_surface, materialize, sha256_hex};

use std::path::{Path, PathBuf};

/// Why a corpus operation failed. Every variant about one model names it.
#[derive(Debug, thiserror::Error)]
pub enum CorpusError {
    /// The manifest is unreadable or invalid.
    #[error("{path}: {msg}")]
    Manifest {
        /// The manifest file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
    /// A Debian-sourced file is not in the cache.
    #[error("model {model}: {path} is missing: run scripts/fetch-corpus.sh")]
    Missing {
        /// Model id.
        model: String,
        /// Expected path.
        path: PathBuf,
    },
    /// A file's checksum differs from the manifest's.
    #[error("model {model}: checksum mismatch for {path}: manifest {expected}, file {actual}")]
    Checksum {
        /// Model id.
        model: String,
        /// The file.
        path: PathBuf,
        /// From the manifest.
        expected: String,
        /// Of the file.
        actual: String,
    },
    /// No model (or generator) of that name.
    #[error("unknown model {0:?}")]
    UnknownModel(String),
    /// The model's file could not be read as a surface.
    #[error("model {0}: {1}")]
    Surface(String, #[source] mesher::io::IoError),
    /// File system error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
}

/// Result of corpus operations.
pub type Result<T, E = CorpusError> = std::result::Result<T, E>;

/// The manifest path of a repository.
pub fn manifest_path(repo_root: &Path) -> PathBuf {
    repo_root.join("corpus").join("manifest.toml")
}

/// Reads and validates `corpus/manifest.toml` under `repo_root`, plus the user's
/// `corpus/local.toml` when there is one ([`import`]); ids must be unique across both.
pub fn load_manifest(repo_root: &Path) -> Result<Vec<Model>> {
    let mut models = load_shared_manifest(repo_root)?;
    let local_path = import::local_manifest_path(repo_root);
    for m in import::load_local(&local_path)? {
        if models.iter().any(|s| s.id == m.id) {
            return Err(CorpusError::Manifest {
                path: local_path,
                msg: format!("model id {:?} is also in corpus/manifest.toml", m.id),
            });
        }
        models.push(m);
    }
    Ok(models)
}

/// Reads and validates `corpus/manifest.toml` alone (the committed corpus).
pub fn load_shared_manifest(repo_root: &Path) -> Result<Vec<Model>> {
    let path = manifest_path(repo_root);
    let text = std::fs::read_to_string(&path).map_err(|e| CorpusError::Io {
        path: path.clone(),
        source: e,
    })?;
    manifest::parse_manifest(&path, &text)
}

/// The repository root: the first ancestor of the working directory holding
/// `corpus/manifest.toml`, else the source tree this binary was built from.
pub fn find_repo_root() -> PathBuf {
    if let Ok(cwd) = std::env::current_dir() {
        if let Some(root) = cwd.ancestors().find(|d| manifest_path(d).is_file()) {
            return root.to_path_buf();
        }
    }
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap_or(Path::new("."))
        .to_path_buf()
}
