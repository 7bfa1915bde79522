//! `index.html`: one self-contained page (inline CSS, the SVG plots beside it as
//! `<img>`) with the run metadata, the summary table, per-model tables and plots and
//! the Table 1 layout.

use std::path::Path;

use crate::report::data::RunData;
use crate::report::plots::{Plot, PlotKind};
use crate::report::table::{self, html_escape, to_html};

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;color:#222;max-width:1400px}\
h1{font-size:1.6em}h2{font-size:1.3em;border-bottom:1px solid #ccc;margin-top:1.6em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}\
th,td{border:1px solid #ccc;padding:.25em .5em;text-align:right}td:last-child{text-align:left}\
thead th{background:#eef}tbody th{text-align:left;font-weight:normal}\
tr.block th{background:#f4f4f4;font-weight:bold;text-align:left}\
.note{font-size:.9em;color:#444}.warn{background:#fff3cd;border:1px solid #e0c060;padding:.4em .6em}\
.plots{display:flex;flex-wrap:wrap;gap:1em}figure{margin:0}\
.plots img{width:560px;max-width:100%;height:auto;border:1px solid #ddd}\
.wide{overflow-x:auto}dl{display:grid;grid-template-columns:max-content auto;gap:.2em 1em}\
dt{font-weight:bold}dd{margin:0}";

/// Link to `reports/METHODOLOGY.md`, relative to `out` when `out` lies under a
/// `reports` folder (e.g. `reports/latest`, `reports/runs/<stamp>`).
pub fn methodology_href(out: &Path) -> String {
    let abs = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    for (depth, dir) in abs.ancestors().enumerate() {
        if dir.file_name().is_some_and(|n| n == "reports") {
            return format!("{}METHODOLOGY.md", "../".repeat(depth));
        }
    }
    "reports/METHODOLOGY.md".into()
}

fn metadata(run: &RunData, out: &Path) -> String {
    let dates = run.distinct(|r| &r.finished_at);
    let span = match (dates.iter().min(), dates.iter().max()) {
        (Some(a), Some(b)) if a != b => format!("{a} to {b}"),
        (Some(a), _) => a.clone(),
        _ => "unknown".into(),
    };
    let versions: Vec<String> = run
        .meshers
        .iter()
        .map(|m| format!("{} {}", m.id, m.versions.join(" / ")))
        .collect();
    let items = [
        ("git revision", run.distinct(|r| &r.git_revision).join(", ")),
        ("machine", run.distinct(|r| &r.machine).join("; ")),
        ("date", span),
        ("records", run.records.len().to_string()),
        ("meshers", versions.join("; ")),
    ];
    let mut s = String::from("<dl>\n");
    for (k, v) in items {
        s += &format!("<dt>{k}</dt><dd>{}</dd>\n", html_escape(&v));
    }
    s += &format!(
        "<dt>methodology</dt><dd><a href=\"{}\">reports/METHODOLOGY.md</a></dd>\n</dl>\n",
        html_escape(&methodology_href(out))
    );
    s
}

fn img(p: &Plot) -> String {
    format!(
        "<figure><img src=\"{}\" alt=\"{}\" width=\"760\" height=\"420\"></figure>\n",
        html_escape(&p.file),
        html_escape(&p.title)
    )
}

fn model_section(run: &RunData, plots: &[Plot], m: usize) -> String {
    let info = &run.models[m];
    let mut s = format!(
        "<h2 id=\"model-{}\">{}</h2>\n<p>{} tier, {}; input {} vertices, {} faces; Q<sub>t</sub> = {}; \
         hard faces {}; in the domain (each face's best tet kept inside it, an estimate) \
         Q<sub>t</sub> = {}, hard faces {}.</p>\n",
        html_escape(&info.id),
        html_escape(&table::model_label(run, m)),
        html_escape(&info.tier),
        html_escape(&info.category),
        info.input_vertices,
        info.input_faces,
        info.q_t.map_or("–".into(), table::fmt_q),
        info.hard_face_fraction
            .map_or("–".into(), |f| format!("{:.1} %", 100.0 * f)),
        info.q_t_domain.map_or("–".into(), table::fmt_q),
        info.hard_domain_fraction
            .map_or("–".into(), |f| format!("{:.1} %", 100.0 * f)),
    );
    if info.surface_limited() {
        s += &format!(
            "<p class=\"warn\">The surface is the limit: no mesher can reach good worst-case quality on \
             this surface (Q<sub>t</sub> = {}).</p>\n",
            info.q_t.map_or("–".into(), table::fmt_q)
        );
    }
    s += &format!(
        "<div class=\"wide\">{}</div>\n",
        to_html(&table::model_table(run, m))
    );
    let mine: Vec<&Plot> = plots.iter().filter(|p| p.model == Some(m)).collect();
    if mine.is_empty() {
        s += "<p class=\"note\">No plot: no mesher produced a measured mesh.</p>\n";
    } else {
        s += "<div class=\"plots\">\n";
        for p in mine {
            s += &img(p);
        }
        s += "</div>\n";
    }
    s
}

/// The whole page.
pub fn page(run: &RunData, plots: &[Plot], out: &Path) -> String {
    let mut s = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>Mesher comparison</title><style>{STYLE}</style></head><body>\n\
         <h1>Mesher comparison</h1>\n{}",
        metadata(run, out)
    );
    s += "<h2>Summary over the models</h2>\n";
    s += &format!(
        "<div class=\"wide\">{}</div>\n",
        to_html(&table::summary(run))
    );
    for n in table::notes(run) {
        s += &format!("<p class=\"note\">{}</p>\n", html_escape(&n));
    }
    let corpus: Vec<&Plot> = plots.iter().filter(|p| p.kind == PlotKind::Rate).collect();
    if !corpus.is_empty() {
        s += "<div class=\"plots\">\n";
        for p in corpus {
            s += &img(p);
        }
        s += "</div>\n";
    }
    let trends: Vec<&Plot> = plots.iter().filter(|p| p.kind == PlotKind::Trend).collect();
    if !trends.is_empty() {
        s += "<h2>Nightly trends</h2>\n<div class=\"plots\">\n";
        for p in trends {
            s += &img(p);
        }
        s += "</div>\n";
    }
    for m in 0..run.models.len() {
        s += &model_section(run, plots, m);
    }
    s += "<h2>Issue targets</h2>\n";
    for (title, t) in super::targets::targets(run) {
        s += &format!(
            "<h3>{}</h3>\n<div class=\"wide\">{}</div>\n",
            html_escape(&title),
            to_html(&t)
        );
    }
    s += "<h2>Table 1 (layout of the paper)</h2>\n";
    s += &format!(
        "<div class=\"wide\">{}</div>\n",
        to_html(&table::table1(run))
    );
    s += "</body></html>\n";
    s
}
