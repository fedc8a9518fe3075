//! The LU factorisation of a square sparse matrix whose pattern is known
//! when the model compiles: a large algebraic loop (the equations of a
//! `for` over an array) has a few entries a row, and factors in time and
//! memory about its number of entries, where a dense LU needs n^2 memory
//! and up to n^3 time.
//!
//! The pivots are chosen once (Markowitz: the pivot whose row and column
//! have the fewest entries left, which keeps the fill small; with values
//! at hand, only among entries not small in their column), and the fill
//! they cause is laid out then. The numeric factorisation runs on that
//! layout without allocating. It checks each pivot against the rest of
//! its column; a pivot too small for the values at hand makes it fail,
//! and the caller then chooses the pivots again from those values.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A static pivot below this fraction of the largest entry left in its
/// column is refused (threshold partial pivoting's test): the growth of
/// the factors then stays bounded.
const PIVOT_THRESHOLD: f64 = 1e-3;

/// Choosing pivots from values, an entry below this fraction of the
/// largest in its column is passed over (the usual threshold of sparse
/// LU); the looser [`PIVOT_THRESHOLD`] then leaves room for the values to
/// drift before the choice is made again.
const CHOICE_THRESHOLD: f64 = 0.1;

/// The layout of the factors and the order of elimination of one pattern.
///
/// The factors are stored by rows in pivot order (row `k` is the `k`-th
/// pivot's row), each row's columns sorted by the step that eliminates
/// them: first `L` (steps before `k`), then the diagonal, then `U`.
#[derive(Clone, Debug)]
pub struct SparseLu {
    n: usize,
    /// The analysed pattern: (row, column) of each entry.
    pattern: Vec<(usize, usize)>,
    /// Where each entry of the analysed pattern sits in the factors.
    entry_at: Vec<u32>,
    /// Row `k` of the factors is `row_start[k]..row_start[k + 1]`.
    row_start: Vec<u32>,
    /// The column (its pivot step) of each stored value.
    columns: Vec<u32>,
    /// The position of each row's diagonal.
    diagonal: Vec<u32>,
    /// For step `k`, `below_start[k]..below_start[k + 1]` of `below`: the
    /// rows after `k` with an entry in column `k`, and its position.
    below_start: Vec<u32>,
    below: Vec<(u32, u32)>,
    /// The matrix row and column of each pivot.
    row_of: Vec<u32>,
    column_of: Vec<u32>,
}

