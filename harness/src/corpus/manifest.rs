//! The corpus manifest (`corpus/manifest.toml`): one `[[model]]` table per model, parsed
//! into [`Model`]s, plus tier selection.

use super::CorpusError;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// The tier of a model: which runs include it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tier {
    /// Clean, under ~15k triangles: runs in CI.
    Ci,
    /// Clean, up to ~100k triangles.
    Nightly,
    /// Refined models, 300k-1M triangles.
    Large,
    /// Defective inputs: a mesher should refuse them.
    Dirty,
    /// A user's clean model from `corpus/local.toml` (`harness corpus import`).
    Local,
}

/// What a model exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Category {
    /// Convex solid.
    Convex,
    /// Mechanical part: sharp edges, flat faces, coarse triangles.
    Cad,
    /// Scanned or sculpted smooth shape.
    Organic,
    /// Genus 1 or more (handles).
    HighGenus,
    /// A thin feature relative to its extent.
    Thin,
    /// Several shells (bodies, or nested shells as holes).
    MultiShell,
    /// Open surface (boundary edges).
    Open,
    /// Edges with more than two faces.
    NonManifold,
    /// Faces crossing other faces.
    SelfIntersecting,
    /// Not a readable surface: an empty file, non-finite coordinates.
    Unreadable,
    /// A user's model (`harness corpus import`), not classified further.
    User,
}

/// Where a model's surface comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// `cgal:PATH`: under `corpus/cache/cgal/` (package libcgal-demo).
    Cgal(String),
    /// `netgen:FILE`: under `corpus/cache/netgen/` (package netgen-doc).
    Netgen(String),
    /// `gmsh:FILE`: under `corpus/cache/gmsh/` (package gmsh-doc).
    Gmsh(String),
    /// `generated:NAME`: one of [`super::generate::NAMES`].
    Generated(String),
    /// `combine:A+~B+...`: the union of other models' surfaces; `~` reverses a part's
    /// orientation (an inner shell bounding a hole).
    Combine(Vec<(String, bool)>),
    /// `refine:MODEL@N`: midpoint subdivision of another model to at least N triangles.
    Refine(String, usize),
    /// `file:PATH`: a user's file outside the cache (`corpus/local.toml`), used in place.
    Local(String),
}

impl Source {
    /// Parses `kind:rest`.
    pub fn parse(s: &str) -> Option<Source> {
        let (kind, rest) = s.split_once(':')?;
        if rest.is_empty() {
            return None;
        }
        let rest = rest.to_string();
        Some(match kind {
            "cgal" => Source::Cgal(rest),
            "netgen" => Source::Netgen(rest),
            "gmsh" => Source::Gmsh(rest),
            "file" => Source::Local(rest),
            "generated" => Source::Generated(rest),
            "combine" => Source::Combine(
                rest.split('+')
                    .map(|p| match p.strip_prefix('~') {
                        Some(id) => (id.to_string(), true),
                        None => (p.to_string(), false),
                    })
                    .collect(),
            ),
            "refine" => {
                let (id, n) = rest.split_once('@')?;
                Source::Refine(id.to_string(), n.parse().ok()?)
            }
            _ => return None,
        })
    }

    /// True for files that come from a Debian package (fetched, not built here) or from
    /// the user (`file:`): looked up and verified, never written.
    pub fn is_fetched(&self) -> bool {
        matches!(
            self,
            Source::Cgal(_) | Source::Netgen(_) | Source::Gmsh(_) | Source::Local(_)
        )
    }
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Source::Cgal(p) => write!(f, "cgal:{p}"),
            Source::Netgen(p) => write!(f, "netgen:{p}"),
            Source::Gmsh(p) => write!(f, "gmsh:{p}"),
            Source::Generated(p) => write!(f, "generated:{p}"),
            Source::Combine(parts) => {
                let parts: Vec<String> = parts
                    .iter()
                    .map(|(id, rev)| format!("{}{id}", if *rev { "~" } else { "" }))
                    .collect();
                write!(f, "combine:{}", parts.join("+"))
            }
            Source::Refine(id, n) => write!(f, "refine:{id}@{n}"),
            Source::Local(p) => write!(f, "file:{p}"),
        }
    }
}

impl fmt::Display for Tier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Tier::Ci => "ci",
            Tier::Nightly => "nightly",
            Tier::Large => "large",
            Tier::Dirty => "dirty",
            Tier::Local => "local",
        })
    }
}

impl fmt::Display for Category {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Category::Convex => "convex",
            Category::Cad => "cad",
            Category::Organic => "organic",
            Category::HighGenus => "high-genus",
            Category::Thin => "thin",
            Category::MultiShell => "multi-shell",
            Category::Open => "open",
            Category::NonManifold => "non-manifold",
            Category::SelfIntersecting => "self-intersecting",
            Category::Unreadable => "unreadable",
            Category::User => "user",
        })
    }
}

