//! Initial equations (`initial der(x) = 0`, `initial y = 1`): they hold at
//! the start only. Their unknowns are the states of the equations whose
//! start values the model did not fix (guess-only parameters among them);
//! Newton's method moves those start values as little as it can until
//! they hold, on one sparse system: its Jacobian's pattern follows from
//! the sorted equations, its values from finite differences through the
//! whole right-hand side, perturbing at once start values whose equations
//! do not overlap.

use super::sort::Sorted;
use super::{problem, Source};
use crate::dynamics::Workspace;
use crate::math::sparse::SparseLu;
use crate::math::symbolic::{evaluate, VarId, S};
use crate::system::equations::Reg;
use crate::{Error, Mechanism};
use nalgebra::{DMatrix, DVector};
use std::collections::BTreeMap;

const ITERATIONS: usize = 50;
const TOLERANCE: f64 = 1e-10;

/// Initial equations with what evaluating them needs.
pub(crate) struct Initial {
    pub residuals: Vec<S>,
    pub origins: Vec<String>,
    /// The register of each variable.
    pub registers: Vec<Reg>,
    /// Registers that hold accelerations, `sum c dy[i]` of the evaluated
    /// derivatives: filled before the residuals are evaluated.
    pub rates: Vec<(Reg, Vec<(usize, f64)>)>,
    /// Indices in the state of the equations' states not fixed at the start.
    pub free: Vec<usize>,
    pub free_names: Vec<String>,
    /// What each residual depends on (see [`dependence`]).
    pub depends: Vec<Dependence>,
}

/// The residuals of the initial equations at the state `y`.
fn residuals(m: &Mechanism, ws: &mut Workspace, init: &Initial, y: &[f64], out: &mut [f64]) -> Result<(), Error> {
    let mut dy = vec![0.0; y.len()];
    let t0 = 0.0;
    // At the start relations hold as they are (as in the first event
    // iteration), from the discrete start: each evaluation sees the same
    // modes. Friction elements are then in no mode yet and carry nothing,
    // so where the split of a holding torque between a stuck friction and
    // a drive is open, the drive holds it all (as Modelica tools choose).
    ws.discrete.copy_from_slice(&m.system.events.discrete_start);
    ws.at_event = true;
    ws.initial = true;
    let evaluated = m.rhs(ws, t0, y, &mut dy);
    ws.reinits.clear();
    evaluated.map_err(|e| {
        problem(
            format!("the start cannot be evaluated: {}", m.describe(&e)),
            init.origins.clone(),
            vec![],
            "check the start values",
        )
    })?;
    for (reg, terms) in &init.rates {
        ws.registers[*reg as usize] = terms.iter().map(|&(i, c)| c * dy[i]).sum();
    }
    m.system.run_output_equations(ws);
    for (r, e) in out.iter_mut().zip(&init.residuals) {
        *r = evaluate(e, t0, &|&v| ws.registers[init.registers[v] as usize]);
    }
    Ok(())
}

/// Moves the free start values until the initial equations hold: first
/// those of the equations' own states; if they cannot (too few, or the
/// equations do not reach them), also the start values of the mechanism's
/// one-coordinate joints that the model left free (a spring's stretch given
/// at the start moves the masses at its ends).
pub(crate) fn solve(mechanism: &mut Mechanism, init: &Initial) -> Result<(), Error> {
    if init.residuals.is_empty() {
        return Ok(());
    }
    let first = if init.residuals.len() <= init.free.len() {
        newton(mechanism, init, &init.free, &init.free_names)
    } else {
        Err(too_many(init, &init.free_names))
    };
    let Err(first) = first else { return Ok(()) };
    let more = mechanical_free(mechanism);
    if more.is_empty() {
        return Err(first);
    }
    let mut free = init.free.clone();
    let mut names = init.free_names.clone();
    for (i, name) in more {
        free.push(i);
        names.push(name);
    }
    if init.residuals.len() > free.len() {
        return Err(too_many(init, &names));
    }
    if held_rows(mechanism).is_empty() {
        newton(mechanism, init, &free, &names)
    } else {
        newton_constrained(mechanism, init, &free, &names)
    }
}

/// The constraint rows that hold at the start whatever moves: those of
/// loops, couplings and prescribed motions (a friction element's row holds
/// only while it is stuck, which the start does not decide here).
fn held_rows(mechanism: &Mechanism) -> Vec<usize> {
    let system = &mechanism.system;
    let friction: Vec<usize> = system.frictions.iter().map(|f| f.row).collect();
    (0..system.constraint_rows).filter(|r| !friction.contains(r)).collect()
}

