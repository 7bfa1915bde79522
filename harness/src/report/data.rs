//! Records of one run, read tolerantly and grouped by model and mesher for the tables
//! and plots.

use std::collections::BTreeMap;
use std::path::Path;

use crate::records::{Record, Status};
use crate::report::ReportError;

/// Fraction of input faces that cannot reach `Q_K <= 3` above which a surface is "the
/// limit": no mesher can reach good worst-case quality on it (issue 3, Metrics).
pub const HARD_FACE_LIMIT: f64 = 0.01;

/// Canonical order of the meshers in tables and legends; unknown ids follow, sorted.
const MESHER_ORDER: [&str; 15] = [
    "ours",
    "ours-front",
    "ours-boundary",
    "tetgen-y-boundary",
    "tetgen",
    "tetgen-y",
    "tetgen-y-sized",
    "cgal",
    "cgal-sized",
    "ftetwild",
    "ftetwild-sized",
    "gmsh-hxt",
    "gmsh-hxt-sized",
    "gmsh-delaunay",
    "gmsh-delaunay-sized",
];

/// Records read from `results.jsonl`, and a warning per skipped line.
#[derive(Debug, Default)]
pub struct Loaded {
    /// Records in file order.
    pub records: Vec<Record>,
    /// One warning per line that did not parse.
    pub warnings: Vec<String>,
}

/// Reads `results.jsonl`, skipping blank lines and warning about unparsable ones.
pub fn load_records(path: &Path) -> Result<Loaded, ReportError> {
    let text = std::fs::read_to_string(path).map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut loaded = Loaded::default();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        match serde_json::from_str::<Record>(line) {
            Ok(r) => loaded.records.push(r),
            Err(e) => loaded.warnings.push(format!(
                "{}:{}: skipped, not a record: {e}",
                path.display(),
                i + 1
            )),
        }
    }
    Ok(loaded)
}

/// The kebab-case name of a status, as in the records.
pub fn status_name(s: Status) -> &'static str {
    match s {
        Status::Ok => "ok",
        Status::Missing => "missing",
        Status::Failed => "failed",
        Status::Crashed => "crashed",
        Status::Timeout => "timeout",
        Status::InvalidOutput => "invalid-output",
        Status::Refused => "refused",
        Status::Skipped => "skipped",
    }
}

/// What the report knows about one input model (taken from its records).
#[derive(Debug, Clone)]
pub struct ModelInfo {
    /// Corpus id.
    pub id: String,
    /// Tier and category.
    pub tier: String,
    /// Category (convex, cad, ...).
    pub category: String,
    /// Input surface vertices.
    pub input_vertices: usize,
    /// Input surface triangles.
    pub input_faces: usize,
    /// Target quality of the surface.
    pub q_t: Option<f64>,
    /// Fraction of input faces whose best possible `Q_K` exceeds 3.
    pub hard_face_fraction: Option<f64>,
    /// Target quality with each face's tet kept inside the domain.
    pub q_t_domain: Option<f64>,
    /// Fraction of input faces whose best tet inside the domain has `Q_K` above 3.
    pub hard_domain_fraction: Option<f64>,
}

impl ModelInfo {
    /// True when the surface itself caps the worst-case quality of any mesher.
    pub fn surface_limited(&self) -> bool {
        [self.hard_face_fraction, self.hard_domain_fraction]
            .iter()
            .any(|f| f.is_some_and(|f| f >= HARD_FACE_LIMIT))
    }
}

/// One mesher as the records describe it.
#[derive(Debug, Clone)]
pub struct MesherInfo {
    /// Runner id.
    pub id: String,
    /// False when the peer moves the input boundary (tables mark it with a dagger).
    pub keeps_boundary: bool,
    /// Distinct version strings seen.
    pub versions: Vec<String>,
    /// The configuration as recorded (switches, size policy), if any record has it.
    pub configuration: Option<String>,
}

/// The records of a run grouped by (model, mesher); a later record of the same pair
/// replaces an earlier one (a resumed run).
#[derive(Debug, Clone)]
pub struct RunData {
    /// Models in order of first appearance.
    pub models: Vec<ModelInfo>,
    /// Meshers in canonical order.
    pub meshers: Vec<MesherInfo>,
    cells: BTreeMap<(usize, usize), Record>,
    /// Every record as read (for metadata).
    pub records: Vec<Record>,
}

