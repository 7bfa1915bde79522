//! The comparison itself: our rows of a run against the baseline's, model by model
//! (status, validity, worst Q_K, % Q_K < 3, tet count), then speed as the ratio of our
//! tets/s to a peer's in the same run: the median, over the models both meshed, of the
//! per-model ratio.
//!
//! A runner absent from the baseline is new and not gated; a runner whose rows are all
//! `missing` counts as absent. A model that failed in the baseline is not a regression if
//! it still fails, and is reported as improved when it now meshes.

use super::data::{is_ours, GateRow, Tolerances};
use crate::records::Status;
use crate::report::table::fmt_q;
use std::collections::{BTreeMap, BTreeSet};

/// The outcome of one check.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Verdict {
    /// Worse than the tolerance allows: the gate fails.
    Regressed,
    /// Better than the baseline in a way worth updating it for.
    Improved,
    /// Not in the baseline: reported, not gated.
    New,
    /// Within tolerance.
    Pass,
}

/// One line of the gate's table.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// Our runner.
    pub runner: String,
    /// Model id, or `N models vs PEER` for a speed ratio.
    pub subject: String,
    /// What was compared.
    pub check: &'static str,
    /// Baseline value.
    pub baseline: String,
    /// Value in this run.
    pub now: String,
    /// The bound that applied.
    pub limit: String,
    /// Outcome.
    pub verdict: Verdict,
}

type Rows<'a> = BTreeMap<(&'a str, &'a str), &'a GateRow>;

fn index(rows: &[GateRow]) -> Rows<'_> {
    rows.iter()
        .filter(|r| r.status != Status::Missing)
        .map(|r| ((r.mesher.as_str(), r.model.as_str()), r))
        .collect()
}

fn runners<'a>(rows: &Rows<'a>) -> BTreeSet<&'a str> {
    rows.keys().map(|k| k.0).filter(|m| is_ours(m)).collect()
}

/// Every check of `current` against `baseline`, in runner then model order.
pub fn compare(baseline: &[GateRow], current: &[GateRow], tol: &Tolerances) -> Vec<Finding> {
    let (base, now) = (index(baseline), index(current));
    let mut out = Vec::new();
    let base_runners = runners(&base);
    for runner in runners(&now).union(&base_runners) {
        if !base_runners.contains(runner) {
            out.push(finding(
                runner,
                "all",
                "runner",
                "absent",
                "present",
                "-",
                Verdict::New,
            ));
            continue;
        }
        let models: BTreeSet<&str> = base
            .keys()
            .chain(now.keys())
            .filter(|k| k.0 == *runner)
            .map(|k| k.1)
            .collect();
        for model in models {
            let key = (*runner, model);
            out.extend(compare_model(base.get(&key), now.get(&key), tol));
        }
        for peer in tol.peers.get(*runner).into_iter().flatten() {
            out.extend(compare_speed(runner, peer, &base, &now, tol));
        }
    }
    out
}

fn finding(
    runner: &str,
    subject: &str,
    check: &'static str,
    baseline: impl Into<String>,
    now: impl Into<String>,
    limit: impl Into<String>,
    verdict: Verdict,
) -> Finding {
    Finding {
        runner: runner.into(),
        subject: subject.into(),
        check,
        baseline: baseline.into(),
        now: now.into(),
        limit: limit.into(),
        verdict,
    }
}

fn status_name(s: Status) -> String {
    serde_json::to_value(s)
        .ok()
        .and_then(|v| v.as_str().map(String::from))
        .unwrap_or_default()
}

