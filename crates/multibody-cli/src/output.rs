//! The files a run writes: checked before the run, streamed while it goes,
//! and put in place only when complete. A result file is written under a
//! temporary name in its folder and renamed at the end, so that no reader
//! ever sees half a file and an earlier result is replaced only by a
//! complete one. A run that stops part way keeps what it computed under a
//! name that says so (`results.partial.csv`).

use crate::exit::Failure;
use crate::table::{Format, TableWriter};
use multibody::{Mechanism, SampleSink, SimulationOptions, Solution};
pub use multibody_dyad::study::bytes;
use multibody_dyad::study::count;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Bytes a CSV row takes per value, about (`-0.12345678901234567,`).
const CSV_BYTES_PER_VALUE: f64 = 20.0;

/// The paths of a run's results, checked: none writes over a model file
/// read, no two are the same, and the views' formats are known.
pub struct ResultFiles {
    pub csv: PathBuf,
    pub animate: Option<PathBuf>,
    pub plot: Option<PathBuf>,
}

impl ResultFiles {
    pub fn new(inputs: &[PathBuf], csv: &Path, animate: Option<&Path>, plot: Option<&Path>) -> Result<Self, Failure> {
        let outputs = [("--out", Some(csv)), ("--animate", animate), ("--plot", plot)];
        outputs_are_safe(inputs, &outputs)?;
        // A table is CSV or Parquet: another name would get CSV text under it.
        let extension = csv.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        if extension.as_deref().is_some_and(|e| !matches!(e, "csv" | "parquet" | "pq")) {
            return Err(Failure::Usage(format!(
                "`--out {}`: results are written as CSV or Parquet; name the file .csv or .parquet",
                csv.display()
            )));
        }
        if let Some(plot) = plot {
            if multibody_view::PlotFormat::from_path(plot).is_none() {
                return Err(Failure::Usage(format!(
                    "`--plot {}`: cannot tell the plot format; name the file .png or .svg",
                    plot.display()
                )));
            }
        }
        Ok(Self { csv: csv.to_path_buf(), animate: animate.map(Path::to_path_buf), plot: plot.map(Path::to_path_buf) })
    }
}

/// `results.csv` -> `results.partial.csv`: where a run that stopped part
/// way keeps what it computed, beside (not over) an earlier complete result.
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map_or_else(|| "results".into(), |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(ext) => format!("{stem}.partial.{}", ext.to_string_lossy()),
        None => format!("{stem}.partial"),
    };
    path.with_file_name(name)
}

/// Writes a file whole or not at all: into a temporary file in the same
/// folder, renamed to `path` once `write` succeeded.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<(), Failure> {
    let io = |e: std::io::Error| cannot_write(path, &e);
    let file = temporary_beside(path).map_err(io)?;
    let mut writer = BufWriter::new(file);
    write(&mut writer).map_err(io)?;
    let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
    file.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

/// Writes a table (CSV or Parquet, by the extension of `path`) as `fill`
/// streams its rows, with `keys` columns before `time` and then `names`,
/// under a temporary name: renamed to `path` when `fill` says it is
/// complete, to [`partial_path`] of it when the work stopped part way.
/// Returns the name.
pub fn write_table_streaming(
    path: &Path,
    keys: &[&str],
    names: &[&str],
    fill: impl FnOnce(&mut TableWriter) -> std::io::Result<bool>,
) -> Result<PathBuf, Failure> {
    let io = |e: std::io::Error| cannot_write(path, &e);
    let file = temporary_beside(path).map_err(io)?;
    let mut table = TableWriter::new(Format::of(path), file, keys, names).map_err(io)?;
    let complete = fill(&mut table).map_err(io)?;
    let name = if complete { path.to_path_buf() } else { partial_path(path) };
    table.finish().map_err(io)?.persist(&name).map_err(|e| io(e.error))?;
    Ok(name)
}

/// The failure of writing `path`.
pub fn cannot_write(path: &Path, e: &std::io::Error) -> Failure {
    Failure::Io(format!("cannot write {}: {}", path.display(), write_error(e)))
}

