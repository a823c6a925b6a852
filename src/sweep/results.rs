//! `results.csv`: one row per finished run, appended as runs finish, read back to resume.
//!
//! Columns: `run_index, run_id, run_key, status (ok|failed), error, wall_s`, then one column
//! per axis key (the run's value, canonical text), then the metric columns of
//! [`metric_columns`], then `check` (a hash of the row's other fields). Numbers are written as
//! shortest round-trip decimals, so equal values give equal text; metrics of a failed run are
//! empty. Beside it, `study.json` records what the table depends on ([`super::study`]).
//!
//! One reader serves the CLI, `--merge` and the dask example (through the CLI): it drops a
//! last line cut short by a kill and any row whose check fails (they are run again), refuses a
//! table of another study or model version with what changed, and counts a run as done only if
//! its stored key is the key the run has now.

use super::metrics::{metric_columns, MetricRow};
use super::spec::{Run, Sweep};
use super::study::{differences, row_check, run_key, study_record};
use super::SweepError;
use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The fixed leading columns.
pub const LEAD: [&str; 6] = [
    "run_index",
    "run_id",
    "run_key",
    "status",
    "error",
    "wall_s",
];

/// The last column: the row's check.
pub const CHECK: &str = "check";

/// All columns of a sweep's results.csv.
pub fn columns(sweep: &Sweep) -> Vec<String> {
    LEAD.iter()
        .map(|s| s.to_string())
        .chain(sweep.axes.iter().map(|a| a.key.clone()))
        .chain(metric_columns(&sweep.keep))
        .chain(std::iter::once(CHECK.to_string()))
        .collect()
}

/// The row of a finished run (its check last).
pub fn row(sweep: &Sweep, run: &Run, result: &Result<MetricRow, String>, wall: f64) -> Vec<String> {
    let n_metrics = metric_columns(&sweep.keep).len();
    let (status, error, metrics) = match result {
        Ok(m) => ("ok", String::new(), m.clone()),
        Err(e) => (
            "failed",
            e.replace(['\n', '\r'], " "),
            vec![String::new(); n_metrics],
        ),
    };
    let mut fields: Vec<String> = [
        run.index.to_string(),
        run.id.clone(),
        run_key(sweep, run),
        status.to_string(),
        error,
        format!("{wall:.3}"),
    ]
    .into_iter()
    .chain(run.params.iter().map(|(_, v)| v.canonical()))
    .chain(metrics)
    .collect();
    fields.push(row_check(&fields));
    fields
}

/// How to open a results folder that holds a table of another study or model version.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnChange {
    /// Refuse with a message that says what changed (the default).
    #[default]
    Refuse,
    /// Keep the old table as `results.N.csv` (and `study.N.json`) and start a new one.
    NewTable,
}

/// What opening a results folder found.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct OpenReport {
    /// Rows dropped because they were cut short or failed their check (run again).
    pub dropped: usize,
    /// Where an old table was kept ([`OnChange::NewTable`]).
    pub kept_as: Option<PathBuf>,
}

/// An open results.csv: the runs already recorded (id → key) and an appending writer.
pub struct ResultsFile {
    path: PathBuf,
    columns: Vec<String>,
    done: HashMap<String, String>,
    writer: csv::Writer<std::fs::File>,
    report: OpenReport,
}

fn io_err(path: &Path) -> impl Fn(&dyn std::fmt::Display) -> SweepError + '_ {
    move |e| SweepError::new(format!("{}: {e}", path.display()))
}

/// A table as read: its header, its valid rows, and how many rows were dropped.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
    dropped: usize,
}

/// The valid rows of a results.csv text: the header and the rows whose field count and check
/// are right (a last line without its newline, cut short by a kill, is not a row), and how
/// many were dropped.
fn read_rows(text: &str, path: &Path) -> Result<Table, SweepError> {
    let complete = match text.rfind('\n') {
        Some(i) => &text[..=i],
        None => "",
    };
    let mut dropped = usize::from(complete.len() < text.len());
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(complete.as_bytes());
    let header: Vec<String> = r
        .headers()
        .map_err(|e| io_err(path)(&e))?
        .iter()
        .map(String::from)
        .collect();
    let mut rows = Vec::new();
    for rec in r.records() {
        let Ok(rec) = rec else {
            dropped += 1;
            continue;
        };
        let fields: Vec<String> = rec.iter().map(String::from).collect();
        let ok = fields.len() == header.len()
            && fields
                .split_last()
                .is_some_and(|(check, rest)| *check == row_check(rest));
        if ok {
            rows.push(fields);
        } else {
            dropped += 1;
        }
    }
    Ok(Table {
        header,
        rows,
        dropped,
    })
}