impl SparseLu {
    /// Chooses the pivots of an `n` x `n` matrix with entries (row, column)
    /// at `pattern` (no repeats) and lays out the factors. With `values`
    /// (the entries' values, in the pattern's order) a pivot must also be
    /// at least [`CHOICE_THRESHOLD`] of the largest entry left in its
    /// column, which the elimination carries along; without, any entry
    /// may be a pivot. `None` when no pivot is left for a row or column:
    /// the pattern (or, with values, the matrix) is singular.
    pub fn analyse(n: usize, pattern: &[(usize, usize)], values: Option<&[f64]>) -> Option<SparseLu> {
        // The active part: each row's (column, value) and each column's
        // rows, sorted. Without values every entry counts as 1.
        let mut rows: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        let mut cols: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (e, &(i, j)) in pattern.iter().enumerate() {
            rows[i].push((j as u32, values.map_or(1.0, |v| v[e])));
            cols[j].push(i as u32);
        }
        rows.iter_mut().for_each(|v| v.sort_unstable_by_key(|e| e.0));
        cols.iter_mut().for_each(|v| v.sort_unstable());
        let threshold = if values.is_some() { CHOICE_THRESHOLD } else { 0.0 };
        // Candidates by count; stale ones (counts since changed) are skipped.
        let mut heap: BinaryHeap<Reverse<(usize, bool, u32)>> = BinaryHeap::new();
        for k in 0..n {
            heap.push(Reverse((rows[k].len(), false, k as u32)));
            heap.push(Reverse((cols[k].len(), true, k as u32)));
        }
        let (mut row_done, mut col_done) = (vec![false; n], vec![false; n]);
        let (mut row_of, mut column_of) = (Vec::with_capacity(n), Vec::with_capacity(n));
        // Each row's columns when it is eliminated (its `U` and diagonal),
        // and each step's rows below (its `L`).
        let mut upper: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut lower: Vec<Vec<u32>> = Vec::with_capacity(n);
        while row_of.len() < n {
            let Reverse((count, is_col, k)) = heap.pop()?;
            let k = k as usize;
            let (done, current) = if is_col { (col_done[k], cols[k].len()) } else { (row_done[k], rows[k].len()) };
            if done || current != count {
                continue;
            }
            // The column to pivot in: this one, or the row's column with
            // the fewest rows; then, of the rows whose entry passes the
            // threshold there, the one with the fewest entries.
            let c = if is_col {
                k
            } else {
                rows[k].iter().min_by_key(|&&(j, _)| (cols[j as usize].len(), j)).map(|e| e.0 as usize)?
            };
            let value = |i: u32| {
                let row = &rows[i as usize];
                row[row.binary_search_by_key(&(c as u32), |e| e.0).expect("the column lists its rows")].1
            };
            let largest = cols[c].iter().fold(0.0f64, |m, &i| m.max(value(i).abs()));
            let r = cols[c]
                .iter()
                .copied()
                .filter(|&i| values.is_none() || (value(i).abs() >= threshold * largest && value(i) != 0.0))
                .min_by_key(|&i| (rows[i as usize].len(), i))? as usize;
            row_done[r] = true;
            col_done[c] = true;
            row_of.push(r as u32);
            column_of.push(c as u32);
            let pivot_row = std::mem::take(&mut rows[r]);
            let pivot = pivot_row[pivot_row.binary_search_by_key(&(c as u32), |e| e.0).expect("pivot")].1;
            for &(j, _) in &pivot_row {
                let list = &mut cols[j as usize];
                if let Ok(at) = list.binary_search(&(r as u32)) {
                    list.remove(at);
                }
                if j as usize != c {
                    heap.push(Reverse((list.len(), true, j)));
                }
            }
            let rest: Vec<(u32, f64)> = pivot_row.iter().copied().filter(|&(j, _)| j as usize != c).collect();
            let below = std::mem::take(&mut cols[c]);
            for &i in &below {
                let row = &mut rows[i as usize];
                let at = row.binary_search_by_key(&(c as u32), |e| e.0).expect("the column lists its rows");
                let l = row.remove(at).1 / pivot;
                // The pivot row's columns fill this row.
                let (merged, added) = eliminate(row, &rest, l);
                for j in added {
                    let list = &mut cols[j as usize];
                    let at = list.binary_search(&i).unwrap_or_else(|at| at);
                    list.insert(at, i);
                    heap.push(Reverse((list.len(), true, j)));
                }
                *row = merged;
                heap.push(Reverse((row.len(), false, i)));
            }
            upper[r] = pivot_row.iter().map(|e| e.0).collect();
            lower.push(below);
        }
        Some(SparseLu::lay_out(n, pattern, row_of, column_of, &upper, &lower))
    }

    /// Stores the factors by pivot rows from the elimination's record.
    fn lay_out(
        n: usize,
        pattern: &[(usize, usize)],
        row_of: Vec<u32>,
        column_of: Vec<u32>,
        upper: &[Vec<u32>],
        lower: &[Vec<u32>],
    ) -> SparseLu {
        let mut step_of_row = vec![0u32; n];
        let mut step_of_col = vec![0u32; n];
        for k in 0..n {
            step_of_row[row_of[k] as usize] = k as u32;
            step_of_col[column_of[k] as usize] = k as u32;
        }
        // Each pivot row's columns, by step: L (from the steps that
        // eliminated below it), then its own diagonal and U.
        let mut by_row: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (k, rows_below) in lower.iter().enumerate() {
            for &i in rows_below {
                by_row[step_of_row[i as usize] as usize].push(k as u32);
            }
        }
        let mut row_start = Vec::with_capacity(n + 1);
        let mut columns = Vec::new();
        let mut diagonal = Vec::with_capacity(n);
        for k in 0..n {
            row_start.push(columns.len() as u32);
            let mut own: Vec<u32> = by_row[k].clone();
            own.extend(upper[row_of[k] as usize].iter().map(|&j| step_of_col[j as usize]));
            own.sort_unstable();
            diagonal.push(row_start[k] + own.binary_search(&(k as u32)).expect("the pivot is in its row") as u32);
            columns.extend(own);
        }
        row_start.push(columns.len() as u32);
        let position = |row: u32, col: u32| {
            let (start, end) = (row_start[row as usize] as usize, row_start[row as usize + 1] as usize);
            start as u32 + columns[start..end].binary_search(&col).expect("every entry is laid out") as u32
        };
        let entry_at = pattern.iter().map(|&(i, j)| position(step_of_row[i], step_of_col[j])).collect::<Vec<u32>>();
        let mut below_start = Vec::with_capacity(n + 1);
        let mut below = Vec::new();
        for (k, rows_below) in lower.iter().enumerate() {
            below_start.push(below.len() as u32);
            let mut steps: Vec<u32> = rows_below.iter().map(|&i| step_of_row[i as usize]).collect();
            steps.sort_unstable();
            below.extend(steps.into_iter().map(|s| (s, position(s, k as u32))));
        }
        below_start.push(below.len() as u32);
        SparseLu {
            n,
            pattern: pattern.to_vec(),
            entry_at,
            row_start,
            columns,
            diagonal,
            below_start,
            below,
            row_of,
            column_of,
        }
    }

