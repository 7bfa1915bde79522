//! `harness run`: every selected model × mesher, measured and recorded.
//!
//! For each model the input surface is read and measured once ([`metrics::measure_input`]);
//! each runner runs in its own work directory `OUT/work/<model>/<mesher>`; its output is
//! read with `mesher::io::read_volume` and measured ([`metrics::measure_output`]). Every
//! run ends in one [`Record`] appended to `OUT/results.jsonl` and `OUT/results.csv`
//! (rewritten atomically after each row). A missing peer, a crash, a timeout or an
//! unreadable output is a row with a status, never an abort. `--resume` skips pairs
//! already recorded. `--shard K/N` runs a deterministic slice of the models
//! ([`crate::shard`]); every run writes `OUT/run.json` ([`RunMeta`]) for `harness merge`.
//!
//! Models come from [`models`]: explicit `--input` files, else the corpus tier through
//! the small adapter `corpus_models` (`harness::corpus`: manifest, selection,
//! materialisation in the cache).

use crate::metrics::{self, InputMeasures};
use crate::records::{self, Record, Status};
use crate::runners::ours::STATS_NAME;
use crate::runners::{registry, RunArgs, RunError, RunOutput, RunRequest, Runner};
use crate::shard::{self, RunMeta};
use anyhow::Context;
use mesher::Surface;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

/// One model to run.
#[derive(Clone, Debug)]
pub struct Model {
    /// Id used in records.
    pub id: String,
    /// Surface file.
    pub path: PathBuf,
    /// Tier (ci, nightly, large, dirty; `adhoc` for `--input` files).
    pub tier: String,
    /// Category (convex, cad, ...; `unknown` for `--input` files).
    pub category: String,
    /// Input triangles (the manifest's count; read from the file for `--input`).
    pub triangles: usize,
    /// Why the model's file could not be provided (rows get a status instead of a run).
    pub error: Option<String>,
    /// SHA-256 of the file (the manifest's for corpus models), for the run's corpus
    /// checksum.
    pub sha256: String,
}

/// The models to run: the `--input` files, else the corpus tier selection, filtered by
/// `--models`.
pub fn models(args: &RunArgs) -> anyhow::Result<Vec<Model>> {
    let mut out: Vec<Model> = if !args.input.is_empty() {
        args.input
            .iter()
            .map(|p| Model {
                id: p
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                path: p.clone(),
                tier: "adhoc".into(),
                category: "unknown".into(),
                triangles: mesher::io::read_surface(p).map_or(0, |r| r.surface.triangles.len()),
                error: None,
                sha256: std::fs::read(p)
                    .map_or_else(|_| String::new(), |b| crate::corpus::sha256_hex(&b)),
            })
            .collect()
    } else {
        let mut all: Vec<Model> = Vec::new();
        for selection in &args.corpus {
            for m in corpus_models(selection)? {
                if !all.iter().any(|a| a.id == m.id) {
                    all.push(m);
                }
            }
        }
        all
    };
    if !args.models.is_empty() {
        out.retain(|m| args.models.contains(&m.id));
    }
    Ok(out)
}

/// Adapter to `harness::corpus`: the models of a tier selection, materialised in the
/// cache (a model that cannot be materialised keeps its error and becomes rows with a
/// status).
fn corpus_models(tier: &str) -> anyhow::Result<Vec<Model>> {
    use crate::corpus;
    let root = corpus::find_repo_root();
    let all = corpus::load_manifest(&root).context("loading the corpus manifest")?;
    let chosen = corpus::manifest::select(&all, tier);
    if chosen.is_empty() {
        anyhow::bail!(
            "corpus selection {tier:?} has no model (known: {:?})",
            corpus::manifest::TIER_SELECTIONS
        );
    }
    Ok(chosen
        .into_iter()
        .map(|m| {
            let (path, error) = match corpus::materialize::materialize(&root, m) {
                Ok(p) => (p, None),
                Err(e) => (PathBuf::new(), Some(e.to_string())),
            };
            Model {
                id: m.id.clone(),
                path,
                tier: kebab(&format!("{:?}", m.tier)),
                category: kebab(&format!("{:?}", m.category)),
                triangles: m.triangles,
                error,
                sha256: m.sha256.clone(),
            }
        })
        .collect())
}