/// Writes `text` to `path` through a temporary file renamed into place.
fn replace_file(path: &Path, text: &str) -> Result<(), SweepError> {
    let tmp = path.with_extension("csv.tmp");
    std::fs::write(&tmp, text).map_err(|e| io_err(&tmp)(&e))?;
    std::fs::rename(&tmp, path).map_err(|e| io_err(path)(&e))
}

/// The first free `stem.N.ext` beside `path`.
fn kept_name(path: &Path, n: usize) -> PathBuf {
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("results");
    let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("csv");
    path.with_file_name(format!("{stem}.{n}.{ext}"))
}

/// Moves a table and its study record aside, to the first free `results.N.csv` and
/// `study.N.json`; returns the table's new path.
fn keep_aside(path: &Path, study_path: &Path) -> Result<PathBuf, SweepError> {
    let n = (1..)
        .find(|n| !kept_name(path, *n).exists())
        .expect("a free name");
    let kept = kept_name(path, n);
    std::fs::rename(path, &kept).map_err(|e| io_err(path)(&e))?;
    if study_path.exists() {
        std::fs::rename(study_path, kept_name(study_path, n))
            .map_err(|e| io_err(study_path)(&e))?;
    }
    Ok(kept)
}

impl ResultsFile {
    /// Opens (or creates) `dir/results.csv` for `sweep`, with `dir/study.json`. A table of
    /// another study or model version (its study record or columns differ) is refused with
    /// what changed, or kept aside ([`OnChange::NewTable`]). Damaged rows are dropped (the
    /// file is rewritten without them, through a temporary file) so that they run again.
    pub fn open(dir: &Path, sweep: &Sweep, on_change: OnChange) -> Result<Self, SweepError> {
        let path = dir.join("results.csv");
        let study_path = dir.join("study.json");
        let columns = columns(sweep);
        let study = study_record(sweep);
        let mut report = OpenReport::default();
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(e) => return Err(io_err(&path)(&e)),
        };
        let mut rows = Vec::new();
        if !text.is_empty() {
            let stored: Option<BTreeMap<String, String>> = std::fs::read_to_string(&study_path)
                .ok()
                .and_then(|s| serde_json::from_str(&s).ok());
            let Table {
                header,
                rows: valid,
                dropped,
            } = read_rows(&text, &path)?;
            let changed: Vec<String> = match &stored {
                None => vec![format!(
                    "{} has no readable study record (a table of an older raceway)",
                    study_path.display()
                )],
                Some(old) => {
                    let mut d = differences(old, &study, 8);
                    if header != columns {
                        d.push("the columns (axes or kept metrics)".into());
                    }
                    d
                }
            };
            if changed.is_empty() {
                rows = valid;
                report.dropped = dropped;
            } else {
                match on_change {
                    OnChange::Refuse => {
                        return Err(SweepError::new(format!(
                            "{} holds results of another study or model version; what changed: \
                             {}. Rerun with --new-table to keep it as {} and start a new table, \
                             or use another --out folder",
                            path.display(),
                            changed.join("; "),
                            kept_name(&path, 1).display()
                        )))
                    }
                    OnChange::NewTable => {
                        report.kept_as = Some(keep_aside(&path, &study_path)?);
                    }
                }
            }
        }
        // The table as it stands: the header and the valid rows (rewritten only if rows were
        // dropped or the table is new).
        let fresh = rows.is_empty() && (text.is_empty() || report.kept_as.is_some());
        if fresh || report.dropped > 0 {
            let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
            w.write_record(&columns).map_err(|e| io_err(&path)(&e))?;
            for r in &rows {
                w.write_record(r).map_err(|e| io_err(&path)(&e))?;
            }
            let bytes = w.into_inner().map_err(|e| io_err(&path)(&e))?;
            replace_file(&path, &String::from_utf8_lossy(&bytes))?;
            let json = serde_json::to_string_pretty(&study).map_err(|e| io_err(&study_path)(&e))?;
            std::fs::write(&study_path, json + "\n").map_err(|e| io_err(&study_path)(&e))?;
        }
        let done = rows
            .into_iter()
            .map(|r| (r[1].clone(), r[2].clone()))
            .collect();
        let f = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| io_err(&path)(&e))?;
        Ok(Self {
            path,
            columns,
            done,
            writer: csv::WriterBuilder::new().has_headers(false).from_writer(f),
            report,
        })
    }

    /// What opening found (dropped rows, an old table kept aside).
    pub fn report(&self) -> &OpenReport {
        &self.report
    }

    /// Whether `run` is recorded with the key it has now.
    pub fn is_done(&self, sweep: &Sweep, run: &Run) -> bool {
        self.done
            .get(&run.id)
            .is_some_and(|k| *k == run_key(sweep, run))
    }

    /// Appends a row (one write of the whole line) and flushes it to the file.
    pub fn append(&mut self, row: &[String]) -> Result<(), SweepError> {
        let e = io_err(&self.path);
        self.writer.write_record(row).map_err(|x| e(&x))?;
        self.writer.flush().map_err(|x| e(&x))?;
        if let (Some(id), Some(key)) = (row.get(1), row.get(2)) {
            self.done.insert(id.clone(), key.clone());
        }
        Ok(())
    }

    /// Appends the rows of another results.csv of the same sweep (e.g. one task's of a
    /// distributed sweep) that this table does not have: read by the same reader (damaged
    /// rows dropped), each row's key checked against the run's key now. Returns how many were
    /// added.
    pub fn merge(&mut self, sweep: &Sweep, other: &Path) -> Result<usize, SweepError> {
        let text = std::fs::read_to_string(other).map_err(|e| io_err(other)(&e))?;
        let Table { header, rows, .. } = read_rows(&text, other)?;
        if header != self.columns {
            return Err(SweepError::new(format!(
                "{}: its columns are not this sweep's",
                other.display()
            )));
        }
        let runs = sweep.runs();
        let mut added = 0;
        for r in rows {
            let run = r[0]
                .parse::<usize>()
                .ok()
                .and_then(|i| runs.get(i))
                .filter(|run| run.id == r[1]);
            let Some(run) = run else {
                return Err(SweepError::new(format!(
                    "{}: run {} ({}) is not in this sweep's grid",
                    other.display(),
                    r[0],
                    r[1]
                )));
            };
            if r[2] != run_key(sweep, run) {
                return Err(SweepError::new(format!(
                    "{}: run {} was computed from another scene or model version (its run_key \
                     differs)",
                    other.display(),
                    r[0]
                )));
            }
            // (r[2] is the run's key now, checked above)
            if self.done.get(&run.id) != Some(&r[2]) {
                self.append(&r)?;
                added += 1;
            }
        }
        Ok(added)
    }
}