/// One corpus model.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// Unique id (used in records, file names, `combine:`/`refine:` sources).
    pub id: String,
    /// Where the surface comes from.
    pub source: Source,
    /// SHA-256 (hex) of the file as extracted or generated.
    pub sha256: String,
    /// Triangles after reading (welded), as the manifest declares.
    pub triangles: usize,
    /// Tier.
    pub tier: Tier,
    /// Category.
    pub category: Category,
    /// Licence and attribution.
    pub licence: String,
    /// Free remark (what the model exercises, known defects).
    pub note: String,
}

impl Model {
    /// True when `check()` must find no defect (every tier but dirty).
    pub fn expect_clean(&self) -> bool {
        self.tier != Tier::Dirty
    }
}

/// The manifest as written.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawManifest {
    model: Vec<RawModel>,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawModel {
    id: String,
    source: String,
    sha256: String,
    triangles: usize,
    tier: Tier,
    category: Category,
    licence: String,
    #[serde(default)]
    note: String,
}

/// Manifest text for `models` (the format [`parse_manifest`] reads).
pub fn to_manifest_text(models: &[Model]) -> Result<String, toml::ser::Error> {
    let raw = RawManifest {
        model: models
            .iter()
            .map(|m| RawModel {
                id: m.id.clone(),
                source: m.source.to_string(),
                sha256: m.sha256.clone(),
                triangles: m.triangles,
                tier: m.tier,
                category: m.category,
                licence: m.licence.clone(),
                note: m.note.clone(),
            })
            .collect(),
    };
    toml::to_string(&raw)
}

/// Parses manifest text; `path` names it in errors. Ids must be unique, sources valid,
/// checksums 64 hex digits, and `combine:`/`refine:` must name other models.
pub fn parse_manifest(path: &Path, text: &str) -> Result<Vec<Model>, CorpusError> {
    let bad = |msg: String| CorpusError::Manifest {
        path: path.to_path_buf(),
        msg,
    };
    let raw: RawManifest = toml::from_str(text).map_err(|e| bad(e.to_string()))?;
    let mut models: Vec<Model> = Vec::with_capacity(raw.model.len());
    for r in raw.model {
        let source = Source::parse(&r.source)
            .ok_or_else(|| bad(format!("model {}: bad source {:?}", r.id, r.source)))?;
        if r.sha256.len() != 64 || !r.sha256.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(bad(format!("model {}: sha256 is not 64 hex digits", r.id)));
        }
        if models.iter().any(|m| m.id == r.id) {
            return Err(bad(format!("duplicate model id {:?}", r.id)));
        }
        models.push(Model {
            id: r.id,
            source,
            sha256: r.sha256.to_ascii_lowercase(),
            triangles: r.triangles,
            tier: r.tier,
            category: r.category,
            licence: r.licence,
            note: r.note,
        });
    }
    check_references(&models).map_err(bad)?;
    Ok(models)
}

/// Every `combine:`/`refine:` part names a model that is itself fetched or generated.
fn check_references(models: &[Model]) -> Result<(), String> {
    let base = |id: &str| {
        models
            .iter()
            .any(|m| m.id == id && !matches!(m.source, Source::Combine(_) | Source::Refine(..)))
    };
    for m in models {
        let parts: Vec<&str> = match &m.source {
            Source::Combine(p) => p.iter().map(|(id, _)| id.as_str()).collect(),
            Source::Refine(id, _) => vec![id.as_str()],
            Source::Generated(name) if !super::generate::NAMES.contains(&name.as_str()) => {
                return Err(format!("model {}: unknown generator {name:?}", m.id));
            }
            _ => continue,
        };
        if let Some(p) = parts.iter().find(|p| !base(p)) {
            return Err(format!(
                "model {}: part {p:?} is not a fetched or generated model",
                m.id
            ));
        }
    }
    Ok(())
}

/// The tier names accepted by [`select`].
pub const TIER_SELECTIONS: &[&str] = &["ci", "nightly", "large", "dirty", "local", "all"];

/// The models of a tier selection: `ci`, `nightly` (ci + nightly), `large`, `dirty`,
/// `local` (a user's clean models, `corpus/local.toml`), `all`; an unknown name selects
/// nothing.
pub fn select<'a>(models: &'a [Model], tier: &str) -> Vec<&'a Model> {
    models
        .iter()
        .filter(|m| match tier {
            "ci" => m.tier == Tier::Ci,
            "nightly" => matches!(m.tier, Tier::Ci | Tier::Nightly),
            "large" => m.tier == Tier::Large,
            "dirty" => m.tier == Tier::Dirty,
            "local" => m.tier == Tier::Local,
            "all" => true,
            _ => false,
        })
        .collect()
}
