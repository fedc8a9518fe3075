//! Index reduction: equations that fix variables whose derivatives are
//! used too (`s_rel = flange_b.s - flange_a.s` with `v_rel = der(s_rel)`,
//! a pendulum written in Cartesian coordinates, `x^2 + y^2 = L^2` with
//! `der(x) = vx`) are differentiated, as often as needed, until every
//! equation can decide an unknown (Pantelides), and for each equation
//! differentiated one of the derivatives it decides stops being integrated:
//! the variable it is the derivative of is computed from the equation
//! (dummy derivatives, Mattsson and Söderlind), level by level from the
//! highest derivatives down.
//!
//! The choice is made once, before the run, preferring the derivative
//! with the largest coefficient at the start values (the pendulum hanging
//! near the bottom keeps `x` and computes `y`); a constraint whose
//! Jacobian loses rank along that choice while the model runs would need
//! it to change, which is not done: the block that computes the
//! variable then fails to converge and the run stops with that message.

use super::{problem, Pending, Read, Role, Table};
use crate::math::graph::maximum_matching;
use crate::math::symbolic::{self as sym, VarId};
use crate::math::union_find::UnionFind;
use crate::system::equations::FrameQuantity;
use crate::Error;

/// How many times one equation may be differentiated: a model that asks
/// for more is structurally singular (nothing decides some unknown
/// however often its equations are differentiated).
const MAX_ORDER: usize = 6;

