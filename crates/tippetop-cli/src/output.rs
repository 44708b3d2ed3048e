//! Writing results to disk: atomic file writes, CSV with shortest round-trip
//! floats, pretty JSON, and the `summary.json` document of a run.
//!
//! Every file goes through [`write_atomic`]: it is written to `DIR/.NAME.tmp`
//! and renamed over `DIR/NAME`, so a reader never sees half a file and a
//! failed write leaves any previous version in place.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::Serialize;
use tippetop::trajectory::COLUMNS;
use tippetop::{EventRecord, Summary, Trajectory};

/// The temporary path [`write_atomic`] writes to before renaming:
/// `DIR/.NAME.tmp` next to `path`.
pub fn tmp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    path.with_file_name(format!(".{name}.tmp"))
}

/// Write `path` atomically: `fill` writes the contents into a buffered
/// `DIR/.NAME.tmp`, which is flushed and renamed to `path`. On any error
/// the temporary file is removed and `path` is left as it was. A process
/// that is interrupted never leaves a half-written `path` (the rename is
/// atomic). The file is not fsync'ed: that would guard only against power
/// loss, at a cost of milliseconds per file (more than a whole simulation).
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    let tmp = tmp_path(path);
    let result = (|| -> io::Result<()> {
        let mut w = BufWriter::new(File::create(&tmp)?);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("writing {}", path.display()));
    }
    Ok(())
}

/// Write `bytes` to `path` atomically (see [`write_atomic`]).
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |w| w.write_all(bytes))
}

/// Shortest decimal text that parses back to exactly `v` (via `zmij`, a
/// shortest-round-trip formatter about twice as fast as `ryu` with the same
/// digits): `0.1`, `1.196e-24`, `-30000000.0`, `5e-324`, `1e+300`; `NaN`,
/// `inf`, `-inf` for non-finite values (all accepted by `str::parse::<f64>`
/// and by every CSV reader).
pub fn fmt_f64(v: f64) -> String {
    let mut buf = zmij::Buffer::new();
    buf.format(v).to_string()
}

/// Append [`fmt_f64`]`(v)` to `out` without an intermediate allocation.
fn push_f64(out: &mut String, v: f64) {
    let mut buf = zmij::Buffer::new();
    out.push_str(buf.format(v));
}

/// The CSV header line of `trajectory.csv`: [`COLUMNS`] joined by commas.
pub fn trajectory_header() -> String {
    COLUMNS.join(",")
}

/// Write a trajectory as CSV: the [`COLUMNS`] header, then one row per
/// sample, floats in shortest round-trip form, `rolling` as `0`/`1`.
pub fn write_trajectory_csv(path: &Path, traj: &Trajectory) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{}", trajectory_header())?;
        let mut line = String::with_capacity(400);
        for s in &traj.samples {
            line.clear();
            let vals = s.values();
            for (i, v) in vals[..vals.len() - 1].iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                push_f64(&mut line, *v);
            }
            line.push(',');
            line.push_str(if s.rolling != 0 { "1" } else { "0" });
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    })
}

/// Write figure data as CSV: `headers[i]` names `columns[i]` (by convention
/// the first column is `t`, then one column per curve). All columns must have
/// the same length; NaN is written as an empty field (a missing value), other
/// numbers in shortest round-trip form. Headers must not contain commas,
/// quotes or newlines.
pub fn write_series_csv(path: &Path, headers: &[&str], columns: &[&[f64]]) -> Result<()> {
    if headers.len() != columns.len() {
        bail!(
            "{}: {} headers for {} columns",
            path.display(),
            headers.len(),
            columns.len()
        );
    }
    if let Some(h) = headers.iter().find(|h| h.contains([',', '"', '\n', '\r'])) {
        bail!("{}: header {h:?} needs quoting", path.display());
    }
    let n = columns.first().map_or(0, |c| c.len());
    if let Some((i, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        bail!(
            "{}: column {:?} has {} values, expected {n}",
            path.display(),
            headers[i],
            c.len()
        );
    }
    write_atomic(path, |w| {
        writeln!(w, "{}", headers.join(","))?;
        let mut line = String::with_capacity(32 * columns.len());
        for row in 0..n {
            line.clear();
            for (i, c) in columns.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                let v = c[row];
                if !v.is_nan() {
                    push_f64(&mut line, v);
                }
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    })
}

/// Write `value` as pretty-printed JSON (trailing newline), atomically.
/// `None` becomes `null`; serde_json also writes non-finite floats as `null`.
pub fn write_json_pretty<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value)
        .with_context(|| format!("serializing {}", path.display()))?;
    text.push('\n');
    write_bytes_atomic(path, text.as_bytes())
}