/// What went wrong in a write: the system's error, or for a file that
/// passed the file size limit (EFBIG, `ulimit -f`; SIGXFSZ is ignored at
/// startup, see `main`), the limit and what to do.
pub fn write_error(e: &std::io::Error) -> String {
    if e.kind() != std::io::ErrorKind::FileTooLarge {
        return e.to_string();
    }
    let limit = file_size_limit().map_or(String::new(), |b| format!(", {}", bytes(b)));
    format!(
        "it reached the file size limit of this process (`ulimit -f`{limit}); raise the limit (`ulimit -f \
         unlimited`), or write less"
    )
}

/// The most bytes this process may write to a file, when it is limited.
fn file_size_limit() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
        // SAFETY: getrlimit writes the struct it is given, nothing else.
        let got = unsafe { libc::getrlimit(libc::RLIMIT_FSIZE, &mut limit) };
        (got == 0 && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur as f64)
    }
    #[cfg(not(unix))]
    None
}

/// A temporary file in the folder of `path` (created if missing), readable
/// like any result file once renamed. It is deleted if never persisted.
fn temporary_beside(path: &Path) -> std::io::Result<NamedTempFile> {
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&folder)?;
    let name = path.file_name().map_or_else(|| "result".into(), |n| n.to_string_lossy().into_owned());
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    builder.tempfile_in(folder)
}

/// What a run may use: memory for the samples the views need, and disk
/// for the CSV.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Bytes of samples a run may keep in memory.
    pub memory: f64,
}

impl Budget {
    /// Half the memory this machine has available now.
    pub fn of_this_machine() -> Self {
        Self { memory: multibody_dyad::study::memory_budget() }
    }

    /// Refuses, before it starts, a run whose output grid cannot fit: the
    /// samples the views keep in memory, or the CSV on its disk. (With
    /// `saveat = 0` the number of samples is not known in advance; the
    /// streaming sink then stops the run when the views reach the budget.)
    pub fn check(
        &self,
        options: &SimulationOptions,
        all_signals: usize,
        written_signals: usize,
        views: bool,
        csv: &Path,
    ) -> Result<(), Failure> {
        let Some(samples) = multibody_dyad::study::grid_samples(options) else { return Ok(()) };
        let advice = "raise --saveat, shorten --stop, or write fewer --signals";
        if views {
            let memory = samples * (all_signals + 1) as f64 * 8.0;
            if memory > self.memory {
                return Err(Failure::Usage(format!(
                    "the animation and plot need every signal in memory: {} samples × {all_signals} signals take \
                     {}, more than the {} this run may use (half the memory available); {advice}, or leave out \
                     --animate and --plot (the CSV alone is streamed to disk)",
                    count(samples),
                    bytes(memory),
                    bytes(self.memory)
                )));
            }
        }
        let format = Format::of(csv);
        let table = TableWriter::memory(format, samples, written_signals + 1);
        if table > self.memory {
            return Err(Failure::Usage(format!(
                "writing Parquet of {} columns would hold about {} in memory ({} samples), more than the {} this \
                 run may use (half the memory available); write CSV instead (it streams), or {advice}",
                written_signals + 1,
                bytes(table),
                count(samples),
                bytes(self.memory)
            )));
        }
        let disk = samples * (written_signals + 1) as f64 * CSV_BYTES_PER_VALUE;
        let folder = csv.parent().filter(|f| !f.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let folder = folder.ancestors().find(|f| f.exists()).unwrap_or(Path::new("."));
        if let Ok(free) = fs4::available_space(folder) {
            if disk > free as f64 {
                return Err(Failure::Usage(format!(
                    "the CSV would take about {} ({} samples × {written_signals} signals), and {} has {} free; \
                     {advice}",
                    bytes(disk),
                    count(samples),
                    folder.display(),
                    bytes(free as f64)
                )));
            }
        }
        Ok(())
    }
}

/// The table of a run (CSV or Parquet), written as the samples come
/// (memory does not grow with the run), with every signal kept in memory
/// too when the views need them.
pub struct StreamingCsv {
    csv: Option<TableWriter>,
    /// The file the table is for, named when a write fails during the run.
    path: PathBuf,
    /// Column of each written signal in the full row.
    picks: Vec<usize>,
    values: Vec<f64>,
    error: Option<std::io::Error>,
    kept: Kept,
    /// Bytes the kept solution may take.
    memory: f64,
}

/// What a streamed run leaves besides its file.
#[derive(Default)]
pub struct Kept {
    pub samples: usize,
    /// First and last time written.
    pub span: Option<(f64, f64)>,
    /// The written signals at the last sample, by name.
    pub last_row: Vec<(String, f64)>,
    /// Every signal at every sample, when the views need them.
    pub solution: Option<Solution>,
    names: Vec<String>,
    /// The written signals at the last sample.
    last: Vec<f64>,
}

impl StreamingCsv {
    /// Starts the CSV (header) under a temporary name beside `path`;
    /// `keep` is the memory budget for keeping every signal for the views.
    pub fn create(path: &Path, mechanism: &Mechanism, signals: &[String], keep: Option<f64>) -> Result<Self, Failure> {
        let io = |e: std::io::Error| cannot_write(path, &e);
        let all = mechanism.signals();
        let names: Vec<String> = all.iter().map(|s| s.name.clone()).collect();
        let index: std::collections::HashMap<&str, usize> =
            names.iter().enumerate().map(|(k, n)| (n.as_str(), k)).collect();
        let picks: Vec<usize> = signals.iter().filter_map(|s| index.get(s.as_str()).copied()).collect();
        let header: Vec<&str> = picks.iter().map(|&k| names[k].as_str()).collect();
        let file = temporary_beside(path).map_err(io)?;
        let csv = TableWriter::new(Format::of(path), file, &[], &header).map_err(io)?;
        let solution = keep.map(|_| Solution::new(names.clone(), all.iter().map(|s| s.unit).collect()));
        Ok(Self {
            csv: Some(csv),
            path: path.to_path_buf(),
            values: vec![0.0; picks.len()],
            picks,
            error: None,
            kept: Kept { solution, names, ..Kept::default() },
            memory: keep.unwrap_or(f64::INFINITY),
        })
    }

