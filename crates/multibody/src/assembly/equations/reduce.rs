//! Index reduction: equations that fix variables whose derivatives are
//! used too (`s_rel = flange_b.s - flange_a.s` with `v_rel = der(s_rel)`,
//! or `x = y` between two filter states) are differentiated until every
//! equation can decide an unknown (Pantelides), and for each equation
//! differentiated one of the variables it fixes stops being a state: it
//! is computed from the equation, and its derivative from the
//! differentiated one (dummy derivatives, Mattsson and Söderlind).
//!
//! The choice of those variables is structural and made once: it suits
//! the linear constraints the library's components write; a nonlinear
//! constraint whose Jacobian loses rank along the motion would need the
//! choice to change while the model runs, which is not done.

use super::{problem, Pending, Role, Table};
use crate::math::graph::maximum_matching;
use crate::math::symbolic::{self as sym, VarId};
use crate::Error;

/// Differentiates the equations the structure needs, marks in
/// `pending.dummy` the variables that stop being states, and turns a
/// fixed start value of such a variable into an initial equation.
pub(super) fn reduce(pending: &mut Pending, table: &mut Table) -> Result<(), Error> {
    let original = pending.residuals.len();
    // The equations the matching sees: an equation once differentiated
    // is seen through its derivative.
    let mut active: Vec<usize> = (0..original).collect();
    let mut differentiated: Vec<usize> = Vec::new();
    let mut gained: Vec<VarId> = Vec::new();
    loop {
        let has_derivative = derivatives(&table.vars);
        let unknown = |v: usize| match table.vars[v].role {
            Role::Declared(_) => has_derivative[v].is_none() && !pending.discrete.contains(&VarId::new(v)),
            Role::Derivative { .. } | Role::Written { .. } => true,
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
        let is_state = |v: VarId| matches!(table.vars[v].role, Role::Declared(_)) && has_derivative[v].is_some();
        let fixes_state = rows.iter().any(|&r| {
            let mut found = false;
            pending.residuals[active[r]].each_var(&mut |&v| found |= is_state(v));
            found
        });
        let variable_of_column: Vec<VarId> =
            VarId::all(table.vars.len()).filter(|&v| column[v] != usize::MAX).collect();
        let fixed: Vec<VarId> = cols.iter().map(|&c| variable_of_column[c]).collect();
        let second = fixed.iter().find(|&&v| matches!(table.vars[v].role, Role::Derivative { .. }));
        if let (Some(&d), true) = (second, fixes_state) {
            // Its own derivative would be needed: a second differentiation.
            let name = table.vars[d].name.clone();
            return Err(problem(
                format!(
                    "these equations fix `{name}`, whose derivative is used too: that needs `der({name})`, a second \
                     derivative (index 3), which is not supported; of a position it would be the mechanism's \
                     acceleration, which equations cannot read"
                ),
                rows.iter().map(|&r| pending.origins[active[r]].clone()).collect(),
                vec![name],
                "take `der` once of what the mechanics gives (a velocity from a position); for an acceleration use \
                 a sensor's output",
            ));
        }
        let helps = fixes_state
            && rows.iter().all(|&r| {
                let mut own = false;
                pending.residuals[active[r]].each_var(&mut |&v| own |= !matches!(table.vars[v].role, Role::Read(_)));
                own && active[r] < original
            });
        if !helps {
            // A constraint on the mechanism alone, or a second
            // differentiation: the sorting names the equations.
            break;
        }
        if !fixed.iter().all(|&v| matches!(table.vars[v].role, Role::Declared(_))) {
            // A signal's rate would be needed: the sorting names the equations.
            break;
        }
        for &v in &fixed {
            let origin = rows
                .iter()
                .find(|&&r| {
                    let mut found = false;
                    pending.residuals[active[r]].each_var(&mut |&w| found |= w == v);
                    found
                })
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
                match table.derivative(v, &origin) {
                    Ok(d) => Some(d),
                    Err(e) => {
                        failure.get_or_insert(e);
                        None
                    }
                }
            });
            if let Some(e) = failure {
                return Err(needs_derivative(e, &origin));
            }
            pending.residuals.push(derivative);
            pending.origins.push(origin);
            active[r] = pending.residuals.len() - 1;
            differentiated.push(k);
        }
    }
    pending.dummy = vec![false; table.vars.len()];
    if differentiated.is_empty() {
        return Ok(());
    }

    // One variable per differentiated equation stops being a state,
    // preferring those that became states only through the differentiation.
    let has_derivative = derivatives(&table.vars);
    let mut candidates: Vec<VarId> = Vec::new();
    for &k in &differentiated {
        pending.residuals[k].each_var(&mut |&v| {
            if has_derivative[v].is_some() && !candidates.contains(&v) {
                candidates.push(v);
            }
        });
    }
    candidates.sort_by_key(|&v| (!gained.contains(&v), std::cmp::Reverse(v)));
    let adjacency: Vec<Vec<usize>> = differentiated
        .iter()
        .map(|&k| {
            let mut cols = Vec::new();
            for (c, &v) in candidates.iter().enumerate() {
                if pending.residuals[k].depends_on(&v) {
                    cols.push(c);
                }
            }
            cols
        })
        .collect();
    let (col_of, _) = maximum_matching(&adjacency, candidates.len());
    if let Some(r) = col_of.iter().position(|&c| c == usize::MAX) {
        return Err(problem(
            "after differentiating these equations, no variable is left for one of them to decide",
            vec![pending.origins[differentiated[r]].clone()],
            candidates.iter().map(|&v| table.vars[v].name.clone()).collect(),
            "check that each equation between states has a variable of its own",
        ));
    }
    for &c in &col_of {
        let v = candidates[c];
        pending.dummy[v] = true;
        if let Role::Declared(d) = table.vars[v].role {
            let declared = &pending.declared[d];
            if let (Some(start), true) = (declared.start, declared.fixed) {
                // It is computed now; its start value holds through the initialization.
                pending.initial.push(sym::sub(sym::var(v), sym::constant(start)));
                let origin =
                    if declared.origin.is_empty() { &pending.origins[differentiated[0]] } else { &declared.origin };
                pending.initial_origins.push(origin.clone());
            }
        }
    }
    Ok(())
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
