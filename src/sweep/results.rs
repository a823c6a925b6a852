//! `results.csv`: one row per finished run, appended as runs finish, read back to resume.
//!
//! Columns: `run_index, run_id, status (ok|failed), error, wall_s`, then one column per axis
//! key (the run's value, canonical text), then the metric columns of
//! [`metric_columns`]. Numbers are written as shortest round-trip
//! decimals, so equal values give equal text; metrics of a failed run are empty.

use super::metrics::{metric_columns, MetricRow};
use super::spec::{Run, Sweep};
use super::SweepError;
use std::collections::HashSet;
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The fixed leading columns.
pub const LEAD: [&str; 5] = ["run_index", "run_id", "status", "error", "wall_s"];

/// All columns of a sweep's results.csv.
pub fn columns(sweep: &Sweep) -> Vec<String> {
    LEAD.iter()
        .map(|s| s.to_string())
        .chain(sweep.axes.iter().map(|a| a.key.clone()))
        .chain(metric_columns(&sweep.keep))
        .collect()
}

/// The row of a finished run.
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
    [
        run.index.to_string(),
        run.id.clone(),
        status.to_string(),
        error,
        format!("{wall:.3}"),
    ]
    .into_iter()
    .chain(run.params.iter().map(|(_, v)| v.canonical()))
    .chain(metrics)
    .collect()
}

/// An open results.csv: the ids already recorded and an appending writer.
pub struct ResultsFile {
    path: PathBuf,
    done: HashSet<String>,
    writer: csv::Writer<std::fs::File>,
}

impl ResultsFile {
    /// Opens (or creates) `path` for a sweep with these columns. An existing file must have
    /// exactly these columns; a last line cut short by a kill is removed.
    pub fn open(path: &Path, columns: Vec<String>) -> Result<Self, SweepError> {
        let err = |e: std::io::Error| SweepError::new(format!("{}: {e}", path.display()));
        let mut f = std::fs::OpenOptions::new()
            .read(true)
            .append(true)
            .create(true)
            .open(path)
            .map_err(err)?;
        let mut text = String::new();
        f.read_to_string(&mut text).map_err(err)?;
        if !text.is_empty() && !text.ends_with('\n') {
            // A partial last row (killed mid-write): drop it so it is run again.
            let keep = text.rfind('\n').map_or(0, |i| i + 1);
            text.truncate(keep);
            f.set_len(keep as u64).map_err(err)?;
            f.seek(std::io::SeekFrom::End(0)).map_err(err)?;
        }
        let mut done = HashSet::new();
        let fresh = text.is_empty();
        if !fresh {
            let mut r = csv::ReaderBuilder::new().from_reader(text.as_bytes());
            let header: Vec<String> = r
                .headers()
                .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?
                .iter()
                .map(String::from)
                .collect();
            if header != columns {
                return Err(SweepError::new(format!(
                    "{} was written by a different sweep (its columns differ); use another --out \
                     folder or remove the file",
                    path.display()
                )));
            }
            for rec in r.records() {
                let rec = rec.map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
                if let Some(id) = rec.get(1) {
                    done.insert(id.to_string());
                }
            }
        }
        let mut writer = csv::WriterBuilder::new().has_headers(false).from_writer(f);
        if fresh {
            writer
                .write_record(&columns)
                .and_then(|_| writer.flush().map_err(csv::Error::from))
                .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
        }
        Ok(Self {
            path: path.to_path_buf(),
            done,
            writer,
        })
    }

    /// Ids of the runs already recorded (ok or failed).
    pub fn done(&self) -> &HashSet<String> {
        &self.done
    }

    /// Appends a row and flushes it to the file.
    pub fn append(&mut self, row: &[String]) -> Result<(), SweepError> {
        let e =
            |e: &dyn std::fmt::Display| SweepError::new(format!("{}: {e}", self.path.display()));
        self.writer.write_record(row).map_err(|x| e(&x))?;
        self.writer.flush().map_err(|x| e(&x))?;
        if let Some(id) = row.get(1) {
            self.done.insert(id.clone());
        }
        Ok(())
    }
}

/// The header and rows of a results.csv in canonical form: sorted by run index, without the
/// `wall_s` column (the only column that depends on the machine and the thread count).
pub fn canonical_rows(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>), SweepError> {
    let mut r = csv::Reader::from_path(path)
        .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?;
    let header: Vec<String> = r
        .headers()
        .map_err(|e| SweepError::new(format!("{}: {e}", path.display())))?
        .iter()
        .map(String::from)
        .collect();
    let wall = header.iter().position(|h| h == "wall_s");
    let strip = |v: Vec<String>| -> Vec<String> {
        v.into_iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != wall)
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