/// The checks of one model: status first; the measures only when both meshed.
fn compare_model(
    base: Option<&&GateRow>,
    now: Option<&&GateRow>,
    tol: &Tolerances,
) -> Vec<Finding> {
    let (b, n) = match (base, now) {
        (None, None) => return Vec::new(),
        (None, Some(n)) => {
            let now = status_name(n.status);
            return vec![finding(
                &n.mesher,
                &n.model,
                "model",
                "absent",
                now,
                "-",
                Verdict::New,
            )];
        }
        (Some(b), None) => {
            let v = if b.ok() {
                Verdict::Regressed
            } else {
                Verdict::Pass
            };
            let base = status_name(b.status);
            return vec![finding(
                &b.mesher, &b.model, "meshes", base, "not run", "ok", v,
            )];
        }
        (Some(b), Some(n)) => (*b, *n),
    };
    let f = |check, base: String, now: String, limit: String, v| {
        finding(&b.mesher, &b.model, check, base, now, limit, v)
    };
    let status = match (b.ok(), n.ok()) {
        (true, false) => Verdict::Regressed,
        (false, true) => Verdict::Improved,
        _ => Verdict::Pass,
    };
    let mut out = vec![f(
        "meshes",
        status_name(b.status),
        status_name(n.status),
        "ok".into(),
        status,
    )];
    if b.ok() && n.ok() {
        out.extend(compare_measures(b, n, tol));
    }
    out
}

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".into(), |x| format!("{x:.digits$}"))
}

/// Validity, worst Q_K, % Q_K < 3 and tet count of a model both runs meshed.
fn compare_measures(b: &GateRow, n: &GateRow, tol: &Tolerances) -> Vec<Finding> {
    let f = |check, base: String, now: String, limit: String, v| {
        finding(&b.mesher, &b.model, check, base, now, limit, v)
    };
    let verdict = |bad: bool| {
        if bad {
            Verdict::Regressed
        } else {
            Verdict::Pass
        }
    };
    let mut out = Vec::new();
    let lost = b.valid == Some(true) && n.valid != Some(true);
    let show = |v: Option<bool>| v.map_or("-".into(), |v| v.to_string());
    out.push(f(
        "valid",
        show(b.valid),
        show(n.valid),
        "true".into(),
        verdict(lost),
    ));
    // An infinite worst Q_K (a degenerate tet) is stored as null: worse than any bound.
    if let Some(bw) = b.worst_q_k {
        let limit = bw * (1.0 + tol.quality.worst_q_k_rel);
        let bad = n.worst_q_k.is_none_or(|w| w > limit);
        let q = |v: Option<f64>| v.map_or("inf".into(), fmt_q);
        let (bs, ns, ls) = (q(Some(bw)), q(n.worst_q_k), format!("<= {}", fmt_q(limit)));
        out.push(f("worst Q_K", bs, ns, ls, verdict(bad)));
    }
    if let (Some(bp), Some(np)) = (b.well_shaped_percent, n.well_shaped_percent) {
        let limit = bp - tol.quality.well_shaped_drop;
        let bad = np.is_nan() || np < limit;
        let (bs, ns, ls) = (
            format!("{bp:.2}"),
            format!("{np:.2}"),
            format!(">= {limit:.2}"),
        );
        out.push(f("% Q_K<3", bs, ns, ls, verdict(bad)));
    }
    if let (Some(bt), Some(nt)) = (b.tets, n.tets) {
        let (lo, hi) = (
            bt as f64 * (1.0 - tol.tets.band),
            bt as f64 * (1.0 + tol.tets.band),
        );
        let bad = (nt as f64) < lo || (nt as f64) > hi;
        let ls = format!("{:.0}..{:.0}", lo.ceil(), hi.floor());
        out.push(f("tets", bt.to_string(), nt.to_string(), ls, verdict(bad)));
    }
    out
}

/// Summed tets and wall seconds of `runner`'s rows over `models`.
fn totals(rows: &Rows<'_>, runner: &str, models: &[&str]) -> (f64, f64) {
    models.iter().fold((0.0, 0.0), |(t, w), m| {
        let r = rows[&(runner, *m)];
        (
            t + r.tets.unwrap_or(0) as f64,
            w + r.wall_seconds.unwrap_or(0.0),
        )
    })
}

