//! Tables: the paper's Table 1 layout (one column per model, one block per mesher), the
//! cross-model summary per mesher and a per-model table, each built once as a [`Table`]
//! and rendered to Markdown, LaTeX or HTML.
//!
//! Marks: `†` after a mesher that moves the input boundary, `‡` after a model whose
//! surface is the limit (see [`crate::report::data::HARD_FACE_LIMIT`]); each mark has a
//! note under the table.

use crate::records::{Record, Status};
use crate::report::data::{cpu_or_wall, status_name, tets_per_second, ModelInfo, RunData};

/// Mark of a mesher that moves the input boundary.
pub const MOVES_BOUNDARY: &str = "†";
/// Mark of a model whose surface limits the reachable quality.
pub const SURFACE_LIMIT: &str = "‡";

/// A block of rows under an optional title row.
#[derive(Debug, Clone, Default)]
pub struct Section {
    /// Title row (e.g. the mesher of a Table 1 block).
    pub title: Option<String>,
    /// Rows of cells, as many as the header.
    pub rows: Vec<Vec<String>>,
}

/// A table with plain-text cells (renderers escape them).
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Header cells.
    pub header: Vec<String>,
    /// Blocks of rows.
    pub sections: Vec<Section>,
    /// Footnotes.
    pub notes: Vec<String>,
}

/// `Q_K`-like value: two decimals, scientific from 1000 on, `inf`/`NaN` spelled out.
pub fn fmt_q(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x.is_infinite() {
        "inf".into()
    } else if x.abs() >= 1000.0 {
        format!("{x:.2e}")
    } else {
        format!("{x:.2}")
    }
}

/// Seconds: two decimals below 10 s, one above.
pub fn fmt_s(x: f64) -> String {
    if x < 10.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.1}")
    }
}

/// A rate or large count, three significant figures with k/M suffixes.
pub fn fmt_rate(x: f64) -> String {
    if x >= 1e6 {
        format!("{:.2}M", x / 1e6)
    } else if x >= 1e3 {
        format!("{:.1}k", x / 1e3)
    } else {
        format!("{x:.0}")
    }
}

fn opt<T>(v: Option<T>, f: impl Fn(T) -> String) -> String {
    v.map(f).unwrap_or_else(|| "–".into())
}

/// The mesher's label with its mark.
pub fn mesher_label(run: &RunData, k: usize) -> String {
    let m = &run.meshers[k];
    if m.keeps_boundary {
        m.id.clone()
    } else {
        format!("{}{MOVES_BOUNDARY}", m.id)
    }
}

/// The model's label with its mark.
pub fn model_label(run: &RunData, m: usize) -> String {
    let info = &run.models[m];
    if info.surface_limited() {
        format!("{}{SURFACE_LIMIT}", info.id)
    } else {
        info.id.clone()
    }
}

/// The in-domain `Q_t` of a model where it exceeds `Q_t` (thin parts), as a clause.
fn domain_note(m: &ModelInfo) -> String {
    match (m.q_t, m.q_t_domain, m.hard_domain_fraction) {
        (Some(q), Some(d), Some(f)) if d > q * 1.001 => format!(
            "; with each face's best tet kept inside the domain (its thin parts), Q_t = {} and \
             {:.1} % of the faces above 3 (an estimate)",
            fmt_q(d),
            100.0 * f
        ),
        _ => String::new(),
    }
}

/// The notes for the marks used in `run`.
pub fn notes(run: &RunData) -> Vec<String> {
    let mut out = Vec::new();
    for m in run.models.iter().filter(|m| m.surface_limited()) {
        out.push(format!(
            "{SURFACE_LIMIT} {}: the surface is the limit: no mesher can reach good worst-case quality \
             on this surface (Q_t = {}; {:.1} % of the input faces have best possible Q_K > 3{}).",
            m.id,
            opt(m.q_t, fmt_q),
            100.0 * m.hard_face_fraction.unwrap_or(0.0),
            domain_note(m)
        ));
    }
    for k in &run.meshers {
        if let Some(c) = &k.configuration {
            out.push(format!("{}: {c}.", k.id));
        }
    }
    for k in run.meshers.iter().filter(|k| !k.keeps_boundary) {
        out.push(format!(
            "{MOVES_BOUNDARY} {} moves the input boundary (it re-meshes the surface): its boundary \
             vertices and faces are not the input's.",
            k.id
        ));
    }
    out
}

