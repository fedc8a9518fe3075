//! The result of a simulation: time and every output signal by name.

use crate::assembly::SignalTable;
use std::io::{self, Write};
use std::sync::Arc;

/// Named signals sampled at common times.
#[derive(Clone, Default)]
pub struct Solution {
    table: Arc<SignalTable>,
    time: Vec<f64>,
    columns: Vec<Vec<f64>>,
    warnings: Vec<String>,
}

/// Samples recorded row by row: one append per sample, where a
/// [`Solution`] pushes onto every column. A [`crate::Simulator`] records
/// this way (5000 samples of 107 signals pushed column by column cost it
/// about a fifth of its time) and makes the columns when they are asked for.
#[derive(Clone, Debug, Default)]
pub struct Rows {
    width: usize,
    time: Vec<f64>,
    /// Row-major: `values[k * width + j]` is signal `j` at `time[k]`.
    values: Vec<f64>,
}

impl Rows {
    pub fn new(width: usize) -> Self {
        Self { width, time: Vec::new(), values: Vec::new() }
    }

    /// Values per sample.
    pub fn width(&self) -> usize {
        self.width
    }

    pub fn time(&self) -> &[f64] {
        &self.time
    }

    /// Every sample's values, one row after the other.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The values of sample `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.values[k * self.width..(k + 1) * self.width]
    }

    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    pub fn reserve(&mut self, samples: usize) {
        self.time.reserve(samples);
        self.values.reserve(samples * self.width);
    }

    pub fn clear(&mut self) {
        self.time.clear();
        self.values.clear();
    }

    /// Appends the samples from `from` on to `solution`.
    pub(crate) fn append_to(&self, solution: &mut Solution, from: usize) {
        solution.reserve(self.len().saturating_sub(from));
        for k in from..self.len() {
            solution.push(self.time[k], self.row(k));
        }
    }
}

impl super::SampleSink for Rows {
    fn sample(&mut self, t: f64, row: &[f64]) -> Result<(), String> {
        debug_assert_eq!(row.len(), self.width);
        self.time.push(t);
        self.values.extend_from_slice(row);
        Ok(())
    }
}

impl std::fmt::Debug for Solution {
    /// A summary: a solution can hold millions of numbers.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let span = match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => format!("t = {a} .. {b}"),
            _ => "empty".into(),
        };
        write!(f, "Solution {{ {} signals, {} samples, {span} }}", self.columns.len(), self.time.len())
    }
}

impl Solution {
    pub fn new(names: Vec<String>, units: Vec<&'static str>) -> Self {
        Self::with_signals(Arc::new(SignalTable::new(names, units)))
    }

    pub(crate) fn with_signals(table: Arc<SignalTable>) -> Self {
        let columns = vec![Vec::new(); table.names().len()];
        Self { table, time: Vec::new(), columns, warnings: Vec::new() }
    }

    /// What the integrator found doubtful about this run (a stiff
    /// stretch, errors that add up beyond the tolerance); empty when the
    /// run met its tolerance without doubt.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    pub(crate) fn set_warnings(&mut self, warnings: Vec<String>) {
        self.warnings = warnings;
    }

    /// Makes room for `samples` more samples of every signal.
    pub fn reserve(&mut self, samples: usize) {
        self.time.reserve(samples);
        for c in &mut self.columns {
            c.reserve(samples);
        }
    }

    /// Appends one sample; `row` has one value per signal.
    pub fn push(&mut self, t: f64, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns.len());
        self.time.push(t);
        for (c, &x) in self.columns.iter_mut().zip(row) {
            c.push(x);
        }
    }

    /// Drops the samples after `t`.
    pub fn truncate_after(&mut self, t: f64) {
        let keep = self.time.partition_point(|&s| s <= t);
        self.time.truncate(keep);
        for c in &mut self.columns {
            c.truncate(keep);
        }
    }

    pub fn time(&self) -> &[f64] {
        &self.time
    }

    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Every signal name, e.g. `body.r_0[2]`.
    pub fn names(&self) -> &[String] {
        self.table.names()
    }

    pub fn unit(&self, name: &str) -> Option<&'static str> {
        self.table.index(name).map(|i| self.table.units()[i])
    }

    /// The samples of a signal.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.table.index(name).map(|i| self.columns[i].as_slice())
    }

    /// The last sample of a signal.
    pub fn last(&self, name: &str) -> Option<f64> {
        self.get(name).and_then(|c| c.last().copied())
    }

    /// A signal at time `t`, linearly interpolated between samples.
    pub fn at(&self, name: &str, t: f64) -> Option<f64> {
        let c = self.get(name)?;
        let k = self.time.partition_point(|&s| s < t);
        if k == 0 {
            return c.first().copied();
        }
        if k >= self.time.len() {
            return c.last().copied();
        }
        let (t0, t1) = (self.time[k - 1], self.time[k]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
        Some(c[k - 1] * (1.0 - w) + c[k] * w)
    }

    /// Names of the signals that match any of `patterns` (`*` matches any
    /// text, `?` one character); all signals when `patterns` is empty.
    pub fn select(&self, patterns: &[String]) -> Vec<&str> {
        self.names()
            .iter()
            .filter(|n| patterns.is_empty() || patterns.iter().any(|p| glob(p, n)))
            .map(String::as_str)
            .collect()
    }

    /// Writes a CSV file: a `time` column, then the chosen signals (names
    /// that are not signals are left out).
    pub fn write_csv(&self, out: &mut impl Write, signals: &[&str]) -> io::Result<()> {
        let signals: Vec<&str> = signals.iter().copied().filter(|s| self.get(s).is_some()).collect();
        let columns: Vec<&[f64]> = signals.iter().filter_map(|s| self.get(s)).collect();
        let mut csv = CsvWriter::new(out, &signals)?;
        let mut row = vec![0.0; columns.len()];
        for (k, &t) in self.time.iter().enumerate() {
            for (x, c) in row.iter_mut().zip(&columns) {
                *x = c[k];
            }
            csv.row(t, &row)?;
        }
        Ok(())
    }
}