/// The `summary.json` document of a run: every [`Summary`] field at the top
/// level, plus `wall_seconds`, the resolved `scenario` (as TOML text) and the
/// `events`.
#[derive(Debug, Serialize)]
pub struct SummaryDoc<'a> {
    /// The library's summary, flattened into the top level.
    #[serde(flatten)]
    pub summary: &'a Summary,
    /// Wall-clock time of the simulation \[s\].
    pub wall_seconds: f64,
    /// The resolved scenario as TOML (what `scenario.toml` holds).
    pub scenario: &'a str,
    /// Events in time order, each `{t, kind}`.
    pub events: &'a [EventRecord],
}

impl<'a> SummaryDoc<'a> {
    /// The document for `traj`. If the run failed and the library left
    /// `status` at `"ok"`, the caller should pass a summary whose `status`
    /// is the error (see [`summary_with_status`]).
    pub fn new(
        summary: &'a Summary,
        events: &'a [EventRecord],
        scenario_toml: &'a str,
        wall_seconds: f64,
    ) -> Self {
        SummaryDoc {
            summary,
            wall_seconds,
            scenario: scenario_toml,
            events,
        }
    }
}

/// `traj.summary`, with `status` set to the run-time error's message when the
/// run failed (and the library did not already say so).
pub fn summary_with_status(traj: &Trajectory) -> Summary {
    let mut s = traj.summary.clone();
    if let Some(e) = &traj.error {
        if s.status.is_empty() || s.status == "ok" {
            s.status = e.to_string();
        }
    }
    s
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use tippetop::{Error, Sample};

    /// A hand-built trajectory (simulate is not available to unit tests):
    /// `n` samples over `[0, t_end]` of a top that flips from 0.1 to ~π.
    pub(crate) fn fake_trajectory(n: usize, t_end: f64, failed: bool) -> Trajectory {
        let samples: Vec<Sample> = (0..n)
            .map(|i| {
                let t = t_end * i as f64 / (n - 1) as f64;
                let x = t / t_end;
                let theta = 0.1 + (std::f64::consts::PI - 0.15) / (1.0 + (-12.0 * (x - 0.5)).exp());
                Sample {
                    t,
                    theta,
                    theta_dot: 0.3 * (20.0 * x).sin(),
                    precession: 150.0 * (x * 3.0).sin(),
                    spin: 100.0 * (1.0 - 1.8 * x),
                    ux: 1e-12 * x,
                    uy: -1e-12 * x,
                    uz: 0.0,
                    normal: 1.172e-23 * (1.0 + 0.2 * (30.0 * x).sin()),
                    slip: 1e-10 * (1.0 - x),
                    jellett: 3.0e-40 * (1.0 + 1e-9 * (5.0 * x).sin()),
                    energy: 1.0e-20 - 2e-21 * x,
                    work_friction: -2e-21 * x,
                    work_applied: 0.0,
                    hx: 1e-22,
                    hy: 1e-22,
                    rolling: u8::from(i % 7 == 0),
                }
            })
            .collect();
        let last = *samples.last().unwrap();
        let error = failed.then(|| Error::runtime(last.t, "step size underflow"));
        Trajectory {
            events: vec![EventRecord {
                t: 0.5 * t_end,
                kind: "theta_above_half_pi".into(),
            }],
            summary: Summary {
                t_end: last.t,
                theta_final: last.theta,
                theta_max: last.theta,
                omega_final: last.spin,
                precession_final: last.precession,
                jellett_initial: samples[0].jellett,
                jellett_max_rel_drift: 1.2e-9,
                energy_initial: samples[0].energy,
                energy_final: last.energy,
                energy_balance_max_rel_error: 3e-11,
                first_time_theta_above_half_pi: Some(0.5 * t_end),
                contact_lost_at: None,
                negative_normal_fraction: 0.0,
                rolling_fraction: 0.14,
                steps: 1234,
                rejected_steps: 5,
                rhs_evaluations: 15000,
                status: "ok".into(),
            },
            samples,
            error,
        }
    }

    #[test]
    fn floats_round_trip_exactly() {
        let cases = [
            1.196e-24,
            0.1,
            -3.0e7,
            5e-324,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            -0.0,
            0.0,
            std::f64::consts::PI,
            1.0 / 3.0,
            2.0f64.sqrt() * 1e-10,
            123_456_789.123_456_79,
        ];
        for v in cases {
            let s = fmt_f64(v);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e} -> {s}");
        }
        assert_eq!(fmt_f64(0.1), "0.1");
        assert_eq!(fmt_f64(1.196e-24), "1.196e-24");
        assert_eq!(fmt_f64(5e-324), "5e-324");
        assert_eq!(fmt_f64(1e300), "1e+300");
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let back: f64 = fmt_f64(v).parse().unwrap();
            assert!(back.is_nan() == v.is_nan() && (v.is_nan() || back == v));
        }
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_tmp() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_bytes_atomic(&p, b"first").unwrap();
        write_bytes_atomic(&p, b"second").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "second");
        assert!(!tmp_path(&p).exists());
        assert_eq!(tmp_path(&p), dir.path().join(".a.txt.tmp"));
        let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }

    #[test]
    fn atomic_write_failure_keeps_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_bytes_atomic(&p, b"old").unwrap();
        let err = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("boom"));
        assert_eq!(fs::read_to_string(&p).unwrap(), "old");
        assert!(!tmp_path(&p).exists());
        // A missing directory is an error, not a panic.
        assert!(write_bytes_atomic(&dir.path().join("no/such/file"), b"x").is_err());
    }

    #[test]
    fn trajectory_csv_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("trajectory.csv");
        let traj = fake_trajectory(11, 1e-4, false);
        write_trajectory_csv(&p, &traj).unwrap();
        let text = fs::read_to_string(&p).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap();
        assert!(header.starts_with("t,theta,theta_dot,Omega,omega,ux,uy,uz,N,slip,J,energy"));
        assert_eq!(header, COLUMNS.join(","));
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), traj.samples.len());
        for (row, s) in rows.iter().zip(&traj.samples) {
            let fields: Vec<&str> = row.split(',').collect();
            assert_eq!(fields.len(), COLUMNS.len());
            let vals = s.values();
            for (f, v) in fields.iter().zip(vals) {
                assert_eq!(f.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{f}");
            }
            assert!(matches!(*fields.last().unwrap(), "0" | "1"));
        }
    }

    #[test]
    fn series_csv_missing_and_mismatch() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("fig.csv");
        let t = [0.0, 0.5, 1.0];
        let a = [1.196e-24, f64::NAN, -3.0e7];
        write_series_csv(&p, &["t", "a"], &[&t, &a]).unwrap();
        assert_eq!(
            fs::read_to_string(&p).unwrap(),
            "t,a\n0.0,1.196e-24\n0.5,\n1.0,-30000000.0\n"
        );
        let short = [1.0];
        assert!(write_series_csv(&p, &["t", "b"], &[&t, &short]).is_err());
        assert!(write_series_csv(&p, &["t"], &[&t, &a]).is_err());
        assert!(write_series_csv(&p, &["t", "a,b"], &[&t, &a]).is_err());
        // The failed writes left the good file alone.
        assert!(fs::read_to_string(&p).unwrap().starts_with("t,a\n"));
    }

    #[test]
    fn summary_doc_has_all_fields() {
        let traj = fake_trajectory(5, 1.0, true);
        let summary = summary_with_status(&traj);
        assert!(summary.status.contains("step size underflow"));
        let doc = SummaryDoc::new(&summary, &traj.events, "[top]\nradius = 0.015\n", 0.25);
        let v = serde_json::to_value(&doc).unwrap();
        for key in [
            "t_end",
            "theta_final",
            "theta_max",
            "omega_final",
            "Omega_final",
            "J_initial",
            "J_max_rel_drift",
            "energy_initial",
            "energy_final",
            "energy_balance_max_rel_error",
            "first_time_theta_above_half_pi",
            "contact_lost_at",
            "negative_normal_fraction",
            "rolling_fraction",
            "steps",
            "rejected_steps",
            "rhs_evaluations",
            "status",
            "wall_seconds",
            "scenario",
            "events",
        ] {
            assert!(v.get(key).is_some(), "missing {key}");
        }
        assert!(v["contact_lost_at"].is_null());
        assert_eq!(v["events"][0]["kind"], "theta_above_half_pi");
        assert_eq!(v["events"][0]["t"], 0.5);
        assert_eq!(v["wall_seconds"], 0.25);
    }
}