/// Differentiates the equations the structure needs, marks in
/// `pending.dummy` the variables that stop being states, and turns a
/// fixed start value of such a variable into an initial equation.
pub(super) fn reduce(pending: &mut Pending, table: &mut Table) -> Result<(), Error> {
    let original = pending.residuals.len();
    // The equations the matching sees: an equation once differentiated
    // is seen through its derivative.
    let mut active: Vec<usize> = (0..original).collect();
    // The equation each residual is the derivative of, and how many times
    // the original was differentiated to get it.
    let mut parent: Vec<Option<usize>> = vec![None; original];
    let mut order: Vec<usize> = vec![0; original];
    let mut gained: Vec<VarId> = Vec::new();
    loop {
        let has_derivative = derivatives(&table.vars);
        let unknown = |v: usize| match table.vars[v].role {
            Role::Declared(_) => has_derivative[v].is_none() && !pending.discrete.contains(&VarId::new(v)),
            Role::Derivative { .. } => has_derivative[v].is_none(),
            Role::Written { .. } => true,
            Role::Read(_) => false,
        };
        let mut column = vec![usize::MAX; table.vars.len()];
        let mut columns = 0;
        for (v, c) in column.iter_mut().enumerate() {
            if unknown(v) {
                *c = columns;
                columns += 1;
            }
        }
        let adjacency: Vec<Vec<usize>> = active
            .iter()
            .map(|&r| {
                let mut cols = Vec::new();
                pending.residuals[r].each_var(&mut |&v| {
                    if column[v] != usize::MAX && !cols.contains(&column[v]) {
                        cols.push(column[v]);
                    }
                });
                cols
            })
            .collect();
        let (col_of, row_of) = maximum_matching(&adjacency, columns);
        // The equations an unmatched one competes with, and their unknowns:
        // more equations than unknowns, so they must be differentiated.
        let mut rows = Vec::new();
        let mut cols = Vec::new();
        let mut stack: Vec<usize> = (0..active.len()).filter(|&r| col_of[r] == usize::MAX).collect();
        if stack.is_empty() {
            break;
        }
        let mut seen = vec![false; active.len()];
        while let Some(r) = stack.pop() {
            if std::mem::replace(&mut seen[r], true) {
                continue;
            }
            rows.push(r);
            for &c in &adjacency[r] {
                if !cols.contains(&c) {
                    cols.push(c);
                }
                if row_of[c] != usize::MAX {
                    stack.push(row_of[c]);
                }
            }
        }
        // Differentiating helps where the surplus comes from states that
        // equations fix, and only equations of variables of their own.
        let is_state = |v: VarId| !matches!(table.vars[v].role, Role::Read(_)) && has_derivative[v].is_some();
        let fixes_state = rows.iter().any(|&r| {
            let mut found = false;
            pending.residuals[active[r]].each_var(&mut |&v| found |= is_state(v));
            found
        });
        let helps = fixes_state
            && rows.iter().all(|&r| {
                let mut own = false;
                pending.residuals[active[r]].each_var(&mut |&v| own |= !matches!(table.vars[v].role, Role::Read(_)));
                own
            });
        if !helps {
            // A constraint on the mechanism alone: the sorting names the equations.
            break;
        }
        let variable_of_column: Vec<VarId> =
            VarId::all(table.vars.len()).filter(|&v| column[v] != usize::MAX).collect();
        let fixed: Vec<VarId> = cols.iter().map(|&c| variable_of_column[c]).collect();
        if !fixed.iter().all(|&v| matches!(table.vars[v].role, Role::Declared(_) | Role::Derivative { .. })) {
            // A signal's rate would be needed: the sorting names the equations.
            break;
        }
        if let Some(&r) = rows.iter().find(|&&r| order[active[r]] >= MAX_ORDER) {
            return Err(problem(
                format!(
                    "differentiating these equations {MAX_ORDER} times still leaves one of them nothing to decide: \
                     the system is singular whatever is differentiated"
                ),
                rows.iter().map(|&r| pending.origins[active[r]].clone()).collect(),
                fixed.iter().map(|&v| table.vars[v].name.clone()).collect(),
                format!(
                    "check that the unknowns of `{}` and the equations around it are not fixed twice",
                    pending.origins[active[r]].lines().next().unwrap_or_default()
                ),
            ));
        }
        for &v in &fixed {
            let origin = rows
                .iter()
                .find(|&&r| pending.residuals[active[r]].depends_on(&v))
                .map_or(String::new(), |&r| pending.origins[active[r]].clone());
            table.derivative(v, &origin)?;
            gained.push(v);
        }
        for &r in &rows {
            let k = active[r];
            let origin = pending.origins[k].clone();
            let mut failure = None;
            let derivative = sym::time_derivative(&pending.residuals[k], &mut |&v| {
                if pending.discrete.contains(&v) {
                    return None;
                }
                if is_rate_of_mechanics(&table.vars[v].role) {
                    // The equations differentiated, and those that use a
                    // second derivative of their variables (why).
                    let mut equations: Vec<String> = Vec::new();
                    let order = |mut v: VarId| {
                        let mut n = 0;
                        while let Role::Derivative { of } = table.vars[v].role {
                            (n, v) = (n + 1, of);
                        }
                        n
                    };
                    for &r in &rows {
                        pending.residuals[active[r]].each_var(&mut |&u| {
                            // `u` and its derivatives: where one of second order is used.
                            let mut chain = Some(u);
                            while let Some(c) = chain {
                                if order(c) >= 2 {
                                    for (k, residual) in pending.residuals[..original].iter().enumerate() {
                                        if residual.depends_on(&c) && !equations.contains(&pending.origins[k]) {
                                            equations.push(pending.origins[k].clone());
                                        }
                                    }
                                }
                                chain = table.by_name.get(&format!("der({})", table.vars[c].name)).copied();
                            }
                        });
                    }
                    for &r in &rows {
                        if !equations.contains(&pending.origins[active[r]]) {
                            equations.push(pending.origins[active[r]].clone());
                        }
                    }
                    failure.get_or_insert(needs_acceleration(&table.vars[v].name, equations));
                    return None;
                }
                match table.derivative(v, &origin) {
                    Ok(d) => Some(d),
                    Err(e) => {
                        failure.get_or_insert(needs_derivative(e, &origin));
                        None
                    }
                }
            });
            if let Some(e) = failure {
                return Err(e);
            }
            pending.residuals.push(derivative);
            pending.origins.push(origin);
            parent.push(Some(k));
            order.push(order[k] + 1);
            active[r] = pending.residuals.len() - 1;
        }
    }
    pending.dummy = vec![false; table.vars.len()];
    let mut is_gained = vec![false; table.vars.len()];
    for v in gained {
        is_gained[v] = true;
    }
    choose_dummies(pending, table, &active, &parent, &is_gained)
}