    /// Puts the CSV in place at `path` (the final or the partial name) and
    /// gives what was kept. A write error during the run is reported here;
    /// the temporary file is removed then.
    pub fn finish(&mut self, path: &Path) -> Result<Kept, Failure> {
        let io = |e: std::io::Error| cannot_write(path, &e);
        let csv = self.csv.take().expect("the CSV is finished once");
        if let Some(e) = self.error.take() {
            // Failed during the run: the file it was for, not the name it would have been kept under.
            return Err(cannot_write(&self.path, &e));
        }
        csv.finish().map_err(io)?.persist(path).map_err(|e| io(e.error))?;
        let mut kept = std::mem::take(&mut self.kept);
        kept.last_row = self.picks.iter().map(|&k| kept.names[k].clone()).zip(kept.last.iter().copied()).collect();
        Ok(kept)
    }
}

impl SampleSink for StreamingCsv {
    /// The written signals alone, unless the views need every signal.
    fn columns(&self) -> Option<&[usize]> {
        self.kept.solution.is_none().then_some(self.picks.as_slice())
    }

    fn sample(&mut self, t: f64, row: &[f64]) -> Result<(), String> {
        for (v, &k) in self.values.iter_mut().zip(&self.picks) {
            *v = row[k];
        }
        let csv = self.csv.as_mut().expect("samples come before the CSV is finished");
        if let Err(e) = csv.row(&[], t, &self.values) {
            // The file and what to do are said when the run has ended.
            let reason = match e.kind() {
                std::io::ErrorKind::FileTooLarge => "cannot write the CSV: it reached the file size limit".to_string(),
                _ => format!("cannot write the CSV: {e}"),
            };
            self.error = Some(e);
            return Err(reason);
        }
        let kept = &mut self.kept;
        kept.samples += 1;
        kept.span = Some((kept.span.map_or(t, |(first, _)| first), t));
        kept.last.clear();
        kept.last.extend_from_slice(&self.values);
        if let Some(solution) = &mut kept.solution {
            if (solution.len() + 1) as f64 * (row.len() + 1) as f64 * 8.0 > self.memory {
                return Err(format!(
                    "the animation and plot would need more than {} of memory for their samples; rerun with a \
                     larger --saveat, or without --animate and --plot (the CSV alone is streamed to disk)",
                    bytes(self.memory)
                ));
            }
            solution.push(t, row);
        }
        Ok(())
    }
}

/// Refuses, before anything is computed, an output that would write over
/// one of the model files read or over another output of the same run,
/// under its own name or under the `.partial` name a run that stops part
/// way writes (`--out r.dyad` would keep a failed run as `r.partial.dyad`);
/// and an output that names something other than a regular file (a
/// folder, a device such as `/dev/null`, a FIFO), which a result renamed
/// into place would replace. Only `.dyad` files in an input folder count
/// as inputs: a rerun in a model folder may replace its own earlier results.
pub fn outputs_are_safe(inputs: &[PathBuf], outputs: &[(&str, Option<&Path>)]) -> Result<(), Failure> {
    let mut read = Vec::new();
    for input in inputs {
        match std::fs::read_dir(input) {
            Ok(entries) => {
                let models = entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "dyad"));
                read.extend(models)
            }
            Err(_) => read.push(input.clone()),
        }
    }
    let read: Vec<(PathBuf, &PathBuf)> = read.iter().map(|i| (comparable(i), i)).collect();
    // Every name each output may be written under: its own, then its partial one.
    let mut written: Vec<(&str, &Path, PathBuf)> = Vec::new();
    for &(option, path) in outputs {
        let Some(path) = path else { continue };
        for (k, name) in [path.to_path_buf(), partial_path(path)].into_iter().enumerate() {
            let partial = k == 1;
            let how = if partial {
                format!("a run that stops part way would keep its results as {}, which", name.display())
            } else {
                "it".to_string()
            };
            not_a_special_file(option, path, &name, &how)?;
            let key = comparable(&name);
            if let Some((_, input)) = read.iter().find(|(i, _)| *i == key) {
                let what = if partial {
                    format!("{how} is the model file {}", input.display())
                } else {
                    format!("it would write over the model file {}", input.display())
                };
                return Err(Failure::Usage(format!(
                    "`{option} {}`: {what}; choose another path for the output",
                    path.display()
                )));
            }
            if let Some((other, other_path, _)) = written.iter().find(|(_, _, w)| *w == key) {
                return Err(Failure::Usage(if partial || *other_path != path {
                    format!(
                        "`{other} {}` and `{option} {}` may both write {}; give each output a name of its own",
                        other_path.display(),
                        path.display(),
                        name.display()
                    )
                } else {
                    format!("`{other}` and `{option}` both name {}; give each output a path of its own", path.display())
                }));
            }
            written.push((option, path, key));
        }
    }
    Ok(())
}