/// Newton's method where the mechanism's start values move under its
/// constraints: the constraints' position and velocity residuals join the
/// initial equations (the loops stay closed, the gears engaged), and each
/// step is the least-squares one of the dense Jacobian by finite
/// differences (the mechanism's free start values are few).
fn newton_constrained(
    mechanism: &mut Mechanism,
    init: &Initial,
    free: &[usize],
    names: &[String],
) -> Result<(), Error> {
    let rows = held_rows(mechanism);
    let (m, k) = (init.residuals.len(), free.len());
    let position_row: Vec<bool> = {
        let mut on = vec![true; mechanism.system.constraint_rows];
        for c in &mechanism.system.constraints {
            for i in (0..c.rows).filter(|&i| c.kind.is_velocity_row(i)) {
                on[c.row + i] = false;
            }
        }
        rows.iter().map(|&r| on[r]).collect()
    };
    let n = m + 2 * rows.len();
    let mut ws = mechanism.workspace();
    let mut y = mechanism.system.states.start.clone();
    let evaluate = |ws: &mut Workspace, y: &[f64], out: &mut DVector<f64>| -> Result<(), Error> {
        residuals(mechanism, ws, init, y, &mut out.as_mut_slice()[..m])?;
        let system = &mechanism.system;
        let unreachable = |e: crate::dynamics::DynamicsError| {
            problem(
                format!("the start cannot be evaluated: {}", mechanism.describe(&e)),
                init.origins.clone(),
                vec![],
                "check the start values",
            )
        };
        system.servo_targets(ws, 0.0);
        system.constraint_state(ws, y).map_err(unreachable)?;
        for (i, (&r, &on)) in rows.iter().zip(&position_row).enumerate() {
            out[m + i] = if on { ws.residual[r] } else { 0.0 };
        }
        system.velocity_residual(ws, y).map_err(unreachable)?;
        for (i, &r) in rows.iter().enumerate() {
            out[m + rows.len() + i] = ws.lambda[r];
        }
        Ok(())
    };
    let (mut r, mut trial) = (DVector::zeros(n), DVector::zeros(n));
    let mut jacobian = DMatrix::zeros(n, k);
    let mut convergence = Convergence::new(n);
    for iteration in 0..ITERATIONS {
        evaluate(&mut ws, &y, &mut r)?;
        if convergence.met(r.as_slice()) {
            mechanism.system.states.start = y;
            return Ok(());
        }
        for (j, &i) in free.iter().enumerate() {
            let keep = y[i];
            let h = fd_step(keep);
            y[i] += h;
            evaluate(&mut ws, &y, &mut trial)?;
            y[i] = keep;
            jacobian.set_column(j, &((&trial - &r) / h));
        }
        if iteration == 0 {
            // The constraints take some of the start values' freedom.
            let taken = jacobian.rows(m, n - m).into_owned().svd(false, false).rank(1e-9);
            if m > k - taken.min(k) {
                return Err(too_many(init, names));
            }
        }
        let step = jacobian.clone().svd(true, true).solve(&(-&r), 1e-12).map_err(|_| {
            problem(
                "the initial equations do not determine the free start values",
                init.origins.clone(),
                names.to_vec(),
                "check that each initial equation involves a state whose start value is free",
            )
        })?;
        convergence.stepped(free.iter().zip(step.iter()).map(|(&i, &dz)| (y[i], dz)));
        for (j, &i) in free.iter().enumerate() {
            y[i] += step[j];
        }
    }
    Err(problem(
        "Newton's method found no start that satisfies the initial equations with the mechanism's constraints",
        init.origins.clone(),
        names.to_vec(),
        "give the states better start values (`guess`), or check the initial equations",
    ))
}

/// The start values of the mechanism that the initial equations may move:
/// positions and velocities of joints with one coordinate (revolute,
/// prismatic, 1-D inertias and masses) that the model did not fix and that
/// no motion drives (with loops or gears, under their constraints).
fn mechanical_free(mechanism: &Mechanism) -> Vec<(usize, String)> {
    let system = &mechanism.system;
    let states = &system.states;
    let mut out = Vec::new();
    for link in system.links.iter().skip(1) {
        if link.joint.nq() != 1 || link.joint.nv() != 1 || !system.free_coordinates[link.v_offset] {
            continue;
        }
        for i in [link.q_offset, states.nq + link.v_offset] {
            if !states.fixed[i] {
                out.push((i, states.names[i].clone()));
            }
        }
    }
    out
}

