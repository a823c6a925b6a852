//! What a sweep's results table depends on, so that a resumed sweep never mixes rows of another
//! study or model version: the study record `study.json` beside `results.csv` (the model
//! version, the resolved base scene, the fixed values, what is kept) and each row's `run_key`
//! (a hash of the run's resolved scene, its noise, what is kept and the model version).

use super::spec::{fnv1a64, Run, Sweep};
use std::collections::BTreeMap;

/// Format name of `study.json`.
const STUDY_FORMAT: &str = "raceway-sweep-study";

/// The study record: flattened `path = value` entries (the model version, the resolved base
/// scene, the fixed values, what is kept), as written to `study.json`.
pub fn study_record(sweep: &Sweep) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    m.insert("format".into(), STUDY_FORMAT.into());
    m.insert("model_version".into(), crate::MODEL_VERSION.into());
    for (k, v) in flatten_debug(&format!("{:#?}", sweep.base)) {
        m.insert(format!("base.{k}"), v);
    }
    for (k, v) in &sweep.set {
        m.insert(format!("set.{k}"), v.canonical());
    }
    for (k, v) in flatten_debug(&format!("{:#?}", sweep.keep)) {
        m.insert(format!("keep.{k}"), v);
    }
    m
}

/// The differences between a stored study record and the current one, one line each
/// (`path: old → new`), at most `max` lines and a count of the rest.
pub fn differences(
    old: &BTreeMap<String, String>,
    new: &BTreeMap<String, String>,
    max: usize,
) -> Vec<String> {
    let none = String::from("(none)");
    let mut keys: Vec<&String> = old.keys().chain(new.keys()).collect();
    keys.sort();
    keys.dedup();
    let diffs: Vec<String> = keys
        .into_iter()
        .filter(|k| old.get(*k) != new.get(*k))
        .map(|k| {
            format!(
                "{k}: {} → {}",
                old.get(k).unwrap_or(&none),
                new.get(k).unwrap_or(&none)
            )
        })
        .collect();
    let mut out: Vec<String> = diffs.iter().take(max).cloned().collect();
    if diffs.len() > max {
        out.push(format!("… and {} more", diffs.len() - max));
    }
    out
}

/// The run's key: a hash of everything its result depends on — its resolved scene and noise
/// (or why it cannot be resolved), what is kept, and the model version.
pub fn run_key(sweep: &Sweep, run: &Run) -> String {
    let scene = match sweep.scene_for(run) {
        Ok((scene, noise)) => format!("{scene:?}\nnoise {noise:?}"),
        Err(e) => format!("unresolved: {e}"),
    };
    let text = format!(
        "{}\n{scene}\n{:?}\n{}",
        crate::MODEL_VERSION,
        sweep.keep,
        run.id
    );
    format!("{:016x}", fnv1a64(text.as_bytes()))
}

/// The check of a row: a hash of its other fields (a row damaged on disk fails it).
pub fn row_check(fields: &[String]) -> String {
    let mut text = String::new();
    for f in fields {
        text.push_str(f);
        text.push('\u{1f}');
    }
    format!("{:016x}", fnv1a64(text.as_bytes()))
}

/// `path = value` pairs of a pretty-printed `Debug` value (`{:#?}`): one per leaf line, the
/// path from the enclosing struct fields (list items by their index).
pub fn flatten_debug(pretty: &str) -> Vec<(String, String)> {
    let mut path: Vec<String> = Vec::new();
    let mut index: Vec<usize> = Vec::new();
    let mut out = Vec::new();
    for line in pretty.lines().skip(1) {
        let t = line.trim().trim_end_matches(',');
        if t.is_empty() {
            continue;
        }
        if t.starts_with('}') || t.starts_with(']') || t.starts_with(')') {
            path.pop();
            index.pop();
            continue;
        }
        let (name, value) = match t.split_once(": ") {
            Some((n, v)) if !n.contains(' ') && !n.contains('"') => (n.to_string(), v.to_string()),
            _ => {
                // A list item: named by its position.
                let i = index.last_mut().map_or(0, |i| {
                    *i += 1;
                    *i - 1
                });
                (i.to_string(), t.to_string())
            }
        };
        let opens = value.ends_with('{') || value.ends_with('[') || value.ends_with('(');
        let key = path
            .iter()
            .chain(std::iter::once(&name))
            .cloned()
            .collect::<Vec<_>>()
            .join(".");
        if opens {
            path.push(name);
            index.push(0);
        } else {
            out.push((key, value));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug)]
    #[allow(dead_code)] // read through Debug only
    struct Inner {
        speed: f64,
        name: String,
    }
    #[derive(Debug)]
    #[allow(dead_code)] // read through Debug only
    struct Outer {
        a: f64,
        inner: Inner,
        list: Vec<f64>,
        maybe: Option<Inner>,
    }

    #[test]
    fn flattened_debug_names_every_leaf_by_its_path() {
        let v = Outer {
            a: 1.5,
            inner: Inner {
                speed: 2.0,
                name: "x y".into(),
            },
            list: vec![3.0, 4.0],
            maybe: None,
        };
        let f = flatten_debug(&format!("{v:#?}"));
        let get = |k: &str| f.iter().find(|(p, _)| p == k).map(|(_, v)| v.as_str());
        assert_eq!(get("a"), Some("1.5"));
        assert_eq!(get("inner.speed"), Some("2.0"));
        assert_eq!(get("inner.name"), Some("\"x y\""));
        assert_eq!(get("list.0"), Some("3.0"));
        assert_eq!(get("list.1"), Some("4.0"));
        assert_eq!(get("maybe"), Some("None"));
    }

    #[test]
    fn differences_list_changed_added_and_removed_entries() {
        let old: BTreeMap<String, String> = [("a", "1"), ("b", "2")]
            .map(|(k, v)| (k.into(), v.into()))
            .into();
        let new: BTreeMap<String, String> = [("a", "1"), ("b", "3"), ("c", "4")]
            .map(|(k, v)| (k.into(), v.into()))
            .into();
        assert_eq!(
            differences(&old, &new, 10),
            vec!["b: 2 → 3".to_string(), "c: (none) → 4".to_string()]
        );
        assert_eq!(differences(&old, &new, 1).len(), 2);
    }
}