/// Refuses an output name that exists and is not a regular file: a folder,
/// a device node (`/dev/null`, `/dev/full`, or a copy of one), a FIFO or a
/// socket (links are followed). Writing a result renames a new file over
/// the name, which would replace the node itself.
fn not_a_special_file(option: &str, given: &Path, name: &Path, how: &str) -> Result<(), Failure> {
    let Ok(meta) = std::fs::metadata(name) else { return Ok(()) };
    if meta.is_file() {
        return Ok(());
    }
    let kind = special_kind(&meta);
    Err(Failure::Usage(format!(
        "`{option} {}`: {how} is {kind}, not a regular file; results are written as new files and renamed into place, which would replace it; give the path of a file (new or earlier results)",
        given.display()
    )))
}

fn special_kind(meta: &std::fs::Metadata) -> &'static str {
    multibody::files::Kind::of(meta).map_or("a regular file", multibody::files::Kind::describe)
}

/// Whether `a` and `b` name one file (through links; either may not exist yet).
pub fn same_file(a: &Path, b: &Path) -> bool {
    comparable(a) == comparable(b)
}

/// The absolute form of a path, through links, for comparing files that
/// may not exist yet (their folder is resolved).
fn comparable(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let folder = folder.canonicalize().unwrap_or(folder);
    path.file_name().map_or(folder.clone(), |name| folder.join(name))
}
