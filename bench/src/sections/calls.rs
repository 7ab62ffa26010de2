//! The `calls` section: `rocking capacity` per call as a new process,
//! process start included, summarised over the far-field records.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use super::options::{BenchError, BenchOptions};
use super::records::far_field_files;
use crate::timing;

/// The budget of one `rocking capacity` call in a script's loop, process
/// start included.
pub const CALL_TARGET_MS: f64 = 3.0;

/// ε of the timed `capacity` calls.
const CALL_EPS: f64 = 0.7;

/// Calls of each command discarded before timing (the record and the
/// executable into the page cache).
const CALL_WARMUP: usize = 2;

/// Per-call times of one block over the records: each record's median.
#[derive(Debug, Clone, PartialEq)]
pub struct CallSummary {
    pub records: usize,
    /// Median over the records of their medians (ms).
    pub median_ms: f64,
    /// Mean of the records' medians (ms): one call per record, in all,
    /// divided by the number of records.
    pub mean_ms: f64,
    pub fastest_ms: f64,
    pub slowest_ms: f64,
    pub slowest_record: String,
    /// Records whose median is at most [`CALL_TARGET_MS`].
    pub within_target: usize,
}

/// Summarises each record's median time per call (ms); `None` without records.
pub fn summarise_calls(per_record: &[(String, f64)]) -> Option<CallSummary> {
    let mut ms: Vec<f64> = per_record.iter().map(|r| r.1).collect();
    let (slowest_record, slowest_ms) = per_record
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(r, t)| (r.clone(), *t))?;
    Some(CallSummary {
        records: ms.len(),
        median_ms: timing::median(&mut ms),
        mean_ms: ms.iter().sum::<f64>() / ms.len() as f64,
        fastest_ms: ms.iter().copied().fold(f64::INFINITY, f64::min),
        slowest_ms,
        slowest_record,
        within_target: per_record.iter().filter(|r| r.1 <= CALL_TARGET_MS).count(),
    })
}

/// Time of one call of `exe` with `args` (ms), from spawn to exit, its
/// output discarded; a call that fails is an error with its stderr.
fn time_call(exe: &Path, args: &[&std::ffi::OsStr]) -> Result<f64, BenchError> {
    use std::process::{Command, Stdio};
    let command = || {
        std::iter::once(exe.as_os_str())
            .chain(args.iter().copied())
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let t = Instant::now();
    let out = Command::new(exe)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .map_err(|source| BenchError::Spawn {
            command: command(),
            source,
        })?;
    let ms = t.elapsed().as_secs_f64() * 1e3;
    if !out.status.success() {
        return Err(BenchError::Call {
            command: command(),
            status: out.status.to_string(),
            stderr: String::from_utf8_lossy(&out.stderr).trim().to_string(),
        });
    }
    Ok(ms)
}

/// Each record's median time per call (ms) at each p, the blocks
/// alternating call by call.
fn per_record_times(
    exe: &Path,
    files: &[std::path::PathBuf],
    p_text: &[String],
    eps: &str,
    reps: usize,
    say: &mut impl FnMut(&str),
) -> Result<Vec<Vec<(String, f64)>>, BenchError> {
    use std::ffi::OsStr;
    let ps = p_text;
    let mut per_p: Vec<Vec<(String, f64)>> = vec![Vec::new(); ps.len()];
    for (i, file) in files.iter().enumerate() {
        let stem = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        say(&format!("calls: {stem} ({}/{})", i + 1, files.len()));
        let call = |p: &str| {
            let a: [&OsStr; 7] = [
                OsStr::new("capacity"),
                OsStr::new("--record"),
                file.as_os_str(),
                OsStr::new("--p"),
                OsStr::new(p),
                OsStr::new("--eps"),
                OsStr::new(eps),
            ];
            time_call(exe, &a)
        };
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); ps.len()];
        for rep in 0..CALL_WARMUP + reps {
            for (j, p) in p_text.iter().enumerate() {
                let ms = call(p)?;
                if rep >= CALL_WARMUP {
                    times[j].push(ms);
                }
            }
        }
        for (j, mut t) in times.into_iter().enumerate() {
            per_p[j].push((stem.clone(), timing::median(&mut t)));
        }
    }
    Ok(per_p)
}