/// The measured Table 1 rows of one record, or its status in every row.
fn table1_measured(r: Option<&Record>) -> [String; 8] {
    let r = match r {
        None => return std::array::from_fn(|_| "not run".into()),
        Some(r) if r.status != Status::Ok => {
            return std::array::from_fn(|_| status_name(r.status).into())
        }
        Some(r) => r,
    };
    let q = r.quality.as_ref();
    [
        opt(r.vertices, |v| v.to_string()),
        opt(r.tets, |v| v.to_string()),
        opt(cpu_or_wall(r), |(s, wall)| {
            if wall {
                format!("{} (wall)", fmt_s(s))
            } else {
                fmt_s(s)
            }
        }),
        opt(r.iterations, |v| v.to_string()),
        opt(q.map(|q| q.worst_q_k), fmt_q),
        opt(q.and_then(|q| q.worse_than_target), |v| v.to_string()),
        opt(q.map(|q| q.well_shaped), |v| v.to_string()),
        opt(q.map(|q| q.well_shaped_percent), |v| format!("{v:.2}")),
    ]
}

/// Row labels of Table 1, in the paper's order.
pub const TABLE1_ROWS: [&str; 11] = [
    "boundary vertices",
    "boundary faces",
    "vertices",
    "tets",
    "CPU s",
    "iterations",
    "Q_t",
    "worst Q_K",
    "# Q_K > Q_t",
    "# Q_K<3",
    "% Q_K<3",
];

/// Table 1: one column per model, one block per mesher.
pub fn table1(run: &RunData) -> Table {
    let mut header = vec![String::new()];
    header.extend((0..run.models.len()).map(|m| model_label(run, m)));
    let mut sections = Vec::new();
    for k in 0..run.meshers.len() {
        let mut rows: Vec<Vec<String>> = TABLE1_ROWS.iter().map(|l| vec![l.to_string()]).collect();
        for (m, info) in run.models.iter().enumerate() {
            let measured = table1_measured(run.get(m, k));
            let input = [
                info.input_vertices.to_string(),
                info.input_faces.to_string(),
                opt(info.q_t, fmt_q),
            ];
            let column = [
                &input[0],
                &input[1],
                &measured[0],
                &measured[1],
                &measured[2],
                &measured[3],
                &input[2],
                &measured[4],
                &measured[5],
                &measured[6],
                &measured[7],
            ];
            for (row, cell) in rows.iter_mut().zip(column) {
                row.push(cell.clone());
            }
        }
        sections.push(Section {
            title: Some(mesher_label(run, k)),
            rows,
        });
    }
    Table {
        header,
        sections,
        notes: notes(run),
    }
}

fn status_counts(run: &RunData, k: usize) -> String {
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for m in 0..run.models.len() {
        let name = run.get(m, k).map_or("not run", |r| status_name(r.status));
        match counts.iter_mut().find(|(n, _)| *n == name) {
            Some(c) => c.1 += 1,
            None => counts.push((name, 1)),
        }
    }
    let parts: Vec<String> = counts.iter().map(|(n, c)| format!("{n} {c}")).collect();
    parts.join(", ")
}

fn summary_row(run: &RunData, k: usize) -> Vec<String> {
    let s = crate::report::history::summarize(run, k);
    vec![
        mesher_label(run, k),
        status_counts(run, k),
        opt(s.worst_q_k_fine, fmt_q),
        opt(s.worst_q_k_all, fmt_q),
        opt(s.well_shaped_percent, |v| format!("{v:.2}")),
        opt(s.tets_per_second, fmt_rate),
        opt(s.peak_rss_bytes, |b| {
            format!("{:.0}", b as f64 / (1024.0 * 1024.0))
        }),
    ]
}