impl RunData {
    /// Groups `records`.
    pub fn new(records: Vec<Record>) -> RunData {
        let mut models: Vec<ModelInfo> = Vec::new();
        let mut meshers: Vec<MesherInfo> = Vec::new();
        for r in &records {
            merge_model(&mut models, r);
            merge_mesher(&mut meshers, r);
        }
        meshers.sort_by_key(|m| mesher_rank(&m.id));
        let mut cells = BTreeMap::new();
        for r in &records {
            let mi = models.iter().position(|m| m.id == r.model);
            let ki = meshers.iter().position(|m| m.id == r.mesher);
            if let (Some(mi), Some(ki)) = (mi, ki) {
                cells.insert((mi, ki), r.clone());
            }
        }
        RunData {
            models,
            meshers,
            cells,
            records,
        }
    }

    /// The record of model `m` by mesher `k` (indices into `models`, `meshers`).
    pub fn get(&self, m: usize, k: usize) -> Option<&Record> {
        self.cells.get(&(m, k))
    }

    /// The ok records of mesher `k`.
    pub fn ok_records(&self, k: usize) -> impl Iterator<Item = &Record> {
        (0..self.models.len())
            .filter_map(move |m| self.get(m, k))
            .filter(|r| r.status == Status::Ok)
    }

    /// Distinct values of a metadata field over all records, in first-seen order.
    pub fn distinct(&self, field: impl Fn(&Record) -> &str) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for r in &self.records {
            let v = field(r);
            if !v.is_empty() && !out.iter().any(|o| o == v) {
                out.push(v.to_string());
            }
        }
        out
    }
}

fn mesher_rank(id: &str) -> (usize, String) {
    let rank = MESHER_ORDER
        .iter()
        .position(|m| *m == id)
        .unwrap_or(MESHER_ORDER.len());
    (rank, id.to_string())
}

fn merge_model(models: &mut Vec<ModelInfo>, r: &Record) {
    let m = match models.iter_mut().find(|m| m.id == r.model) {
        Some(m) => m,
        None => {
            models.push(ModelInfo {
                id: r.model.clone(),
                tier: r.tier.clone(),
                category: r.category.clone(),
                input_vertices: 0,
                input_faces: 0,
                q_t: None,
                hard_face_fraction: None,
                q_t_domain: None,
                hard_domain_fraction: None,
            });
            models.last_mut().expect("just pushed")
        }
    };
    m.input_vertices = m.input_vertices.max(r.input_vertices);
    m.input_faces = m.input_faces.max(r.input_faces);
    m.q_t = m.q_t.or(r.q_t);
    m.hard_face_fraction = m.hard_face_fraction.or(r.hard_face_fraction);
    m.q_t_domain = m.q_t_domain.or(r.q_t_domain);
    m.hard_domain_fraction = m.hard_domain_fraction.or(r.hard_domain_fraction);
}

fn merge_mesher(meshers: &mut Vec<MesherInfo>, r: &Record) {
    let k = match meshers.iter_mut().find(|k| k.id == r.mesher) {
        Some(k) => k,
        None => {
            meshers.push(MesherInfo {
                id: r.mesher.clone(),
                keeps_boundary: r.keeps_boundary,
                versions: Vec::new(),
                configuration: None,
            });
            meshers.last_mut().expect("just pushed")
        }
    };
    k.keeps_boundary &= r.keeps_boundary;
    if k.configuration.is_none() {
        k.configuration.clone_from(&r.configuration);
    }
    if !r.mesher_version.is_empty() && !k.versions.contains(&r.mesher_version) {
        k.versions.push(r.mesher_version.clone());
    }
}

/// CPU seconds (user + system), or wall seconds when CPU was not measured; the flag
/// is true for the wall fallback.
pub fn cpu_or_wall(r: &Record) -> Option<(f64, bool)> {
    r.cpu_seconds
        .map(|c| (c, false))
        .or(r.wall_seconds.map(|w| (w, true)))
}

/// Output tets per wall second.
pub fn tets_per_second(r: &Record) -> Option<f64> {
    match (r.tets, r.wall_seconds) {
        (Some(t), Some(w)) if w > 0.0 => Some(t as f64 / w),
        _ => None,
    }
}