/// One `rocking capacity` call over every file at each p: the median (ms)
/// of `reps` calls, after the warm-up.
fn batch_times(
    exe: &Path,
    files: &[std::path::PathBuf],
    ps: &[String],
    eps: &str,
    reps: usize,
) -> Result<Vec<f64>, BenchError> {
    use std::ffi::OsStr;
    ps.iter()
        .map(|p| {
            let mut a: Vec<&OsStr> = vec![OsStr::new("capacity"), OsStr::new("--record")];
            a.extend(files.iter().map(|f| f.as_os_str()));
            a.extend([
                OsStr::new("--p"),
                OsStr::new(p.as_str()),
                OsStr::new("--eps"),
                OsStr::new(eps),
                OsStr::new("--json"),
            ]);
            for _ in 0..CALL_WARMUP {
                time_call(exe, &a)?;
            }
            let mut t: Vec<f64> = (0..reps)
                .map(|_| time_call(exe, &a))
                .collect::<Result<_, _>>()?;
            Ok(timing::median(&mut t))
        })
        .collect()
}

/// `rocking capacity` on each far-field record as a new process, as a
/// script calling it in a loop would: each record's median of `reps` calls
/// at each p (the blocks alternate call by call, so a slow spell of the
/// machine weighs on all alike), and `rocking --version`, the process alone.
pub(super) fn calls_table(
    args: &BenchOptions,
    say: &mut impl FnMut(&str),
) -> Result<String, BenchError> {
    use std::ffi::OsStr;
    let files = far_field_files(args)?;
    let files = if args.quick {
        &files[..files.len().min(3)]
    } else {
        &files[..]
    };
    let ps: &[f64] = if args.quick { &[2.0] } else { &[0.5, 2.0, 8.0] };
    let exe = &args.exe;
    let version = [OsStr::new("--version")];
    for _ in 0..CALL_WARMUP {
        time_call(exe, &version)?;
    }
    let mut alone: Vec<f64> = (0..args.reps.max(20))
        .map(|_| time_call(exe, &version))
        .collect::<Result<_, _>>()?;
    let alone_ms = timing::median(&mut alone);
    let p_text: Vec<String> = ps.iter().map(|p| p.to_string()).collect();
    let eps = CALL_EPS.to_string();
    let per_p = per_record_times(exe, files, &p_text, &eps, args.reps, say)?;
    say("calls: one batch call over the records");
    let batch_ms = batch_times(exe, files, &p_text, &eps, args.reps)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## `rocking capacity` per call, process start included
"
    );
    let _ = writeln!(
        s,
        "Each far-field record's median of {} calls (after {CALL_WARMUP} warm-up calls) of \
         `rocking capacity --record R --p P --eps {CALL_EPS}`, each a new process timed from spawn \
         to exit by `rocking-bench`, its output discarded; the blocks alternate call by call; \
         the loop is those calls added up, one per record. The batch is one call over all the \
         records (`--record R1 R2 … --json`, the same capacities), median of {} calls. The \
         process alone (`rocking --version`, median \
         of {}): {alone_ms:.2} ms.\n",
        args.reps,
        args.reps,
        alone.len()
    );
    let _ = writeln!(
        s,
        "| p (1/s) | records | median over the records | mean | fastest | slowest | within {CALL_TARGET_MS} ms | loop | batch |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---|---:|---:|---:|");
    for ((p, rows), batch) in ps.iter().zip(&per_p).zip(&batch_ms) {
        if let Some(c) = summarise_calls(rows) {
            let _ = writeln!(
                s,
                "| {p} | {} | {:.2} ms | {:.2} ms | {:.2} ms | {:.2} ms ({}) | {} of {} | {:.0} ms | {batch:.0} ms |",
                c.records,
                c.median_ms,
                c.mean_ms,
                c.fastest_ms,
                c.slowest_ms,
                c.slowest_record,
                c.within_target,
                c.records,
                c.mean_ms * c.records as f64
            );
        }
    }
    s.push('\n');
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::summarise_calls;

    /// Hand-worked: four records' medians 2, 3, 3.5 and 1 ms.
    #[test]
    fn call_times_are_summarised_over_the_records() {
        let rows: Vec<(String, f64)> = [("a", 2.0), ("b", 3.0), ("c", 3.5), ("d", 1.0)]
            .iter()
            .map(|&(r, t)| (r.to_string(), t))
            .collect();
        let c = summarise_calls(&rows).unwrap();
        assert_eq!(c.records, 4);
        // The median of an even count is the mean of the middle two.
        assert_eq!(c.median_ms, 2.5);
        // (2 + 3 + 3.5 + 1) / 4, exact in binary.
        assert_eq!(c.mean_ms, 2.375);
        assert_eq!((c.fastest_ms, c.slowest_ms), (1.0, 3.5));
        assert_eq!(c.slowest_record, "c");
        // 3 ms exactly is within the target.
        assert_eq!(c.within_target, 3);
        assert_eq!(summarise_calls(&[]), None);
    }
}