/// Cross-model summary: one row per mesher.
pub fn summary(run: &RunData) -> Table {
    let header = [
        "mesher",
        "runs",
        "worst Q_K (fine surfaces)",
        "worst Q_K (all)",
        "% Q_K<3",
        "tets/s",
        "peak RSS MiB",
    ];
    Table {
        header: header.iter().map(|s| s.to_string()).collect(),
        sections: vec![Section {
            title: None,
            rows: (0..run.meshers.len())
                .map(|k| summary_row(run, k))
                .collect(),
        }],
        notes: vec![
            "worst Q_K (fine surfaces) leaves out models whose surface is the limit; % Q_K<3 is \
             over all tets of the ok runs; tets/s = total tets / total wall seconds."
                .into(),
        ],
    }
}

fn model_row(run: &RunData, m: usize, k: usize) -> Vec<String> {
    let mut row = vec![mesher_label(run, k)];
    let r = match run.get(m, k) {
        None => {
            row.push("not run".into());
            row.resize(14, "–".to_string());
            return row;
        }
        Some(r) => r,
    };
    let q = r.quality.as_ref();
    row.extend([
        status_name(r.status).to_string(),
        opt(r.tets, |v| v.to_string()),
        opt(r.cpu_seconds, fmt_s),
        opt(r.wall_seconds, fmt_s),
        opt(r.mesh_seconds, fmt_s),
        opt(tets_per_second(r), fmt_rate),
        opt(r.peak_rss_bytes, |b| format!("{:.0}", b as f64 / 1048576.0)),
        opt(q.map(|q| q.worst_q_k), fmt_q),
        opt(q.map(|q| q.median_q_k), fmt_q),
        opt(q.map(|q| q.well_shaped_percent), |v| format!("{v:.2}")),
        opt(r.edge_band.as_ref().map(|b| b.in_band_percent), |v| {
            format!("{v:.1}")
        }),
        opt(q.map(|q| q.min_dihedral), |v| format!("{v:.1}")),
    ]);
    let msg = r.message.as_deref().unwrap_or("");
    row.push(msg.chars().take(120).collect());
    row
}

/// One model: one row per mesher.
pub fn model_table(run: &RunData, m: usize) -> Table {
    let header = [
        "mesher",
        "status",
        "tets",
        "CPU s",
        "wall s",
        "mesh s",
        "tets/s",
        "peak RSS MiB",
        "worst Q_K",
        "median Q_K",
        "% Q_K<3",
        "% edges in band",
        "min dihedral °",
        "message",
    ];
    Table {
        header: header.iter().map(|s| s.to_string()).collect(),
        sections: vec![Section {
            title: None,
            rows: (0..run.meshers.len())
                .map(|k| model_row(run, m, k))
                .collect(),
        }],
        notes: vec![
            "mesh s: the meshing call alone, where the mesher reports it (ours: the library \
             call, without reading and writing files; Gmsh, fTetWild: the Python call); wall s \
             is the whole process."
                .into(),
        ],
    }
}

/// Renders a table as GitHub Markdown (block titles become bold rows).
pub fn to_markdown(t: &Table) -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let line = |cells: &[String]| {
        let c: Vec<String> = cells.iter().map(|s| esc(s)).collect();
        format!("| {} |\n", c.join(" | "))
    };
    let mut out = line(&t.header);
    out += &format!("|{}\n", "---|".repeat(t.header.len()));
    for s in &t.sections {
        if let Some(title) = &s.title {
            let mut cells = vec![format!("**{title}**")];
            cells.resize(t.header.len(), String::new());
            out += &line(&cells);
        }
        for r in &s.rows {
            out += &line(r);
        }
    }
    for n in &t.notes {
        out += &format!("\n{}\n", esc(n));
    }
    out
}

