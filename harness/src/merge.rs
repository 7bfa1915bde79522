//! `harness merge DIR... --out DIR`: the shards of one run (`harness run --shard K/N`)
//! combined into one run directory, as if the run had not been sharded: the same records
//! in the same order (models, then meshers, in the whole run's order from `run.json`).
//!
//! It refuses shards that do not belong together: a different harness version, git
//! revision, corpus checksum, model list, mesher list or shard count; a shard given
//! twice or missing; a (model, mesher) pair recorded twice; or one mesher reporting two
//! versions across the shards. The report then reads the merged directory as usual.

use crate::records::{self, Record};
use crate::shard::{RunMeta, META_NAME};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Why shards cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A shard's `run.json` disagrees with the first shard's.
    #[error("{dir}: {what} differs from {first}'s ({theirs:?} vs {ours:?})")]
    Mismatch {
        /// The shard that disagrees.
        dir: PathBuf,
        /// The first shard.
        first: PathBuf,
        /// Which field.
        what: &'static str,
        /// Its value there.
        theirs: String,
        /// The first shard's value.
        ours: String,
    },
    /// The set of shards is not one whole run.
    #[error("shards: {0}")]
    Shards(String),
    /// A pair recorded by two shards.
    #[error("{model} / {mesher} is recorded twice ({dir})")]
    Duplicate {
        /// Model id.
        model: String,
        /// Runner id.
        mesher: String,
        /// The second shard holding it.
        dir: PathBuf,
    },
    /// A mesher with different versions across the shards.
    #[error("mesher {mesher} has different versions across the shards: {versions:?}")]
    Versions {
        /// Runner id.
        mesher: String,
        /// The versions seen.
        versions: Vec<String>,
    },
}

/// Arguments of `harness merge`.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Shard run directories (each with run.json and results.jsonl).
    #[arg(required = true, num_args = 1..)]
    pub dirs: Vec<PathBuf>,
    /// The merged run directory.
    #[arg(long)]
    pub out: PathBuf,
    /// Merge even when some shards of the run are absent.
    #[arg(long)]
    pub partial: bool,
}

fn read_meta(dir: &Path) -> Result<RunMeta, MergeError> {
    RunMeta::read(dir).map_err(|source| MergeError::Io {
        path: dir.join(META_NAME),
        source,
    })
}

/// Every shard's metadata agrees with the first's on what identifies the run.
fn check_metas(dirs: &[PathBuf], metas: &[RunMeta], partial: bool) -> Result<(), MergeError> {
    let first = &metas[0];
    type Field = fn(&RunMeta) -> String;
    let fields: [(&'static str, Field); 6] = [
        ("harness version", |m| m.harness_version.clone()),
        ("git revision", |m| m.git_revision.clone()),
        ("corpus checksum", |m| m.corpus_checksum.clone()),
        ("model list", |m| m.models.join(",")),
        ("mesher list", |m| m.meshers.join(",")),
        ("shard count", |m| {
            m.shard().map_or("none".into(), |s| s.count.to_string())
        }),
    ];
    for (dir, meta) in dirs.iter().zip(metas).skip(1) {
        for (what, f) in &fields {
            if f(meta) != f(first) {
                return Err(MergeError::Mismatch {
                    dir: dir.clone(),
                    first: dirs[0].clone(),
                    what,
                    theirs: f(meta),
                    ours: f(first),
                });
            }
        }
    }
    let shards: Vec<_> = metas.iter().filter_map(RunMeta::shard).collect();
    if shards.len() != metas.len() {
        return Err(MergeError::Shards(
            "every directory must be a shard (run.json \"shard\": \"K/N\")".into(),
        ));
    }
    let indices: BTreeSet<usize> = shards.iter().map(|s| s.index).collect();
    if indices.len() != shards.len() {
        return Err(MergeError::Shards("a shard is given twice".into()));
    }
    let count = shards[0].count;
    if !partial && indices.len() != count {
        let missing: Vec<String> = (1..=count)
            .filter(|k| !indices.contains(k))
            .map(|k| format!("{k}/{count}"))
            .collect();
        return Err(MergeError::Shards(format!(
            "missing {} (or pass --partial)",
            missing.join(", ")
        )));
    }
    Ok(())
}

/// One version per mesher across all records (empty versions, e.g. missing peers, aside).
fn check_versions(records: &[Record]) -> Result<(), MergeError> {
    let mut seen: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for r in records.iter().filter(|r| !r.mesher_version.is_empty()) {
        seen.entry(&r.mesher).or_default().insert(&r.mesher_version);
    }
    match seen.into_iter().find(|(_, v)| v.len() > 1) {
        Some((mesher, versions)) => Err(MergeError::Versions {
            mesher: mesher.into(),
            versions: versions.into_iter().map(String::from).collect(),
        }),
        None => Ok(()),
    }
}

/// Merges the shard directories into `out`; returns the number of records.
pub fn merge(dirs: &[PathBuf], out: &Path, partial: bool) -> Result<usize, MergeError> {
    let metas: Vec<RunMeta> = dirs
        .iter()
        .map(|d| read_meta(d))
        .collect::<Result<_, _>>()?;
    check_metas(dirs, &metas, partial)?;
    let mut all: Vec<Record> = Vec::new();
    let mut keys = BTreeSet::new();
    for dir in dirs {
        let path = dir.join("results.jsonl");
        let rows = records::read_jsonl(&path).map_err(|source| MergeError::Io { path, source })?;
        for r in rows {
            if !keys.insert((r.model.clone(), r.mesher.clone())) {
                let (model, mesher) = (r.model, r.mesher);
                return Err(MergeError::Duplicate {
                    model,
                    mesher,
                    dir: dir.clone(),
                });
            }
            all.push(r);
        }
    }
    check_versions(&all)?;
    let meta = &metas[0];
    let rank = |list: &[String], id: &str| list.iter().position(|x| x == id).unwrap_or(usize::MAX);
    all.sort_by_key(|r| (rank(&meta.models, &r.model), rank(&meta.meshers, &r.mesher)));
    let io = |source| MergeError::Io {
        path: out.to_path_buf(),
        source,
    };
    std::fs::create_dir_all(out).map_err(io)?;
    records::write_all(out, &all).map_err(io)?;
    let merged = RunMeta {
        shard: None,
        merged_from: dirs.to_vec(),
        ..meta.clone()
    };
    merged.write(out).map_err(io)?;
    Ok(all.len())
}

/// `harness merge`.
pub fn cli(args: MergeArgs) -> anyhow::Result<ExitCode> {
    let n = merge(&args.dirs, &args.out, args.partial)?;
    eprintln!(
        "harness merge: {n} records from {} shards into {}",
        args.dirs.len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
