//! `harness corpus list|check|refine`.

use super::generate;
use super::manifest::{select, Category, Model, TIER_SELECTIONS};
use super::materialize::{cache_path, load_surface, off_bytes};
use super::{find_repo_root, load_manifest};
use anyhow::Context;
use mesher::surface::CheckReport;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `harness corpus`.
#[derive(clap::Args, Debug)]
pub struct CorpusArgs {
    /// Repository root (default: the nearest ancestor holding corpus/manifest.toml).
    #[arg(long, global = true)]
    pub root: Option<PathBuf>,
    /// What to do (default: list).
    #[command(subcommand)]
    pub action: Option<CorpusAction>,
}

/// Subcommands of `harness corpus`.
#[derive(clap::Subcommand, Debug)]
pub enum CorpusAction {
    /// Models with tier, category, triangles and whether the file is in the cache.
    List {
        /// Tier selection: ci, nightly (= ci + nightly), large, dirty, all.
        #[arg(long, default_value = "all", value_parser = clap::builder::PossibleValuesParser::new(TIER_SELECTIONS))]
        tier: String,
    },
    /// Checks each model's surface; exit 1 if a clean-tier model has defects, a dirty
    /// one is clean, or a file is missing or fails its checksum.
    Check {
        /// Tier selection: ci, nightly (= ci + nightly), large, dirty, all.
        #[arg(long, default_value = "all", value_parser = clap::builder::PossibleValuesParser::new(TIER_SELECTIONS))]
        tier: String,
        /// Only these model ids (default: every model of the tier).
        models: Vec<String>,
    },
    /// Adds the surface files under DIR to the local manifest (corpus/local.toml,
    /// git-ignored) with checksums and Surface::check() tiers: `local` when clean, `dirty`
    /// otherwise. Run them with `harness run --corpus local`.
    Import {
        /// Directory of surface files (.off, .obj, .stl, .mesh), searched recursively.
        dir: PathBuf,
        /// The local manifest to write (default: corpus/local.toml).
        #[arg(long)]
        manifest: Option<PathBuf>,
    },
    /// Midpoint subdivision (each triangle into 4, planar) until >= N triangles.
    Refine {
        /// Model id, or a surface file.
        model: String,
        /// Minimum number of triangles.
        #[arg(long)]
        triangles: usize,
        /// Output surface file (format from the extension).
        #[arg(short, long)]
        out: PathBuf,
    },
}

/// `harness corpus`.
pub fn cli(args: CorpusArgs) -> anyhow::Result<ExitCode> {
    let root = args.root.unwrap_or_else(find_repo_root);
    let action = args
        .action
        .unwrap_or(CorpusAction::List { tier: "all".into() });
    match action {
        CorpusAction::List { tier } => list(&root, &tier),
        CorpusAction::Check { tier, models } => check(&root, &tier, &models),
        CorpusAction::Refine {
            model,
            triangles,
            out,
        } => refine(&root, &model, triangles, &out),
        CorpusAction::Import { dir, manifest } => {
            let manifest = manifest.unwrap_or_else(|| super::import::local_manifest_path(&root));
            import(&root, &dir, &manifest)
        }
    }
}