/// The header and rows of a results.csv in canonical form: sorted by run index, without the
/// `wall_s` column (the only column that depends on the machine and the thread count) and the
/// `check` that covers it.
pub fn canonical_rows(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>), SweepError> {
    let mut r = csv::Reader::from_path(path)
        .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
    let header: Vec<String> = r
        .headers()
        .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?
        .iter()
        .map(String::from)
        .collect();
    // wall_s depends on the machine and the thread count, and the check on wall_s.
    let drop: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| *h == "wall_s" || *h == CHECK)
        .map(|(i, _)| i)
        .collect();
    let strip = |v: Vec<String>| -> Vec<String> {
        v.into_iter()
            .enumerate()
            .filter(|(i, _)| !drop.contains(i))
            .map(|(_, s)| s)
            .collect()
    };
    let mut rows = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
        rows.push(strip(rec.iter().map(String::from).collect()));
    }
    rows.sort_by_key(|r| r.first().and_then(|s| s.parse::<usize>().ok()));
    Ok((strip(header), rows))
}

/// Writes a canonical copy of results.csv (sorted by run index, `wall_s` kept) to `dest`.
pub fn write_sorted(path: &Path, dest: &Path) -> Result<(), SweepError> {
    let mut r = csv::Reader::from_path(path)
        .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
    let header = r
        .headers()
        .map_err(|e| SweepError::new(e.to_string()))?
        .clone();
    let mut rows: Vec<csv::StringRecord> = r
        .records()
        .collect::<Result<_, _>>()
        .map_err(|e| SweepError::new(e.to_string()))?;
    rows.sort_by_key(|r| r.get(0).and_then(|s| s.parse::<usize>().ok()));
    let mut w = csv::Writer::from_path(dest)
        .map_err(|e| SweepError::new(format!("{}: {e}", dest.display())))?;
    w.write_record(&header)
        .map_err(|e| SweepError::new(e.to_string()))?;
    for row in rows {
        w.write_record(&row)
            .map_err(|e| SweepError::new(e.to_string()))?;
    }
    w.flush().map_err(|e| SweepError::new(e.to_string()))?;
    let _ = w.into_inner().map(|mut f| f.flush());
    Ok(())
}
