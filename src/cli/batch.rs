//! `lplace eval` over several streams or a folder: each stream evaluated on its own (a fresh
//! tracker, the same engine), then one summary row per stream and a total
//! ([`crate::report::batch`]) in the `--format` asked for (a table by default).

use super::args::{ArgError, EvalArgs, Format};
use super::eval::{evaluate, new_run, open_source};
use super::{output, CliError, EXIT_OK, EXIT_REJECTED};
use crate::report::batch::{self, BatchRow};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The streams named on the command line, each looked up under `$LPLACE_DATA` when not found
/// here, a folder replaced by its `.jsonl` and `.csv` files in name order.
pub fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, CliError> {
    let mut out = Vec::new();
    for p in paths {
        let p = super::data::resolve(p);
        if !p.is_dir() {
            out.push(p);
            continue;
        }
        let read_err = |source| CliError::Read {
            path: p.display().to_string(),
            source,
        };
        let mut files = Vec::new();
        for entry in std::fs::read_dir(&p).map_err(read_err)? {
            let f = entry.map_err(read_err)?.path();
            let ext = f.extension().and_then(|e| e.to_str());
            if f.is_file() && matches!(ext, Some("jsonl" | "csv")) {
                files.push(f);
            }
        }
        if files.is_empty() {
            return Err(ArgError::EmptyFolder(p.display().to_string()).into());
        }
        files.sort();
        out.extend(files);
    }
    Ok(out)
}

/// Evaluates every stream and prints the table; exit 3 when any stream had rejected records.
pub fn run(args: &EvalArgs, streams: &[PathBuf], out: &mut impl Write) -> Result<u8, CliError> {
    for (flag, set) in [
        ("--svg", args.svg().is_some()),
        ("--trajectory-svg", args.trajectory_svg().is_some()),
        ("--degrees", args.degrees),
        ("--query", !args.query.is_empty()),
        ("--labels", args.labels.is_some()),
    ] {
        if set {
            return Err(ArgError::NotInBatch(flag).into());
        }
    }
    let template = new_run(args)?;
    let bar = super::progress::steps(streams.len() as u64, "streams");
    let mut rows = Vec::with_capacity(streams.len());
    for path in streams {
        let mut run = template.clone();
        let mut source = open_source(Some(path), args.input)?;
        source.time = args.time.into();
        let name = source.name.clone();
        evaluate(&mut run, source, |_, _, _| Ok(()))?;
        rows.push(BatchRow::new(name, &run.summary()));
        if let Some(b) = &bar {
            b.inc(1);
        }
    }
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let total = BatchRow::total(&rows);
    let format = args.format.unwrap_or(Format::Table);
    match &args.output {
        Some(p) => output::write_atomic(p, |w| write_rows(format, &rows, &total, w))?,
        None => write_rows(format, &rows, &total, out)?,
    }
    Ok(if total.rejected > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

fn write_rows(
    format: Format,
    rows: &[BatchRow],
    total: &BatchRow,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    match format {
        Format::Table => batch::write_table(rows, total, out),
        Format::Csv => batch::write_csv(rows, total, out),
        Format::Json => {
            let v = serde_json::json!({ "streams": rows, "total": total });
            serde_json::to_writer_pretty(&mut *out, &v).map_err(std::io::Error::from)?;
            writeln!(out)
        }
        Format::Jsonl => {
            for r in rows.iter().chain([total]) {
                serde_json::to_writer(&mut *out, r).map_err(std::io::Error::from)?;
                writeln!(out)?;
            }
            Ok(())
        }
    }
}

/// Whether `path` names a folder of streams (for the caller's choice of mode).
pub fn is_folder(path: &Path) -> bool {
    super::data::resolve(path).is_dir()
}