/// Escapes text for LaTeX, setting `Q_K`, `Q_t` and the marks in math.
pub fn latex_escape(s: &str) -> String {
    let s = s.replace("Q_K", "\u{E000}").replace("Q_t", "\u{E001}");
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\u{E000}' => out.push_str("$Q_K$"),
            '\u{E001}' => out.push_str("$Q_t$"),
            '†' => out.push_str("$^\\dagger$"),
            '‡' => out.push_str("$^\\ddagger$"),
            '°' => out.push_str("$^\\circ$"),
            '–' => out.push_str("--"),
            '<' => out.push_str("$<$"),
            '>' => out.push_str("$>$"),
            '\\' => out.push_str("\\textbackslash{}"),
            '~' => out.push_str("\\textasciitilde{}"),
            '^' => out.push_str("\\textasciicircum{}"),
            '%' | '#' | '&' | '_' | '$' | '{' | '}' => {
                out.push('\\');
                out.push(c);
            }
            _ => out.push(c),
        }
    }
    out
}

/// Renders a table as a LaTeX `tabular` (block titles span the row), notes after it.
pub fn to_latex(t: &Table) -> String {
    let n = t.header.len();
    let row = |cells: &[String]| {
        let c: Vec<String> = cells.iter().map(|s| latex_escape(s)).collect();
        format!("{} \\\\\n", c.join(" & "))
    };
    let mut out = format!(
        "\\begin{{tabular}}{{l{}}}\n\\hline\n",
        "r".repeat(n.saturating_sub(1))
    );
    out += &row(&t.header);
    out += "\\hline\n";
    for s in &t.sections {
        if let Some(title) = &s.title {
            out += &format!(
                "\\multicolumn{{{n}}}{{l}}{{\\textbf{{{}}}}} \\\\\n\\hline\n",
                latex_escape(title)
            );
        }
        for r in &s.rows {
            out += &row(r);
        }
        out += "\\hline\n";
    }
    out += "\\end{tabular}\n";
    for note in &t.notes {
        out += &format!("\n{}\n", latex_escape(note));
    }
    out
}

/// Escapes text for HTML.
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Renders a table as an HTML `<table>` (notes as paragraphs after it).
pub fn to_html(t: &Table) -> String {
    let n = t.header.len();
    let mut out = String::from("<table>\n<thead><tr>");
    for h in &t.header {
        out += &format!("<th>{}</th>", html_escape(h));
    }
    out += "</tr></thead>\n<tbody>\n";
    for s in &t.sections {
        if let Some(title) = &s.title {
            out += &format!(
                "<tr class=\"block\"><th colspan=\"{n}\">{}</th></tr>\n",
                html_escape(title)
            );
        }
        for r in &s.rows {
            out += "<tr>";
            for (i, c) in r.iter().enumerate() {
                let tag = if i == 0 { "th" } else { "td" };
                out += &format!("<{tag}>{}</{tag}>", html_escape(c));
            }
            out += "</tr>\n";
        }
    }
    out += "</tbody>\n</table>\n";
    for note in &t.notes {
        out += &format!("<p class=\"note\">{}</p>\n", html_escape(note));
    }
    out
}

/// `table.md`: summary, then Table 1, then the notes.
pub fn markdown(run: &RunData) -> String {
    let mut out = String::from("# Mesher comparison\n\n");
    out += &format!("{}\n\n", metadata_line(run));
    out += "## Summary over the models\n\n";
    out += &to_markdown(&summary(run));
    out += "\n## Table 1 (layout of the paper)\n\n";
    out += &to_markdown(&table1(run));
    out
}

/// `table.tex`: Table 1 and the summary as two `tabular`s.
pub fn latex(run: &RunData) -> String {
    let mut out = format!("% {}\n", metadata_line(run));
    out += "% Table 1 layout: one column per model, one block per mesher.\n";
    out += &to_latex(&table1(run));
    out += "\n% Summary over the models, one row per mesher.\n";
    out += &to_latex(&summary(run));
    out
}

/// One line naming the revisions, machines and dates of the records.
pub fn metadata_line(run: &RunData) -> String {
    let dates = run.distinct(|r| &r.finished_at);
    let first = dates.iter().min().cloned().unwrap_or_default();
    let last = dates.iter().max().cloned().unwrap_or_default();
    format!(
        "Run: git {}; machine {}; finished {} to {}; {} records.",
        run.distinct(|r| &r.git_revision).join(", "),
        run.distinct(|r| &r.machine).join(", "),
        first,
        last,
        run.records.len()
    )
}