/// More initial equations than start values free to meet them.
fn too_many(init: &Initial, names: &[String]) -> Error {
    let (m, k) = (init.residuals.len(), names.len());
    problem(
        format!(
            "{m} initial equation{} but {k} state{} free to satisfy them{}",
            if m == 1 { "" } else { "s" },
            if k == 1 { "" } else { "s" },
            if names.is_empty() { String::new() } else { format!(" ({})", names.join(", ")) }
        ),
        init.origins.clone(),
        names.to_vec(),
        if k == 0 {
            "the start of the mechanism comes from its joints' and masses' start values (`initial`): leave some of \
             them free (a `guess` instead of an `initial` value), or give the start there"
        } else {
            "remove initial equations, or leave more start values free (a `guess` instead of an `initial` value)"
        },
    )
}

/// Newton's method with least-norm steps over the start values `free`
/// (the equations' free states first, in [`Initial::free`]'s order). The
/// Jacobian is sparse: its pattern comes from [`Initial::depends`], and one
/// evaluation of the right-hand side perturbs every start value of a group
/// whose residuals do not overlap (a ladder of capacitors started at rest
/// needs three, not one per capacitor). The step solves the sparse
/// `J dz = -r` (as many equations as start values) or, with fewer
/// equations, the least-norm `dz = -J' (J J')^-1 r`.
fn newton(mechanism: &mut Mechanism, init: &Initial, free: &[usize], free_names: &[String]) -> Result<(), Error> {
    let (m, k) = (init.residuals.len(), free.len());
    let jacobian = Pattern::new(&init.depends, k);
    let mut ws = mechanism.workspace();
    let mut y = mechanism.system.states.start.clone();
    let (mut r, mut trial) = (vec![0.0; m], vec![0.0; m]);
    let mut values = vec![0.0; jacobian.entries.len()];
    let mut step = vec![0.0; k];
    let singular = || {
        problem(
            "the initial equations do not determine the free start values (their Jacobian is singular)",
            init.origins.clone(),
            free_names.to_vec(),
            "check that each initial equation involves a state whose start value is free",
        )
    };
    let mut convergence = Convergence::new(m);
    for _ in 0..ITERATIONS {
        residuals(mechanism, &mut ws, init, &y, &mut r)?;
        if convergence.met(&r) {
            mechanism.system.states.start = y;
            return Ok(());
        }
        for group in &jacobian.groups {
            let keep: Vec<f64> = group.iter().map(|&j| y[free[j]]).collect();
            for &j in group {
                y[free[j]] += fd_step(y[free[j]]);
            }
            residuals(mechanism, &mut ws, init, &y, &mut trial)?;
            for (&j, &x) in group.iter().zip(&keep) {
                y[free[j]] = x;
            }
            for &j in group {
                let h = fd_step(y[free[j]]);
                for &e in &jacobian.of_column[j] {
                    let row = jacobian.entries[e].0;
                    values[e] = (trial[row] - r[row]) / h;
                }
            }
        }
        if !jacobian.step(&values, &r, &mut step) {
            return Err(singular());
        }
        convergence.stepped(free.iter().zip(&step).map(|(&i, &dz)| (y[i], dz)));
        for (j, &i) in free.iter().enumerate() {
            y[i] += step[j];
        }
    }
    Err(problem(
        "Newton's method found no start that satisfies the initial equations",
        init.origins.clone(),
        free_names.to_vec(),
        "give the states better start values (`guess`), or check the initial equations",
    ))
}

/// When Newton's iterates have converged: every residual below
/// [`TOLERANCE`], or, where the residuals' size puts that below rounding
/// (a capacitor's rate `i / C` is of order 1e8), the last step below
/// rounding of the values and each residual a 1e-8 of the largest it was.
struct Convergence {
    largest: Vec<f64>,
    last_step: f64,
}

impl Convergence {
    fn new(m: usize) -> Self {
        Convergence { largest: vec![0.0; m], last_step: f64::INFINITY }
    }