/// Dummy derivatives, level by level. First the differentiated equations
/// at their highest order decide as many of the highest derivatives in
/// them; one level down, the equations that were themselves derivatives
/// decide as many of the derivatives chosen, one order lower; and so on.
/// Each derivative chosen is computed, not integrated: the variable it is
/// the derivative of stops being a state.
fn choose_dummies(
    pending: &mut Pending,
    table: &Table,
    active: &[usize],
    parent: &[Option<usize>],
    gained: &[bool],
) -> Result<(), Error> {
    let has_derivative = derivatives(&table.vars);
    let of = |z: VarId| match table.vars[z].role {
        Role::Derivative { of } => Some(of),
        _ => None,
    };
    // The start point the coefficients are taken at: start values and
    // guesses of the declared variables, zero elsewhere.
    let value = |v: &VarId| match table.vars[*v].role {
        Role::Declared(d) => pending.declared[d].start.unwrap_or(0.0),
        _ => 0.0,
    };
    let mut level: Vec<usize> = active.iter().copied().filter(|&k| parent[k].is_some()).collect();
    let mut candidates: Vec<VarId> = Vec::new();
    for &k in &level {
        pending.residuals[k].each_var(&mut |&v| {
            if of(v).is_some() && has_derivative[v].is_none() && !candidates.contains(&v) {
                candidates.push(v);
            }
        });
    }
    while !level.is_empty() {
        // Ties (the ±1 coefficients of linear constraints) go to a
        // derivative of a derivative (so that declared variables stay
        // states), then to one whose variable became a state only through
        // the differentiation, then to the later declared.
        let rank = |c: usize| {
            let variable = of(candidates[c]).expect("candidates are derivatives");
            let declared = matches!(table.vars[variable].role, Role::Declared(_));
            (declared, !gained[variable], std::cmp::Reverse(variable))
        };
        let residuals: Vec<&sym::S> = level.iter().map(|&k| &pending.residuals[k]).collect();
        let col_of = select(&residuals, &candidates, &value, &rank);
        if let Some(r) = col_of.iter().position(|&c| c == usize::MAX) {
            return Err(problem(
                "after differentiating these equations, no variable is left for one of them to decide",
                vec![pending.origins[level[r]].clone()],
                candidates.iter().map(|&v| table.vars[v].name.clone()).collect(),
                "check that each equation between states has a variable of its own",
            ));
        }
        let chosen: Vec<VarId> = col_of.iter().map(|&c| candidates[c]).collect();
        for &z in &chosen {
            let v = of(z).expect("candidates are derivatives");
            pending.dummy[v] = true;
            if let Role::Declared(d) = table.vars[v].role {
                let declared = &pending.declared[d];
                if let (Some(start), true) = (declared.start, declared.fixed) {
                    // It is computed now; its start value holds through the initialization.
                    pending.initial.push(sym::sub(sym::var(v), sym::constant(start)));
                    let origin = if declared.origin.is_empty() { &pending.origins[level[0]] } else { &declared.origin };
                    pending.initial_origins.push(origin.clone());
                }
            }
        }
        level = level.iter().filter_map(|&k| parent[k]).filter(|&p| parent[p].is_some()).collect();
        candidates = chosen.iter().filter_map(|&z| of(z)).filter(|&v| of(v).is_some()).collect();
    }
    Ok(())
}

/// Groups of equations that share candidates at most this large are
/// chosen numerically; larger ones (rare) structurally.
const NUMERIC_GROUP: usize = 4096;

/// The candidate each equation decides (`usize::MAX` where none is left):
/// per group of equations that share candidates, Gaussian elimination of
/// their Jacobian at the start point with the largest pivot in each row
/// (ties to the best `rank`), so the derivatives chosen can be solved for;
/// where the start point is singular or the group large, a maximum
/// matching that tries candidates by `rank`.
fn select<K: PartialOrd>(
    residuals: &[&sym::S],
    candidates: &[VarId],
    value: &dyn Fn(&VarId) -> f64,
    rank: &dyn Fn(usize) -> K,
) -> Vec<usize> {
    let adjacency: Vec<Vec<usize>> = residuals
        .iter()
        .map(|r| {
            let mut cols: Vec<usize> = (0..candidates.len()).filter(|&c| r.depends_on(&candidates[c])).collect();
            cols.sort_by(|&a, &b| rank(a).partial_cmp(&rank(b)).unwrap_or(std::cmp::Ordering::Equal));
            cols
        })
        .collect();
    let mut groups = UnionFind::new(residuals.len() + candidates.len());
    for (r, cols) in adjacency.iter().enumerate() {
        for &c in cols {
            groups.union(r, residuals.len() + c);
        }
    }
    let (class, count) = groups.classes();
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut cols_of: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (r, &g) in class[..residuals.len()].iter().enumerate() {
        rows_of[g].push(r);
    }
    for (c, &g) in class[residuals.len()..].iter().enumerate() {
        cols_of[g].push(c);
    }
    let mut col_of = vec![usize::MAX; residuals.len()];
    for (rows, cols) in rows_of.iter().zip(&cols_of) {
        let numeric = (rows.len() * cols.len() <= NUMERIC_GROUP)
            .then(|| {
                pivot(
                    rows,
                    cols,
                    |r, c| sym::evaluate(&sym::derivative(residuals[r], &candidates[c]), 0.0, value),
                    rank,
                )
            })
            .flatten();
        let chosen = numeric.unwrap_or_else(|| {
            let local: Vec<Vec<usize>> = rows
                .iter()
                .map(|&r| {
                    adjacency[r].iter().map(|c| cols.iter().position(|x| x == c).expect("in the group")).collect()
                })
                .collect();
            let (matched, _) = maximum_matching(&local, cols.len());
            matched.into_iter().map(|k| if k == usize::MAX { usize::MAX } else { cols[k] }).collect()
        });
        for (&r, c) in rows.iter().zip(chosen) {
            col_of[r] = c;
        }
    }
    col_of
}