fn list(root: &Path, tier: &str) -> anyhow::Result<ExitCode> {
    let models = load_manifest(root)?;
    println!(
        "{:<30} {:<8} {:<18} {:>9}  {:<7} source",
        "id", "tier", "category", "triangles", "cached"
    );
    for m in select(&models, tier) {
        let present = cache_path(root, m).is_file();
        println!(
            "{:<30} {:<8} {:<18} {:>9}  {:<7} {}",
            m.id,
            m.tier.to_string(),
            m.category.to_string(),
            m.triangles,
            if present { "yes" } else { "no" },
            m.source
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn import(root: &Path, dir: &Path, manifest: &Path) -> anyhow::Result<ExitCode> {
    let done = super::import::import(root, dir, manifest)?;
    let mut refused = 0;
    for i in &done {
        match &i.model {
            Ok(m) => println!(
                "{:<30} {:<6} {:>9} tri  {:<40} {}",
                m.id,
                m.tier.to_string(),
                m.triangles,
                i.defects,
                i.path.display()
            ),
            Err(e) => {
                refused += 1;
                println!("{:<30} ERROR {e}", i.path.display());
            }
        }
    }
    eprintln!(
        "harness corpus import: {} model(s) in {}; {refused} file(s) unreadable",
        done.len() - refused,
        manifest.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn check(root: &Path, tier: &str, only: &[String]) -> anyhow::Result<ExitCode> {
    let models = load_manifest(root)?;
    if let Some(id) = only.iter().find(|id| !models.iter().any(|m| &m.id == *id)) {
        anyhow::bail!("unknown model {id:?}");
    }
    let mut failures = 0;
    for m in select(&models, tier) {
        if !only.is_empty() && !only.contains(&m.id) {
            continue;
        }
        match check_model(root, m) {
            Ok((line, ok)) => {
                println!("{line}");
                failures += usize::from(!ok);
            }
            Err(e) => {
                println!("{:<30} {:<8} ERROR {e}", m.id, m.tier.to_string());
                failures += 1;
            }
        }
    }
    if failures > 0 {
        eprintln!("harness corpus check: {failures} model(s) not as the manifest expects");
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

/// One line for a model, and whether it is as expected (clean unless dirty, triangle
/// count as declared).
pub fn check_model(root: &Path, m: &Model) -> super::Result<(String, bool)> {
    let s = match load_surface(root, m) {
        Ok(s) => s,
        // An unreadable model is as expected when the reader refuses it.
        Err(super::CorpusError::Surface(_, e)) if m.category == Category::Unreadable => {
            let line = format!(
                "{:<30} {:<8} unreadable: {e:<60} ok",
                m.id,
                m.tier.to_string()
            );
            return Ok((line, true));
        }
        Err(e) => return Err(e),
    };
    let report = s.check();
    let q_t = mesher::quality::target_quality(&s.vertices, &s.triangles).q_t;
    let count_ok = s.triangles.len() == m.triangles;
    let ok = report.is_clean() == m.expect_clean() && count_ok;
    let genus: Vec<String> = report
        .shells
        .iter()
        .map(|sh| sh.genus.map_or("-".into(), |g| g.to_string()))
        .collect();
    let line = format!(
        "{:<30} {:<8} {:>9} tri  shells {:<2} genus {:<8} Q_t {:<10.4} {:<40} {}",
        m.id,
        m.tier.to_string(),
        s.triangles.len(),
        report.shells.len(),
        genus.join("+"),
        q_t,
        defect_summary(&report),
        match (ok, count_ok) {
            (true, _) => "ok".to_string(),
            (false, false) => format!("UNEXPECTED: manifest says {} triangles", m.triangles),
            (false, true) if m.expect_clean() => "UNEXPECTED: defects".to_string(),
            (false, true) => "UNEXPECTED: clean".to_string(),
        }
    );
    Ok((line, ok))
}

/// "clean" or the defect counts by kind.
pub fn defect_summary(r: &CheckReport) -> String {
    let kinds = [
        ("non-finite", r.non_finite_vertices.len()),
        ("out-of-range", r.out_of_range_faces.len()),
        ("degenerate", r.degenerate_faces.len()),
        ("zero-area", r.zero_area_faces.len()),
        ("duplicate", r.duplicate_faces.len()),
        ("open-edges", r.open_edges.len()),
        ("non-manifold", r.non_manifold_edges.len()),
        ("inconsistent", r.inconsistent_edges.len()),
        ("pinched", r.pinched_vertices.len()),
        ("self-intersections", r.self_intersections.count),
    ];
    let found: Vec<String> = kinds
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(k, n)| format!("{k} {n}"))
        .collect();
    if found.is_empty() {
        "clean".into()
    } else {
        found.join(", ")
    }
}

fn refine(root: &Path, model: &str, triangles: usize, out: &Path) -> anyhow::Result<ExitCode> {
    let surface = if Path::new(model).is_file() {
        mesher::io::read_surface(Path::new(model))?.surface
    } else {
        let models = load_manifest(root)?;
        let m = models
            .iter()
            .find(|m| m.id == model)
            .with_context(|| format!("unknown model {model:?} (and no such file)"))?;
        load_surface(root, m)?
    };
    let before = surface.triangles.len();
    let (refined, levels) = generate::refine(&surface, triangles);
    if out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("off"))
    {
        std::fs::write(out, off_bytes(&refined)).with_context(|| out.display().to_string())?;
    } else {
        mesher::io::write_surface(out, &refined)?;
    }
    println!(
        "{model}: {before} -> {} triangles ({levels} levels), written to {}",
        refined.triangles.len(),
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}
