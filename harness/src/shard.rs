//! Sharding a run (issue 7): `harness run --shard K/N` runs a deterministic 1/N slice of
//! the models, and every run directory carries a `run.json` ([`RunMeta`]) naming what
//! identifies it (harness version, git revision, the corpus checksum, the models and
//! meshers of the whole run, the shard), so that `harness merge` ([`crate::merge`]) can
//! refuse shards that do not belong together.
//!
//! The slice: models are taken largest first (input triangles, the cost that dominates
//! a run), ties broken by a SHA-256 of the model id (stable across machines and Rust
//! versions, unlike `std`'s hasher), and each goes to the shard with the least total
//! triangles so far (longest-processing-time greedy, lowest shard on ties). Every shard
//! computes the same assignment from the same model list, so the N slices are disjoint
//! and cover the run.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Shard `index` (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1..=count.
    pub index: usize,
    /// Number of shards, >= 1.
    pub count: usize,
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("shard {s:?}: expected K/N with 1 <= K <= N");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The shard (0-based) of each item, given `(id, weight)` pairs, for `count` shards.
pub fn assign(items: &[(&str, usize)], count: usize) -> Vec<usize> {
    let count = count.max(1);
    let key = |id: &str| crate::corpus::sha256_hex(id.as_bytes());
    let mut order: Vec<usize> = (0..items.len()).collect();
    order.sort_by_cached_key(|&i| (std::cmp::Reverse(items[i].1), key(items[i].0)));
    let mut load = vec![0usize; count];
    let mut out = vec![0; items.len()];
    for i in order {
        let s = (0..count).min_by_key(|&s| (load[s], s)).unwrap_or(0);
        // Weight 0 still counts, so empty models spread too.
        load[s] += items[i].1.max(1);
        out[i] = s;
    }
    out
}

/// The items of `shard`, in their original order.
pub fn slice<T>(items: Vec<T>, shard: Shard, id_weight: impl Fn(&T) -> (&str, usize)) -> Vec<T> {
    let pairs: Vec<(&str, usize)> = items.iter().map(&id_weight).collect();
    let owner = assign(&pairs, shard.count);
    items
        .into_iter()
        .zip(owner)
        .filter(|(_, s)| *s + 1 == shard.index)
        .map(|(t, _)| t)
        .collect()
}

/// `run.json`: what identifies a run directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunMeta {
    /// Version of the harness that wrote it.
    pub harness_version: String,
    /// Git revision of this project (`git describe --always --dirty`).
    pub git_revision: String,
    /// The corpus selections (`--corpus`), or `input` for explicit files.
    pub corpus: Vec<String>,
    /// SHA-256 over `id sha256` of every model of the whole run (before sharding).
    pub corpus_checksum: String,
    /// Model ids of the whole run, in run order (before sharding).
    pub models: Vec<String>,
    /// Runner ids, in run order.
    pub meshers: Vec<String>,
    /// `K/N` for a shard, `None` for a whole run.
    pub shard: Option<String>,
    /// The shard directories a merged run came from.
    #[serde(default)]
    pub merged_from: Vec<PathBuf>,
}

/// File name of the metadata in a run directory.
pub const META_NAME: &str = "run.json";

impl RunMeta {
    /// Reads `dir/run.json`.
    pub fn read(dir: &Path) -> std::io::Result<RunMeta> {
        let text = std::fs::read_to_string(dir.join(META_NAME))?;
        serde_json::from_str(&text).map_err(std::io::Error::other)
    }

    /// Writes `dir/run.json` (pretty).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(dir.join(META_NAME), text + "\n")
    }

    /// The shard, if this is one.
    pub fn shard(&self) -> Option<Shard> {
        self.shard.as_deref().and_then(|s| s.parse().ok())
    }
}

/// The corpus checksum of `(id, sha256)` pairs.
pub fn corpus_checksum<'a>(models: impl Iterator<Item = (&'a str, &'a str)>) -> String {
    let text: String = models.map(|(id, sha)| format!("{id} {sha}\n")).collect();
    crate::corpus::sha256_hex(text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_k_of_n() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("3".parse::<Shard>().is_err());
    }

    #[test]
    fn shards_are_disjoint_cover_and_balance() {
        let items: Vec<(String, usize)> = (0..40)
            .map(|i| (format!("model-{i}"), 100 + (i * 37) % 1000))
            .collect();
        let pairs: Vec<(&str, usize)> = items.iter().map(|(s, w)| (s.as_str(), *w)).collect();
        let owner = assign(&pairs, 3);
        assert_eq!(owner, assign(&pairs, 3), "deterministic");
        let mut load = [0usize; 3];
        for (i, s) in owner.iter().enumerate() {
            load[*s] += pairs[i].1;
        }
        let (lo, hi) = (load.iter().min().unwrap(), load.iter().max().unwrap());
        assert!(hi - lo <= 1000, "{load:?}");
        let all: usize = (1..=3)
            .map(|k| slice(pairs.clone(), Shard { index: k, count: 3 }, |p| *p).len())
            .sum();
        assert_eq!(all, 40);
    }
}