/// Gaussian elimination with the column pivot chosen per row: the column
/// (of `cols`) each row of `rows` is solved for, or `None` if a row has no
/// pivot left at this point (the point is singular for the group).
fn pivot<K: PartialOrd>(
    rows: &[usize],
    cols: &[usize],
    entry: impl Fn(usize, usize) -> f64,
    rank: &dyn Fn(usize) -> K,
) -> Option<Vec<usize>> {
    let mut a: Vec<Vec<f64>> = rows.iter().map(|&r| cols.iter().map(|&c| entry(r, c)).collect()).collect();
    let scale = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut used = vec![false; cols.len()];
    let mut chosen = Vec::with_capacity(rows.len());
    for i in 0..rows.len() {
        let largest = (0..cols.len()).filter(|&j| !used[j]).fold(0.0f64, |m, j| m.max(a[i][j].abs()));
        if largest <= 1e-10 * scale || !largest.is_finite() {
            return None;
        }
        // The largest, ties (within rounding) to the best rank.
        let j = (0..cols.len())
            .filter(|&j| !used[j] && a[i][j].abs() >= largest * (1.0 - 1e-9))
            .min_by(|&x, &y| rank(cols[x]).partial_cmp(&rank(cols[y])).unwrap_or(std::cmp::Ordering::Equal))
            .expect("the largest is among them");
        used[j] = true;
        chosen.push(cols[j]);
        let pivot_row = a[i].clone();
        for row in a.iter_mut().skip(i + 1) {
            let f = row[j] / pivot_row[j];
            if f != 0.0 {
                for (x, p) in row.iter_mut().zip(&pivot_row) {
                    *x -= f * p;
                }
            }
        }
    }
    Some(chosen)
}

/// For each variable, the variable that is its derivative, if any.
fn derivatives(vars: &[super::Var]) -> Vec<Option<VarId>> {
    let mut out = vec![None; vars.len()];
    for (d, var) in VarId::all(vars.len()).zip(vars) {
        if let Role::Derivative { of } = var.role {
            out[of] = Some(d);
        }
    }
    out
}

/// Whether a read of the mechanics is a rate, whose derivative would be
/// an acceleration.
fn is_rate_of_mechanics(role: &Role) -> bool {
    match role {
        Role::Read(Read::Axis { speed, .. }) => *speed,
        Role::Read(Read::State { rate, .. }) => *rate,
        Role::Read(Read::Frame { quantity, .. }) => matches!(
            quantity,
            FrameQuantity::Velocity(_)
                | FrameQuantity::RotationRate(..)
                | FrameQuantity::PlanarVelocity(_)
                | FrameQuantity::PlanarAngleRate
        ),
        _ => false,
    }
}

/// The error of equations whose differentiation reaches the mechanism's accelerations.
fn needs_acceleration(rate: &str, equations: Vec<String>) -> Error {
    problem(
        format!(
            "these equations fix a variable whose derivative is used too, so they are differentiated, and that \
             needs the derivative of the mechanism's `{rate}`: a second derivative of a position, its \
             acceleration, which equations cannot read"
        ),
        equations,
        vec![rate.to_string()],
        "take `der` once of what the mechanics gives (a velocity from a position); for an acceleration use a \
         sensor's output, and for a mass or inertia use Body, PointMass or RotationalComponents.Inertia",
    )
}

/// An error of differentiating an equation, saying why it was differentiated.
fn needs_derivative(e: Error, origin: &str) -> Error {
    match e {
        Error::Equations { problem: what, variables, fix, .. } => problem(
            format!("this equation fixes a variable whose derivative is used, so it is differentiated, but {what}"),
            vec![origin.to_string()],
            variables,
            fix,
        ),
        other => other,
    }
}