/// The models of `models` on which both sides ran at least `min_model` seconds in
/// `rows` (the baseline): the run's median is taken over the same models, so that a
/// model crossing that floor between runs does not change the set. The ratios fall in
/// two groups (fine models at 2-7 times Gmsh HXT's tets per second, CAD models at
/// 20-130) and the median sits between them: nested-spheres at 0.044 s, then 0.05 s,
/// moved it from 14.2 to 6.5 with the same code.
fn timed_models<'m>(
    rows: &Rows<'_>,
    runner: &str,
    peer: &str,
    models: &[&'m str],
    min_model: f64,
) -> Vec<&'m str> {
    let timed = |who: &str, m: &str| {
        rows.get(&(who, m))
            .and_then(|r| r.wall_seconds)
            .is_some_and(|w| w >= min_model)
    };
    models
        .iter()
        .copied()
        .filter(|m| timed(runner, m) && timed(peer, m))
        .collect()
}

/// The median over `models` of our tets/s over the peer's on the same model; `None`
/// when a side ran for less than `min` in total or no model has both speeds. A median,
/// not a ratio of sums: one model on which a peer's time swings fivefold between runs
/// (TetGen -q on fandisk-in-box: 51 s, then 9 s) must not move the figure.
fn speed_ratio(
    rows: &Rows<'_>,
    runner: &str,
    peer: &str,
    models: &[&str],
    min: f64,
) -> Option<f64> {
    let (ot, ow) = totals(rows, runner, models);
    let (pt, pw) = totals(rows, peer, models);
    if !(ow >= min && pw >= min && ot > 0.0 && pt > 0.0) {
        return None;
    }
    let speed = |who: &str, m: &str| {
        let r = rows.get(&(who, m))?;
        let (t, w) = (r.tets? as f64, r.wall_seconds?);
        (w > 0.0 && t > 0.0).then_some(t / w)
    };
    let mut ratios: Vec<f64> = models
        .iter()
        .filter_map(|m| Some(speed(runner, m)? / speed(peer, m)?))
        .collect();
    (!ratios.is_empty()).then(|| mesher::quality::median(&mut ratios))
}

/// The speed check of one (runner, peer) pair over the models all four rows meshed.
fn compare_speed(
    runner: &str,
    peer: &str,
    base: &Rows<'_>,
    now: &Rows<'_>,
    tol: &Tolerances,
) -> Option<Finding> {
    let ok = |rows: &Rows<'_>, who: &str, m: &str| rows.get(&(who, m)).is_some_and(|r| r.ok());
    let models: Vec<&str> = base
        .keys()
        .filter(|k| k.0 == runner)
        .map(|k| k.1)
        .filter(|m| {
            ok(base, runner, m) && ok(base, peer, m) && ok(now, runner, m) && ok(now, peer, m)
        })
        .collect();
    if models.is_empty() {
        return None;
    }
    let timed = timed_models(base, runner, peer, &models, tol.speed.min_model_seconds);
    let subject = format!("{} models vs {peer}", timed.len());
    let min = tol.speed.min_seconds;
    let (b, n) = (
        speed_ratio(base, runner, peer, &timed, min),
        speed_ratio(now, runner, peer, &timed, min),
    );
    let (Some(b), Some(n)) = (b, n) else {
        let (bs, ns) = (fmt_opt(b, 3), fmt_opt(n, 3));
        let limit = format!("not timed (< {min} s)");
        return Some(finding(
            runner,
            &subject,
            "tets/s ratio",
            bs,
            ns,
            limit,
            Verdict::Pass,
        ));
    };
    let limit = b * tol.speed.min_ratio;
    let verdict = if n < limit {
        Verdict::Regressed
    } else {
        Verdict::Pass
    };
    let (bs, ns, ls) = (
        format!("{b:.3}"),
        format!("{n:.3}"),
        format!(">= {limit:.3}"),
    );
    Some(finding(
        runner,
        &subject,
        "tets/s ratio",
        bs,
        ns,
        ls,
        verdict,
    ))
}