/// Writes samples as CSV rows as they come: a `time` column, then one per
/// signal, with the names quoted as in Modelica's result files (matrix
/// entries like `R[1,2]` contain commas).
pub struct CsvWriter<W: Write> {
    out: W,
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header.
    pub fn new(out: W, names: &[&str]) -> io::Result<Self> {
        Self::with_keys(out, &[], names)
    }

    /// Writes the header of a table whose rows start with `keys` (the run
    /// and its parameters of a sweep), before `time`.
    pub fn with_keys(mut out: W, keys: &[&str], names: &[&str]) -> io::Result<Self> {
        for (k, s) in keys.iter().chain(&["time"]).chain(names).enumerate() {
            let comma = if k == 0 { "" } else { "," };
            write!(out, "{comma}\"{}\"", s.replace('"', "\"\""))?;
        }
        writeln!(out)?;
        Ok(Self { out })
    }

    /// One row: the time and one value per signal of the header.
    pub fn row(&mut self, t: f64, values: &[f64]) -> io::Result<()> {
        self.keyed_row(&[], t, values)
    }

    /// One row of a table with keys: their values, the time, the signals.
    pub fn keyed_row(&mut self, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
        csv_row(&mut self.out, keys, t, values)
    }

    /// Rows written elsewhere with [`csv_row`] (by the threads that
    /// computed them), added as they are.
    pub fn rendered_rows(&mut self, rows: &[u8]) -> io::Result<()> {
        self.out.write_all(rows)
    }

    /// The writer, flushed.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// One row of a [`CsvWriter`]'s table: the keys' values, the time, the
/// signals.
pub fn csv_row<W: Write>(out: &mut W, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
    for k in keys {
        write!(out, "{k},")?;
    }
    write!(out, "{t}")?;
    for x in values {
        write!(out, ",{x}")?;
    }
    writeln!(out)
}

/// Shell-style matching with `*` and `?`.
pub fn glob(pattern: &str, text: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), text.chars().collect());
    let (mut pi, mut ti, mut star, mut mark) = (0, 0, None, 0);
    while ti < t.len() {
        if pi < p.len() && (p[pi] == '?' || p[pi] == t[ti]) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == '*' {
            star = Some(pi);
            mark = ti;
            pi += 1;
        } else if let Some(s) = star {
            pi = s + 1;
            mark += 1;
            ti = mark;
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glob_matches_signal_names() {
        assert!(glob("body.r_0[*]", "body.r_0[2]"));
        assert!(glob("*.phi", "rev.phi"));
        assert!(!glob("*.phi", "rev.phid"));
        assert!(glob("rev.?", "rev.w"));
    }

    #[test]
    fn interpolates_between_samples() {
        let mut s = Solution::new(vec!["x".into()], vec![""]);
        s.push(0.0, &[0.0]);
        s.push(1.0, &[2.0]);
        assert_eq!(s.at("x", 0.25), Some(0.5));
        assert_eq!(s.last("x"), Some(2.0));
    }
}