    /// The analysed pattern: (row, column) of each entry, in its order.
    pub fn pattern(&self) -> &[(usize, usize)] {
        &self.pattern
    }

    /// The number of values the factors hold (the entries and their fill).
    pub fn stored(&self) -> usize {
        self.columns.len()
    }

    /// Puts the values of the analysed pattern's entries (in its order)
    /// into `values` (of length [`SparseLu::stored`]), the fill zeroed.
    pub fn load(&self, entries: impl Iterator<Item = f64>, values: &mut [f64]) {
        values.fill(0.0);
        for (&at, x) in self.entry_at.iter().zip(entries) {
            values[at as usize] = x;
        }
    }

    /// Factors `values` in place. False when a pivot is below
    /// [`PIVOT_THRESHOLD`] of the largest entry left in its column, or
    /// below `1e-13` of the largest entry (singular to working accuracy).
    pub fn factor(&self, values: &mut [f64]) -> bool {
        let scale = values.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..self.n {
            let d = self.diagonal[k] as usize;
            let pivot = values[d];
            let below = &self.below[self.below_start[k] as usize..self.below_start[k + 1] as usize];
            let largest = below.iter().fold(0.0f64, |m, &(_, at)| m.max(values[at as usize].abs()));
            if pivot.is_nan() || pivot.abs() <= 1e-13 * scale || pivot.abs() < PIVOT_THRESHOLD * largest {
                return false;
            }
            let upper = d + 1..self.row_start[k + 1] as usize;
            for &(i, at) in below {
                let at = at as usize;
                let l = values[at] / pivot;
                values[at] = l;
                if l == 0.0 {
                    continue;
                }
                // Row `i` holds every column of row `k`'s U (its fill), in
                // the same order, after column `k`.
                let mut q = at + 1;
                let end = self.row_start[i as usize + 1] as usize;
                for t in upper.clone() {
                    while self.columns[q] != self.columns[t] {
                        q += 1;
                    }
                    debug_assert!(q < end, "the fill was laid out");
                    values[q] -= l * values[t];
                }
            }
        }
        true
    }

    /// Solves `A x = b` with the factors of [`SparseLu::factor`]: `b` by
    /// matrix rows in, `x` by matrix columns out (in `b`); `work` needs `n`.
    pub fn solve(&self, values: &[f64], b: &mut [f64], work: &mut [f64]) {
        let n = self.n;
        for k in 0..n {
            let mut s = b[self.row_of[k] as usize];
            for t in self.row_start[k] as usize..self.diagonal[k] as usize {
                s -= values[t] * work[self.columns[t] as usize];
            }
            work[k] = s;
        }
        for k in (0..n).rev() {
            let d = self.diagonal[k] as usize;
            let mut s = work[k];
            for t in d + 1..self.row_start[k + 1] as usize {
                s -= values[t] * work[self.columns[t] as usize];
            }
            work[k] = s / values[d];
        }
        for k in 0..n {
            b[self.column_of[k] as usize] = work[k];
        }
    }
}