    fn met(&mut self, r: &[f64]) -> bool {
        for (l, x) in self.largest.iter_mut().zip(r) {
            *l = l.max(x.abs());
        }
        r.iter().all(|x| x.abs() <= TOLERANCE)
            || (self.last_step <= 1e-10 && r.iter().zip(&self.largest).all(|(x, l)| x.abs() <= 1e-8 * (1.0 + l)))
    }

    /// Records a step: `(value, change)` of each start value moved.
    fn stepped(&mut self, moves: impl Iterator<Item = (f64, f64)>) {
        self.last_step = moves.fold(0.0, |m, (z, dz)| m.max(dz.abs() / (1.0 + z.abs())));
    }
}

/// The finite-difference step of a start value `x`.
fn fd_step(x: f64) -> f64 {
    1e-7 * (1.0 + x.abs())
}

/// The pattern of the initial equations' Jacobian over `k` start values,
/// and the groups of columns one evaluation perturbs together.
struct Pattern {
    m: usize,
    k: usize,
    /// (row, column) of each entry.
    entries: Vec<(usize, usize)>,
    /// The entries of each column.
    of_column: Vec<Vec<usize>>,
    /// Columns no two of which share a row.
    groups: Vec<Vec<usize>>,
}

impl Pattern {
    fn new(depends: &[Dependence], k: usize) -> Pattern {
        let m = depends.len();
        let mut entries = Vec::new();
        for (row, d) in depends.iter().enumerate() {
            if d.everything {
                entries.extend((0..k).map(|j| (row, j)));
            } else {
                entries.extend(d.columns.iter().filter(|&&j| j < k).map(|&j| (row, j)));
            }
        }
        let mut of_column = vec![Vec::new(); k];
        for (e, &(_, j)) in entries.iter().enumerate() {
            of_column[j].push(e);
        }
        // Greedy colouring: each column joins the first group none of whose
        // rows it has.
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut rows_of_group: Vec<Vec<bool>> = Vec::new();
        for (j, column) in of_column.iter().enumerate() {
            if column.is_empty() {
                continue;
            }
            let free = rows_of_group.iter().position(|used| column.iter().all(|&e| !used[entries[e].0]));
            let g = free.unwrap_or_else(|| {
                groups.push(Vec::new());
                rows_of_group.push(vec![false; m]);
                groups.len() - 1
            });
            groups[g].push(j);
            column.iter().for_each(|&e| rows_of_group[g][entries[e].0] = true);
        }
        Pattern { m, k, entries, of_column, groups }
    }

    /// The Newton step for the Jacobian `values` (on the entries) and the
    /// residuals `r`; false when the system is singular.
    fn step(&self, values: &[f64], r: &[f64], step: &mut [f64]) -> bool {
        let (m, k) = (self.m, self.k);
        let mut work = vec![0.0; m.max(k)];
        if m == k {
            let Some(lu) = SparseLu::analyse(m, &self.entries, Some(values)) else { return false };
            let mut factors = vec![0.0; lu.stored()];
            lu.load(values.iter().copied(), &mut factors);
            if !lu.factor(&mut factors) {
                return false;
            }
            step.iter_mut().zip(r).for_each(|(s, r)| *s = -r);
            lu.solve(&factors, step, &mut work);
            return true;
        }
        // Least norm: (J J') w = r, dz = -J' w; J J' has an entry where two
        // rows share a column.
        let mut product: BTreeMap<(usize, usize), f64> = BTreeMap::new();
        for column in &self.of_column {
            for &a in column {
                for &b in column {
                    *product.entry((self.entries[a].0, self.entries[b].0)).or_insert(0.0) += values[a] * values[b];
                }
            }
        }
        let (pattern, entries): (Vec<(usize, usize)>, Vec<f64>) = product.into_iter().unzip();
        let Some(lu) = SparseLu::analyse(m, &pattern, Some(&entries)) else { return false };
        let mut factors = vec![0.0; lu.stored()];
        lu.load(entries.iter().copied(), &mut factors);
        if !lu.factor(&mut factors) {
            return false;
        }
        let mut w = r.to_vec();
        lu.solve(&factors, &mut w, &mut work);
        step.fill(0.0);
        for (e, &(row, j)) in self.entries.iter().enumerate() {
            step[j] -= values[e] * w[row];
        }
        true
    }
}

/// What an initial equation's residual can depend on among the start
/// values Newton moves: the equations' states (by their position in
/// [`Initial::free`]) and, when it reads the mechanism or a signal, every
/// start value (the mechanism's among them).
#[derive(Clone, Debug, Default)]
pub(crate) struct Dependence {
    pub columns: Vec<usize>,
    pub everything: bool,
}