/// `HighGenus` -> `high-genus` (the manifest's spelling of its enum names).
fn kebab(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('-');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

/// The models a slow peer runs on under `--limit-slow N`: the N smallest of each clean
/// tier (by input triangles, then id) and no dirty model (the dirty tier's largest,
/// `man`, would take a slow peer longer than the rest of the run); all of them without
/// a limit.
pub fn slow_models(models: &[Model], limit: Option<usize>) -> HashSet<String> {
    let Some(n) = limit else {
        return models.iter().map(|m| m.id.clone()).collect();
    };
    let mut tiers: Vec<&str> = models
        .iter()
        .map(|m| m.tier.as_str())
        .filter(|t| *t != "dirty")
        .collect();
    tiers.sort_unstable();
    tiers.dedup();
    let mut keep = HashSet::new();
    for tier in tiers {
        let mut of_tier: Vec<&Model> = models.iter().filter(|m| m.tier == tier).collect();
        of_tier.sort_by(|a, b| (a.triangles, &a.id).cmp(&(b.triangles, &b.id)));
        keep.extend(of_tier.into_iter().take(n).map(|m| m.id.clone()));
    }
    keep
}

/// `harness run`.
pub fn cli(args: RunArgs) -> anyhow::Result<ExitCode> {
    execute(&args)?;
    Ok(ExitCode::SUCCESS)
}

/// Runs every selected model × mesher into `args.out` (or a stamped folder under
/// `reports/runs`) and returns that folder (absolute).
pub fn execute(args: &RunArgs) -> anyhow::Result<PathBuf> {
    let all_models = models(args)?;
    let runners = select_runners(&args.meshers)?;
    let out = args.out.clone().unwrap_or_else(default_out_dir);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    // Peers run in their own work directories: every path handed to them is absolute.
    let out = std::path::absolute(&out).with_context(|| format!("resolving {}", out.display()))?;
    let meta = run_meta(args, &all_models, &runners);
    meta.write(&out)
        .with_context(|| format!("writing {}", out.join(shard::META_NAME).display()))?;
    // The slow peers' smallest models are chosen over the whole run, so a shard skips
    // exactly what the unsharded run would.
    let slow_ok = slow_models(&all_models, args.limit_slow);
    let models = match args.shard {
        Some(k) => shard::slice(all_models, k, |m| (m.id.as_str(), m.triangles)),
        None => all_models,
    };
    let mut rows = if args.resume {
        records::read_jsonl(&out.join("results.jsonl")).context("reading results.jsonl")?
    } else {
        Vec::new()
    };
    // A skipped pair is not done: a resumed run with a larger limit runs it.
    rows.retain(|r| r.status != Status::Skipped);
    let done: HashSet<(String, String)> = rows
        .iter()
        .map(|r| (r.model.clone(), r.mesher.clone()))
        .collect();
    let ctx = Context_::new(
        Duration::from_secs_f64(args.timeout.max(0.001)),
        args.repeat,
    );
    let mut progress = Progress::new(&models, &runners, &done);
    for model in &models {
        let todo: Vec<&dyn Runner> = runners
            .iter()
            .map(|r| r.as_ref())
            .filter(|r| !done.contains(&(model.id.clone(), r.info().id.to_string())))
            .collect();
        if todo.is_empty() {
            continue;
        }
        progress.start_model(&model.id);
        let prepared = prepare(model);
        for runner in todo {
            let work = out.join("work").join(&model.id).join(runner.info().id);
            let row = if runner.info().slow && !slow_ok.contains(&model.id) {
                skipped(&ctx, model, runner, args.limit_slow.unwrap_or(0))
            } else {
                run_one(&ctx, model, &prepared, runner, &work)
            };
            eprintln!(
                "{} {:<24} {:<14} {}",
                progress.step(),
                model.id,
                row.mesher,
                summary_line(&row)
            );
            rows.push(row);
            records::write_all(&out, &rows).context("writing results")?;
            if !args.keep_meshes {
                let _ = std::fs::remove_dir_all(&work);
            }
        }
    }
    eprintln!("harness run: {} records in {}", rows.len(), out.display());
    Ok(out)
}

/// Progress of a run on stderr: pairs done / to do, the model being meshed, elapsed time.
struct Progress {
    total: usize,
    done: usize,
    models: usize,
    model: usize,
    start: std::time::Instant,
}

impl Progress {
    fn new(
        models: &[Model],
        runners: &[Box<dyn Runner>],
        done: &HashSet<(String, String)>,
    ) -> Progress {
        let total = models
            .iter()
            .flat_map(|m| {
                runners
                    .iter()
                    .map(move |r| (m.id.clone(), r.info().id.to_string()))
            })
            .filter(|pair| !done.contains(pair))
            .count();
        if !done.is_empty() {
            eprintln!(
                "harness run: resuming, {} pairs already recorded, {total} to do",
                done.len()
            );
        }
        Progress {
            total,
            done: 0,
            models: models.len(),
            model: 0,
            start: std::time::Instant::now(),
        }
    }

    fn start_model(&mut self, id: &str) {
        self.model += 1;
        let (m, n, t) = (self.model, self.models, self.elapsed());
        eprintln!("harness run: model {m}/{n} {id} (elapsed {t})");
    }

    /// `[done/total elapsed]` after one more pair.
    fn step(&mut self) -> String {
        self.done += 1;
        format!("[{}/{} {}]", self.done, self.total, self.elapsed())
    }

    fn elapsed(&self) -> String {
        let s = self.start.elapsed().as_secs();
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    }
}

/// What identifies this run (`run.json`): computed over the whole run, before sharding.
fn run_meta(args: &RunArgs, models: &[Model], runners: &[Box<dyn Runner>]) -> RunMeta {
    RunMeta {
        harness_version: env!("CARGO_PKG_VERSION").into(),
        git_revision: git_revision(),
        corpus: if args.input.is_empty() {
            args.corpus.clone()
        } else {
            vec!["input".into()]
        },
        corpus_checksum: shard::corpus_checksum(
            models.iter().map(|m| (m.id.as_str(), m.sha256.as_str())),
        ),
        models: models.iter().map(|m| m.id.clone()).collect(),
        meshers: runners.iter().map(|r| r.info().id.to_string()).collect(),
        shard: args.shard.map(|k| k.to_string()),
        merged_from: Vec::new(),
    }
}

/// The row of a slow peer left out by `--limit-slow`.
fn skipped(ctx: &Context_, model: &Model, runner: &dyn Runner, limit: usize) -> Record {
    let mut rec = blank_record(ctx, model, &runner.info());
    rec.input_faces = model.triangles;
    let why = format!(
        "slow peer: --limit-slow {limit} runs it on the {limit} smallest models of each clean tier only"
    );
    finish(rec, Status::Skipped, Some(why))
}

fn select_runners(ids: &[String]) -> anyhow::Result<Vec<Box<dyn Runner>>> {
    let all = registry();
    if ids.is_empty() {
        return Ok(all);
    }
    let known: Vec<&str> = all.iter().map(|r| r.info().id).collect();
    if let Some(bad) = ids.iter().find(|id| !known.contains(&id.as_str())) {
        anyhow::bail!("unknown mesher {bad:?}; known: {}", known.join(", "));
    }
    Ok(all
        .into_iter()
        .filter(|r| ids.iter().any(|id| id == r.info().id))
        .collect())
}

/// Run-wide facts put in every record.
struct Context_ {
    timeout: Duration,
    /// Runs in all of a quick (model, mesher), the fastest kept (`--repeat`).
    repeat: usize,
    git_revision: String,
    machine: String,
}

impl Context_ {
    fn new(timeout: Duration, repeat: usize) -> Context_ {
        Context_ {
            timeout,
            repeat: repeat.max(1),
            git_revision: git_revision(),
            machine: machine(),
        }
    }
}

/// A model's input, read and measured once for all runners.
type Prepared = Result<(PathBuf, Surface, InputMeasures, f64), NotPrepared>;

/// Why a model's input could not be prepared.
enum NotPrepared {
    /// The file is there but our reader refuses it (an empty file, a NaN coordinate):
    /// ours still gets it, and must refuse it naming the defect; the peers' runners
    /// convert their input with our reader, so they cannot be run on it.
    Unreadable(String),
    /// Anything else (a model error, a missing file).
    Failed(String),
}

fn prepare(model: &Model) -> Prepared {
    if let Some(e) = &model.error {
        return Err(NotPrepared::Failed(e.clone()));
    }
    let path = std::fs::canonicalize(&model.path)
        .map_err(|e| NotPrepared::Failed(format!("{}: {e}", model.path.display())))?;
    let surface = mesher::io::read_surface(&path)
        .map_err(|e| NotPrepared::Unreadable(format!("unreadable input: {e}")))?
        .surface;
    let measures = metrics::measure_input(&surface);
    let h = crate::runners::input::mean_edge_length(&surface);
    Ok((path, surface, measures, h))
}

/// The input measures of a file our reader refuses: nothing to measure (its records
/// carry no Q_t).
fn unmeasured_input() -> InputMeasures {
    InputMeasures {
        q_t: f64::NAN,
        hard_face_fraction: f64::NAN,
        q_t_domain: None,
        hard_domain_fraction: None,
        enclosed_volume: None,
        sizes: Vec::new(),
        background: None,
    }
}

fn run_one(
    ctx: &Context_,
    model: &Model,
    prepared: &Prepared,
    runner: &dyn Runner,
    work: &Path,
) -> Record {
    let info = runner.info();
    let mut rec = blank_record(ctx, model, &info);
    let unreadable;
    let (path, surface, input, h) = match prepared {
        Ok((p, s, i, h)) => {
            rec.q_t = Some(i.q_t);
            rec.hard_face_fraction = Some(i.hard_face_fraction);
            rec.q_t_domain = i.q_t_domain;
            rec.hard_domain_fraction = i.hard_domain_fraction;
            (p, s, i, h)
        }
        Err(NotPrepared::Unreadable(_)) if info.id.starts_with("ours") => {
            unreadable = (model.path.clone(), Surface::default(), unmeasured_input());
            (&unreadable.0, &unreadable.1, &unreadable.2, &1.0)
        }
        Err(NotPrepared::Unreadable(e)) => {
            let why = format!("not run: the peer's input is converted by our reader ({e})");
            return finish(rec, Status::Skipped, Some(why));
        }
        Err(NotPrepared::Failed(e)) => {
            return finish(rec, Status::InvalidOutput, Some(format!("input: {e}")))
        }
    };
    rec.input_vertices = surface.vertices.len();
    rec.input_faces = surface.triangles.len();
    rec.edge_length = Some(*h);
    let _ = std::fs::remove_dir_all(work);
    if let Err(e) = std::fs::create_dir_all(work) {
        return finish(
            rec,
            Status::Failed,
            Some(format!("{}: {e}", work.display())),
        );
    }
    let req = RunRequest {
        model: &model.id,
        input: path,
        workdir: work,
        timeout: ctx.timeout,
        edge_length: *h,
    };
    match runner.run(&req) {
        Ok(out) => {
            let (out, mesh_seconds) = fastest_of_repeats(ctx.repeat, runner, &req, out);
            let rec = Record {
                mesh_seconds,
                ..rec
            };
            measure(rec, &out, surface, input, info.keeps_boundary, work)
        }
        Err(RunError::Missing(m)) => finish(rec, Status::Missing, Some(m)),
        Err(RunError::Io(m)) => finish(rec, Status::InvalidOutput, Some(m)),
        Err(RunError::Failed { message, stats }) => {
            set_stats(&mut rec, &stats);
            if let Some(reason) = refusal(info.id, &stats) {
                return finish(rec, Status::Refused, Some(reason));
            }
            let status = if stats.timed_out {
                Status::Timeout
            } else if stats.signal.is_some() {
                Status::Crashed
            } else {
                Status::Failed
            };
            finish(rec, status, Some(message))
        }
    }
}

/// Runs longer than this are not repeated (`--repeat`): their noise is a small part.
const REPEAT_UNDER_SECONDS: f64 = 10.0;

/// `first` and up to `repeat - 1` more runs of a quick (model, mesher): the output of
/// the last successful run with the process measures of the fastest, and the smallest
/// meshing time the mesher reported (see [`mesh_seconds`]). A repeat
/// that fails is ignored (the first run succeeded).
fn fastest_of_repeats(
    repeat: usize,
    runner: &dyn Runner,
    req: &RunRequest<'_>,
    first: RunOutput,
) -> (RunOutput, Option<f64>) {
    let mut mesh = mesh_seconds(req.workdir);
    let mut best = first;
    for _ in 1..repeat {
        if best.stats.wall_seconds > REPEAT_UNDER_SECONDS {
            break;
        }
        if let Ok(out) = runner.run(req) {
            let stats = if out.stats.wall_seconds < best.stats.wall_seconds {
                out.stats.clone()
            } else {
                best.stats.clone()
            };
            best = RunOutput { stats, ..out };
            mesh = match (mesh, mesh_seconds(req.workdir)) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
    }
    (best, mesh)
}

/// The meshing call's own time: what the Python drivers write to `meta.json`
/// (`mesh_seconds`), or for our mesher the library call's time in its statistics
/// (`time_total`: without reading the surface and writing the mesh, like the drivers').
fn mesh_seconds(work: &Path) -> Option<f64> {
    std::fs::read_to_string(work.join("meta.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|m| m["mesh_seconds"].as_f64())
        .or_else(|| records::MesherStats::read(&work.join(STATS_NAME))?.time_total)
}

fn measure(
    mut rec: Record,
    out: &RunOutput,
    surface: &Surface,
    input: &InputMeasures,
    keeps: bool,
    work: &Path,
) -> Record {
    rec.mesher_version = out.version.clone();
    set_stats(&mut rec, &out.stats);
    // Ours writes its front statistics and phase times there (`mesher mesh --stats`).
    let stats = records::MesherStats::read(&work.join(crate::runners::ours::STATS_NAME));
    rec.optimize_share = stats
        .as_ref()
        .and_then(records::MesherStats::optimize_share);
    rec.front = stats.and_then(records::MesherStats::into_front);
    rec.iterations = rec.front.as_ref().map(Vec::len);
    let mesh = match mesher::io::read_volume(&out.mesh) {
        Ok(m) => m,
        Err(e) => {
            return finish(
                rec,
                Status::InvalidOutput,
                Some(format!("reading the output: {e}")),
            )
        }
    };
    if mesh.tets.is_empty() {
        // A peer that gives up on an open surface may still exit 0 with an empty file.
        return finish(
            rec,
            Status::InvalidOutput,
            Some("the output has no tetrahedra".into()),
        );
    }
    let moved_boundary = (!keeps).then(|| metrics::boundary_surface(&mesh));
    match metrics::measure_output(input, surface, mesh, keeps) {
        Ok(mut m) => {
            if let Some(b) = moved_boundary {
                m.validity.hausdorff = relative_hausdorff(work, surface, &b);
            }
            rec.vertices = Some(m.vertices);
            rec.tets = Some(m.tets);
            rec.quality = Some(m.quality);
            rec.edge_lengths = Some(m.edge_lengths);
            rec.edge_band = Some(m.edge_band);
            rec.validity = Some(m.validity);
            rec.orientation_flipped = Some(m.orientation_flipped);
            finish(rec, Status::Ok, None)
        }
        Err(e) => finish(rec, Status::InvalidOutput, Some(e)),
    }
}

/// Two-sided Hausdorff distance between the input and an output boundary, relative to
/// the input's bounding-box diagonal, through `scripts/surface_check.py` (pymeshlab);
/// `None` when pymeshlab is unavailable or fails.
fn relative_hausdorff(work: &Path, input: &Surface, boundary: &Surface) -> Option<f64> {
    let (a, b) = (
        work.join("hausdorff_input.off"),
        work.join("hausdorff_output.off"),
    );
    mesher::io::write_surface(&a, input).ok()?;
    mesher::io::write_surface(&b, boundary).ok()?;
    let python = crate::runners::venv_python();
    let script = crate::runners::project_root().join("scripts/surface_check.py");
    let mut cmd = std::process::Command::new(python);
    // The child runs in `work`: name the files relative to it.
    cmd.arg(script).args([
        "--input",
        "hausdorff_input.off",
        "--output",
        "hausdorff_output.off",
    ]);
    let stats =
        crate::runners::process::run_measured(cmd, work, "surface_check", Duration::from_secs(600))
            .ok()?;
    if stats.exit_code != Some(0) {
        return None;
    }
    let text = std::fs::read_to_string(work.join("surface_check.stdout")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v["relative"].as_f64()
}

fn set_stats(rec: &mut Record, s: &crate::runners::ProcessStats) {
    rec.wall_seconds = Some(s.wall_seconds);
    rec.cpu_seconds = Some(s.cpu_seconds);
    rec.peak_rss_bytes = Some(s.peak_rss_bytes);
    rec.exit_code = s.exit_code;
    rec.signal = s.signal;
}

fn blank_record(ctx: &Context_, model: &Model, info: &crate::runners::PeerInfo) -> Record {
    Record {
        model: model.id.clone(),
        tier: model.tier.clone(),
        category: model.category.clone(),
        mesher: info.id.to_string(),
        mesher_version: String::new(),
        keeps_boundary: info.keeps_boundary,
        status: Status::Ok,
        message: None,
        input_vertices: 0,
        input_faces: 0,
        q_t: None,
        hard_face_fraction: None,
        q_t_domain: None,
        hard_domain_fraction: None,
        vertices: None,
        tets: None,
        wall_seconds: None,
        cpu_seconds: None,
        peak_rss_bytes: None,
        quality: None,
        edge_lengths: None,
        edge_band: None,
        validity: None,
        iterations: None,
        git_revision: ctx.git_revision.clone(),
        machine: ctx.machine.clone(),
        finished_at: String::new(),
        orientation_flipped: None,
        exit_code: None,
        signal: None,
        mesh_seconds: None,
        edge_length: None,
        configuration: Some(info.configuration.clone()),
        front: None,
        optimize_share: None,
    }
}

/// The reason when our mesher refused the input: `mesher mesh` and `mesher boundary`
/// exit 1 with `mesher: refused: FILE: REASON` (or, for `boundary`, `mesher: FILE:
/// REASON`) on stderr for unreadable, defective or degenerate input, as opposed to a
/// failure (exit 2), a crash (signal) or a timeout. Peers have no such convention.
fn refusal(runner: &str, stats: &crate::runners::ProcessStats) -> Option<String> {
    if !runner.starts_with("ours") || stats.timed_out || stats.exit_code != Some(1) {
        return None;
    }
    let lines: Vec<&str> = stats.stderr_tail.trim().lines().map(str::trim).collect();
    let from = lines
        .iter()
        .rposition(|l| l.starts_with("mesher: "))
        .unwrap_or(0);
    let reason = lines[from..]
        .iter()
        .filter(|l| !l.is_empty())
        .copied()
        .collect::<Vec<_>>()
        .join("; ");
    let reason = reason.strip_prefix("mesher: ").unwrap_or(&reason);
    let reason = reason.strip_prefix("refused: ").unwrap_or(reason);
    Some(format!("refused: {reason}"))
}

fn finish(mut rec: Record, status: Status, message: Option<String>) -> Record {
    rec.status = status;
    rec.message = message;
    rec.finished_at = rfc3339_now();
    rec
}

fn summary_line(r: &Record) -> String {
    match (&r.quality, r.wall_seconds) {
        (Some(q), Some(w)) if r.status == Status::Ok => format!(
            "ok  {} tets  {:.2} s  worst Q_K {:.3}  {:.1} % Q_K<3",
            q.count, w, q.worst_q_k, q.well_shaped_percent
        ),
        _ => format!(
            "{:?}: {}",
            r.status,
            r.message
                .as_deref()
                .unwrap_or("")
                .lines()
                .next()
                .unwrap_or("")
        ),
    }
}

fn default_out_dir() -> PathBuf {
    let stamp: String = rfc3339_now()
        .chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .collect();
    PathBuf::from("reports/runs").join(stamp)
}

fn git_revision() -> String {
    let out = std::process::Command::new("git")
        .args(["describe", "--always", "--dirty"])
        .current_dir(crate::runners::project_root())
        .output();
    match out {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).trim().to_string(),
        _ => "unknown".into(),
    }
}

fn machine() -> String {
    let cpus = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(0);
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown cpu".into());
    format!("{cpus} cpus, {model}")
}

/// Current UTC time as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn rfc3339_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::{fastest_of_repeats, mesh_seconds, refusal};
    use crate::runners::{PeerInfo, ProcessStats, RunError, RunOutput, RunRequest, Runner};
    use std::cell::Cell;
    use std::path::{Path, PathBuf};
    use std::time::Duration;

    /// A runner whose successive runs take the given wall times (`None`: it fails).
    struct Timed {
        walls: Vec<Option<f64>>,
        next: Cell<usize>,
    }

    impl Runner for Timed {
        fn info(&self) -> PeerInfo {
            PeerInfo {
                id: "timed",
                name: "timed",
                keeps_boundary: true,
                sized: false,
                slow: false,
                configuration: String::new(),
            }
        }

        fn run(&self, _: &RunRequest<'_>) -> Result<RunOutput, RunError> {
            let k = self.next.get();
            self.next.set(k + 1);
            let wall = self.walls[k].ok_or_else(|| RunError::Io("failed".into()))?;
            Ok(RunOutput {
                mesh: PathBuf::from(format!("run{k}")),
                version: String::new(),
                stats: ProcessStats {
                    wall_seconds: wall,
                    ..ProcessStats::default()
                },
            })
        }
    }

    #[test]
    fn repeats_keep_the_fastest_time_and_the_last_output() {
        let runner = Timed {
            walls: vec![Some(0.5), Some(0.3), None, Some(0.4), Some(20.0), Some(0.1)],
            next: Cell::new(0),
        };
        let req = RunRequest {
            model: "m",
            input: Path::new("in.off"),
            workdir: Path::new("/nonexistent"),
            timeout: Duration::from_secs(1),
            edge_length: 1.0,
        };
        let first = runner.run(&req).unwrap();
        let (out, mesh) = fastest_of_repeats(4, &runner, &req, first);
        // Runs 0-3 (run 2 failed): the fastest time, the last good run's mesh.
        assert_eq!(out.stats.wall_seconds, 0.3);
        assert_eq!(out.mesh, PathBuf::from("run3"));
        assert_eq!(mesh, None);
        assert_eq!(runner.next.get(), 4);
        // One run only without --repeat; none after a slow run.
        let slow = Timed {
            walls: vec![Some(20.0), Some(0.1)],
            next: Cell::new(0),
        };
        let first = slow.run(&req).unwrap();
        let (out, _) = fastest_of_repeats(3, &slow, &req, first);
        assert_eq!((out.stats.wall_seconds, slow.next.get()), (20.0, 1));
    }

    #[test]
    fn mesh_seconds_come_from_the_driver_else_from_our_statistics() {
        let dir = std::env::temp_dir().join(format!("harness-mesh-seconds-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(mesh_seconds(&dir), None);
        std::fs::write(dir.join("stats.json"), r#"{"time_total": 1.5, "tets": 9}"#).unwrap();
        assert_eq!(mesh_seconds(&dir), Some(1.5));
        std::fs::write(dir.join("meta.json"), r#"{"mesh_seconds": 0.25}"#).unwrap();
        assert_eq!(mesh_seconds(&dir), Some(0.25));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn our_exit_1_is_a_refusal_with_its_reason() {
        let stats = ProcessStats {
            exit_code: Some(1),
            stderr_tail:
                "mesher: refused: open.off: the surface has 1 defect(s)\n  3 boundary edges\n"
                    .into(),
            ..ProcessStats::default()
        };
        assert_eq!(
            refusal("ours", &stats).as_deref(),
            Some("refused: open.off: the surface has 1 defect(s); 3 boundary edges")
        );
        assert_eq!(refusal("tetgen", &stats), None);
        let failed = ProcessStats {
            exit_code: Some(2),
            ..stats.clone()
        };
        assert_eq!(refusal("ours", &failed), None);
        let timed_out = ProcessStats {
            timed_out: true,
            ..stats
        };
        assert_eq!(refusal("ours", &timed_out), None);
    }
}
