//! Small dense linear algebra in preallocated row-major buffers: the
//! Cholesky factorisation of the mass matrix, and a pivoted LDL' that
//! solves the (possibly rank-deficient) constraint equations.

/// Factors the symmetric positive definite `a` (n x n, row-major) in place
/// into its lower Cholesky factor. False if `a` is not positive definite.
pub fn cholesky(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// Solves `L L' x = b` in place, with `l` from [`cholesky`].
pub fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Factors the square `a` (n x n, row-major) in place as `P A = L U` with
/// partial pivoting (`L` unit lower, below the diagonal; `U` on and above
/// it; row `i` of `P A` is row `pivots[i]` of `A`). False when a pivot is
/// below `1e-13` of the largest entry: `a` is singular to working accuracy.
pub fn lu(a: &mut [f64], n: usize, pivots: &mut [usize]) -> bool {
    let scale = a[..n * n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (i, p) in pivots.iter_mut().enumerate().take(n) {
        *p = i;
    }
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs())).unwrap_or(k);
        let d = a[p * n + k];
        if d.is_nan() || d.abs() <= 1e-13 * scale {
            return false;
        }
        if p != k {
            pivots.swap(k, p);
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        for i in k + 1..n {
            let l = a[i * n + k] / d;
            a[i * n + k] = l;
            // Rows with nothing below the pivot are left as they are: a
            // sparse block (a long algebraic loop of a `for`) factors in
            // about n^2, not n^3.
            if l == 0.0 {
                continue;
            }
            for j in k + 1..n {
                a[i * n + j] -= l * a[k * n + j];
            }
        }
    }
    true
}

/// Solves `A x = b` in place with the factors of [`lu`]; `work` needs `n`
/// entries.
pub fn lu_solve(a: &[f64], n: usize, pivots: &[usize], b: &mut [f64], work: &mut [f64]) {
    for i in 0..n {
        let mut s = b[pivots[i]];
        for k in 0..i {
            s -= a[i * n + k] * work[k];
        }
        work[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = work[i];
        for k in i + 1..n {
            s -= a[i * n + k] * work[k];
        }
        work[i] = s / a[i * n + i];
    }
    b[..n].copy_from_slice(&work[..n]);
}

/// Factors the symmetric `a` (n x n) in place as `P' A P = L D L'`,
/// pivoting on the largest remaining diagonal in magnitude. Pivots below
/// `tolerance` times the largest diagonal end the factorisation: the
/// returned rank counts the independent rows. `perm` receives `P`. Made
/// for positive semi-definite matrices; a definite one of either sign (the
/// constraint Schur complement of an indefinite mass matrix) works too.
pub fn ldlt_pivoted(a: &mut [f64], n: usize, perm: &mut [usize], tolerance: f64) -> usize {
    for (i, p) in perm.iter_mut().enumerate().take(n) {
        *p = i;
    }
    let scale = (0..n).map(|i| a[i * n + i].abs()).fold(0.0f64, f64::max);
    let floor = tolerance * scale.max(f64::MIN_POSITIVE);
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i * n + i].abs().total_cmp(&a[j * n + j].abs())).unwrap_or(k);
        if p != k {
            perm.swap(k, p);
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
            for i in 0..n {
                a.swap(i * n + k, i * n + p);
            }
        }
        let d = a[k * n + k];
        if d.is_nan() || d.abs() <= floor {
            return k;
        }
        for i in k + 1..n {
            a[i * n + k] /= d;
        }
        for i in k + 1..n {
            let lik = a[i * n + k];
            for j in k + 1..=i {
                a[i * n + j] -= lik * d * a[j * n + k];
                a[j * n + i] = a[i * n + j];
            }
        }
    }
    n
}

/// Solves `A x = b` with the factors of [`ldlt_pivoted`] of rank `rank`:
/// the dependent rows get zero (a basic solution, exact when `b` is
/// consistent). `work` needs `n` entries; the answer replaces `b`.
pub fn ldlt_solve(a: &[f64], n: usize, perm: &[usize], rank: usize, b: &mut [f64], work: &mut [f64]) {
    for i in 0..n {
        work[i] = b[perm[i]];
    }
    for i in 0..rank {
        for k in 0..i {
            work[i] -= a[i * n + k] * work[k];
        }
    }
    for i in 0..rank {
        work[i] /= a[i * n + i];
    }
    for w in work.iter_mut().take(n).skip(rank) {
        *w = 0.0;
    }
    for i in (0..rank).rev() {
        for k in i + 1..rank {
            work[i] -= a[k * n + i] * work[k];
        }
    }
    for i in 0..n {
        b[perm[i]] = work[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_an_indefinite_system_and_refuses_a_singular_one() {
        // Symmetric and indefinite (eigenvalues of both signs): Cholesky fails.
        let a0 = [1.0, 2.0, 0.0, 2.0, 1.0, 3.0, 0.0, 3.0, -2.0];
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| a0[i * 3 + j] * x[j]).sum()).collect();
        let mut a = a0;
        assert!(!cholesky(&mut a.clone(), 3));
        let (mut pivots, mut work) = ([0; 3], [0.0; 3]);
        assert!(lu(&mut a, 3, &mut pivots));
        lu_solve(&a, 3, &pivots, &mut b, &mut work);
        for (bi, xi) in b.iter().zip(x) {
            assert!((bi - xi).abs() < 1e-14, "{b:?}");
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert!(!lu(&mut singular, 2, &mut [0; 2]));
    }

    #[test]
    fn cholesky_solves_a_positive_definite_system() {
        let a0 = [4.0, 2.0, 0.6, 2.0, 5.0, 1.0, 0.6, 1.0, 3.0];
        let mut a = a0;
        assert!(cholesky(&mut a, 3));
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| a0[i * 3 + j] * x[j]).sum()).collect();
        cholesky_solve(&a, 3, &mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn pivoted_ldlt_solves_consistent_rank_deficient_systems() {
        // A = G G' with G 4x2: rank 2.
        let g = [[1.0, 0.0], [0.5, 1.0], [1.5, 1.0], [0.0, 2.0]];
        let mut a = [0.0; 16];
        for i in 0..4 {
            for j in 0..4 {
                a[i * 4 + j] = g[i][0] * g[j][0] + g[i][1] * g[j][1];
            }
        }
        let a0 = a;
        // b in the range of A.
        let b0: Vec<f64> = (0..4).map(|i| a0[i * 4] * 0.3 - a0[i * 4 + 3] * 1.1).collect();
        let mut perm = [0; 4];
        let rank = ldlt_pivoted(&mut a, 4, &mut perm, 1e-12);
        assert_eq!(rank, 2);
        let mut x = b0.clone();
        let mut work = [0.0; 4];
        ldlt_solve(&a, 4, &perm, rank, &mut x, &mut work);
        for i in 0..4 {
            let ax: f64 = (0..4).map(|j| a0[i * 4 + j] * x[j]).sum();
            assert!((ax - b0[i]).abs() < 1e-12, "row {i}: {ax} vs {}", b0[i]);
        }
    }
}