/// `row - l * pivot_row` over the union of their columns (both sorted),
/// and the columns the pivot row added.
fn eliminate(row: &[(u32, f64)], pivot_row: &[(u32, f64)], l: f64) -> (Vec<(u32, f64)>, Vec<u32>) {
    let mut out = Vec::with_capacity(row.len() + pivot_row.len());
    let mut added = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < row.len() || j < pivot_row.len() {
        let take_row = j == pivot_row.len() || (i < row.len() && row[i].0 <= pivot_row[j].0);
        let take_pivot = i == row.len() || (j < pivot_row.len() && pivot_row[j].0 <= row[i].0);
        match (take_row, take_pivot) {
            (true, true) => {
                out.push((row[i].0, row[i].1 - l * pivot_row[j].1));
                i += 1;
                j += 1;
            }
            (true, false) => {
                out.push(row[i]);
                i += 1;
            }
            _ => {
                out.push((pivot_row[j].0, -l * pivot_row[j].1));
                added.push(pivot_row[j].0);
                j += 1;
            }
        }
    }
    (out, added)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator, so the tests need no crate.
    fn next(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Factors and solves `A x = b` for a pattern and values; returns the
    /// backward error `|A x - b| / (|A| |x| + |b|)` (largest entries), or
    /// None when the factorisation refused.
    fn residual(n: usize, entries: &[(usize, usize, f64)], b: &[f64]) -> Option<f64> {
        let pattern: Vec<(usize, usize)> = entries.iter().map(|e| (e.0, e.1)).collect();
        let values: Vec<f64> = entries.iter().map(|e| e.2).collect();
        let lu = SparseLu::analyse(n, &pattern, Some(&values)).expect("regular");
        let mut values = vec![f64::NAN; lu.stored()];
        lu.load(entries.iter().map(|e| e.2), &mut values);
        if !lu.factor(&mut values) {
            return None;
        }
        let mut x = b.to_vec();
        lu.solve(&values, &mut x, &mut vec![0.0; n]);
        let mut r = b.to_vec();
        let mut row_sums = vec![0.0f64; n];
        for &(i, j, a) in entries {
            r[i] -= a * x[j];
            row_sums[i] += a.abs();
        }
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        Some(largest(&r) / (largest(&row_sums) * largest(&x) + largest(b)))
    }

    #[test]
    fn a_cycle_factors_with_fill_linear_in_its_size() {
        // x1 - x_n / 2 = 1; x_i - x_(i-1) / 2 = 1: two entries a row.
        let n = 10_000;
        let mut entries = vec![(0, 0, 1.0), (0, n - 1, -0.5)];
        for i in 1..n {
            entries.extend([(i, i, 1.0), (i, i - 1, -0.5)]);
        }
        let pattern: Vec<(usize, usize)> = entries.iter().map(|e| (e.0, e.1)).collect();
        let lu = SparseLu::analyse(n, &pattern, None).unwrap();
        assert!(lu.stored() <= 3 * n, "fill: {} values for {n} rows", lu.stored());
        // The closed form: every x_i = 2 (x = 1 + x/2).
        let mut values = vec![0.0; lu.stored()];
        lu.load(entries.iter().map(|e| e.2), &mut values);
        assert!(lu.factor(&mut values));
        let mut x = vec![1.0; n];
        lu.solve(&values, &mut x, &mut vec![0.0; n]);
        let worst = x.iter().fold(0.0f64, |m, &x| m.max((x - 2.0).abs()));
        assert!(worst < 1e-13, "worst error {worst}");
    }

    #[test]
    fn random_sparse_matrices_solve_to_rounding() {
        let mut seed = 7;
        for n in [1, 2, 5, 30, 200] {
            // A permuted diagonal and a few entries a row, of either sign.
            let mut entries = Vec::new();
            for i in 0..n {
                let j = (i * 7 + 3) % n;
                entries.push((i, j, next(&mut seed)));
                for _ in 0..3 {
                    let k = ((next(&mut seed) + 1.0) * 0.5 * n as f64) as usize % n;
                    if !entries.iter().any(|e| e.0 == i && e.1 == k) {
                        entries.push((i, k, next(&mut seed)));
                    }
                }
            }
            let b: Vec<f64> = (0..n).map(|_| next(&mut seed)).collect();
            let r = residual(n, &entries, &b).expect("regular");
            assert!(r < 1e-15, "n = {n}: backward error {r}");
        }
    }

    #[test]
    fn pivots_chosen_from_the_pattern_are_chosen_again_when_too_small() {
        // From the pattern alone (0, 0) is the second pivot; its value is tiny.
        let entries = [(0, 0, 1e-9), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (2, 0, 1.0)];
        let pattern: Vec<(usize, usize)> = entries.iter().map(|e| (e.0, e.1)).collect();
        let values: Vec<f64> = entries.iter().map(|e| e.2).collect();
        let blind = SparseLu::analyse(3, &pattern, None).unwrap();
        let mut factors = vec![0.0; blind.stored()];
        blind.load(values.iter().copied(), &mut factors);
        assert!(!blind.factor(&mut factors), "a pivot of 1e-9 over 1 is refused");
        // Chosen with the values, the factors solve to rounding.
        let r = residual(3, &entries, &[1.0, 2.0, 3.0]).expect("chosen with the values");
        assert!(r < 1e-16, "backward error {r}");
    }

    #[test]
    fn a_singular_matrix_has_no_pivots_from_its_values() {
        // Row 1 is twice row 0.
        let pattern = [(0, 0), (0, 1), (1, 0), (1, 1)];
        assert!(SparseLu::analyse(2, &pattern, Some(&[1.0, 2.0, 2.0, 4.0])).is_none());
    }

    #[test]
    fn a_structurally_singular_pattern_has_no_layout() {
        // Column 1 has no entry.
        assert!(SparseLu::analyse(2, &[(0, 0), (1, 0)], None).is_none());
    }
}