impl Dependence {
    fn join(&mut self, other: &Dependence) {
        self.everything |= other.everything;
        self.columns.extend_from_slice(&other.columns);
    }

    fn tidy(mut self) -> Dependence {
        self.columns.sort_unstable();
        self.columns.dedup();
        self
    }
}

/// For each initial equation, the start values its residual depends on:
/// followed from the states through the sorted blocks (a block's unknowns
/// depend on what its equations read), so that the Jacobian's pattern is
/// known and one evaluation perturbs many start values at once.
pub(super) fn dependence(
    sorted: &Sorted,
    reads: &[Option<Source>],
    signal_of_time: &[bool],
    column_of_state: &[Option<usize>],
    residuals: &[S],
) -> Vec<Dependence> {
    // What the blocks do not compute (the mechanism's and the signals'
    // quantities, and any other) may depend on every start; discrete
    // values and signals of time only stay as they are.
    let fixed = |source: &Option<Source>| match source {
        Some(Source::Discrete(_)) => true,
        Some(Source::Slot(slot)) => signal_of_time.get(*slot).copied().unwrap_or(false),
        _ => false,
    };
    let mut of: Vec<Dependence> =
        reads.iter().map(|source| Dependence { columns: Vec::new(), everything: !fixed(source) }).collect();
    for (k, &s) in sorted.states.iter().enumerate() {
        of[s] = Dependence { columns: column_of_state[k].into_iter().collect(), everything: false };
    }
    let root = |v: VarId| sorted.alias[v].map_or(v, |(of, _)| of);
    let mut names = Vec::new();
    for (equations, unknowns) in &sorted.blocks {
        let mut block = Dependence::default();
        for &e in equations {
            names.clear();
            sorted.residuals[e].variables(&mut names);
            for &&v in &names {
                let v = root(v);
                if !unknowns.contains(&v) {
                    block.join(&of[v]);
                }
            }
        }
        let block = block.tidy();
        for &u in unknowns {
            of[u] = block.clone();
        }
    }
    residuals
        .iter()
        .map(|r| {
            let mut d = Dependence::default();
            names.clear();
            r.variables(&mut names);
            for &&v in &names {
                d.join(&of[root(v)]);
            }
            d.tidy()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reads(columns: &[usize]) -> Dependence {
        Dependence { columns: columns.to_vec(), everything: false }
    }

    /// Equations that each read three neighbours take three evaluations;
    /// one that reads the mechanism takes one per start value.
    #[test]
    fn start_values_of_disjoint_equations_are_perturbed_together() {
        let n: usize = 300;
        let chain: Vec<Dependence> = (0..n)
            .map(|i| Dependence { columns: (i.saturating_sub(1)..=(i + 1).min(n - 1)).collect(), everything: false })
            .collect();
        let pattern = Pattern::new(&chain, n);
        assert_eq!(pattern.groups.len(), 3);
        assert_eq!(pattern.entries.len(), 3 * n - 2);
        let mut dense = chain.clone();
        dense[7] = Dependence { columns: Vec::new(), everything: true };
        assert_eq!(Pattern::new(&dense, n).groups.len(), n);
    }

    /// The sparse step solves J dz = -r when square, and gives the
    /// least-norm step otherwise: x + y = 2 from 0 moves both by 1.
    #[test]
    fn the_step_is_newtons_or_the_least_norm_one() {
        let pattern = Pattern::new(&[reads(&[0, 1]), reads(&[1])], 2);
        // J = [[2, 1], [0, 4]], r = [3, 8]: dz = -J^-1 r = [-0.5, -2].
        let mut step = vec![0.0; 2];
        assert!(pattern.step(&[2.0, 1.0, 4.0], &[3.0, 8.0], &mut step));
        assert!((step[0] + 0.5).abs() < 1e-15 && (step[1] + 2.0).abs() < 1e-15, "{step:?}");
        let under = Pattern::new(&[reads(&[0, 1])], 2);
        assert!(under.step(&[1.0, 1.0], &[-2.0], &mut step));
        assert!((step[0] - 1.0).abs() < 1e-15 && (step[1] - 1.0).abs() < 1e-15, "{step:?}");
        assert!(!pattern.step(&[2.0, 1.0, 0.0], &[3.0, 8.0], &mut step), "a singular J is refused");
    }
}
