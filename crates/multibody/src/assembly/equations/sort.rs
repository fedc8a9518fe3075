//! From residuals to sorted blocks: aliases out, unknowns matched to
//! equations, blocks of equations that must be solved together in the
//! order they depend on each other (BLT). A system that does not match is
//! an error that names the variables and equations concerned.

use super::{problem, Pending, Read, Role, Source};
use crate::math::graph::{maximum_matching, strongly_connected_components};
use crate::math::symbolic::{self as sym, Sym, VarId, S};
use crate::Error;

/// The sorted equations.
pub(super) struct Sorted {
    /// Per variable: the unknown it is an alias of and the sign
    /// (`v = sign * of`), for aliases.
    pub alias: Vec<Option<(VarId, f64)>>,
    /// The residuals that remain, with the aliases substituted.
    pub residuals: Vec<S>,
    /// Index into the pending residuals of each remaining one (for messages).
    pub source: Vec<usize>,
    /// Blocks in evaluation order: equation indices (into `residuals`) and
    /// the unknowns they solve for, in matching order.
    pub blocks: Vec<(Vec<usize>, Vec<VarId>)>,
    /// The declared variables that are states, in order.
    pub states: Vec<VarId>,
    /// For each state (in `states` order), its derivative variable.
    pub rates: Vec<VarId>,
}

/// Whether variable `v` is an unknown the equations decide.
pub(super) fn is_unknown(pending: &Pending, is_state: &[bool], v: VarId) -> bool {
    match pending.vars[v].role {
        Role::Declared(_) => !is_state[v] && pending.discrete_slot(v).is_none(),
        // A derivative is integrated where its own derivative is.
        Role::Derivative { .. } => !is_state[v],
        Role::Written { .. } => true,
        Role::Read(_) => false,
    }
}

pub(super) fn sort(pending: &Pending, reads: &[Option<Source>]) -> Result<Sorted, Error> {
    let n = pending.vars.len();
    let mut is_state = vec![false; n];
    let mut states = Vec::new();
    let mut rates = Vec::new();
    for (d, var) in VarId::all(n).zip(&pending.vars) {
        if let Role::Derivative { of } = var.role {
            if pending.dummy[of] {
                continue;
            }
            is_state[of] = true;
            states.push(of);
            rates.push(d);
        }
    }
    // States in declaration order (rates follow).
    let mut order: Vec<usize> = (0..states.len()).collect();
    order.sort_by_key(|&k| states[k]);
    let states: Vec<VarId> = order.iter().map(|&k| states[k]).collect();
    let rates: Vec<VarId> = order.iter().map(|&k| rates[k]).collect();
    let unknown = |v: VarId| is_unknown(pending, &is_state, v);

    // Aliases: `a = s b` between two unknowns, one class per set of them.
    let mut classes = SignedSets::new(n);
    let mut kept = Vec::new();
    for (k, r) in pending.residuals.iter().enumerate() {
        match alias_of(r, &unknown) {
            Some((a, b, s)) if classes.join(a.index(), b.index(), s) => {}
            _ => kept.push(k),
        }
    }
    // The representative of each class: a declared variable where there is one.
    let rank = |v: usize| match pending.vars[v].role {
        Role::Declared(_) => 0,
        Role::Derivative { .. } => 1,
        _ => 2,
    };
    let mut best: Vec<usize> = (0..n).collect();
    for v in 0..n {
        let (root, _) = classes.find(v);
        if (rank(v), v) < (rank(best[root]), best[root]) {
            best[root] = v;
        }
    }
    let alias: Vec<Option<(VarId, f64)>> = (0..n)
        .map(|v| {
            let (root, s_v) = classes.find(v);
            let rep = best[root];
            // v = s_v root, rep = s_rep root: v = s_v s_rep rep.
            (rep != v).then(|| (VarId::new(rep), s_v * classes.find(rep).1))
        })
        .collect();
    let substitute =
        |&v: &VarId| alias[v].map(|(rep, s)| if s > 0.0 { sym::var(rep) } else { sym::neg(sym::var(rep)) });
    let residuals: Vec<S> = kept.iter().map(|&k| sym::substitute_all(&pending.residuals[k], &substitute)).collect();

    // Match the unknowns that remain to the equations.
    let unknowns: Vec<VarId> = VarId::all(n).filter(|&v| unknown(v) && alias[v].is_none()).collect();
    let mut column = vec![usize::MAX; n];
    for (c, &v) in unknowns.iter().enumerate() {
        column[v] = c;
    }
    let mut adjacency = Vec::with_capacity(residuals.len());
    for (k, r) in residuals.iter().enumerate() {
        let mut cols = Vec::new();
        r.each_var(&mut |&v| {
            if column[v] != usize::MAX && !cols.contains(&column[v]) {
                cols.push(column[v]);
            }
        });
        if cols.is_empty() {
            return Err(no_unknown(pending, reads, r, &pending.origins[kept[k]]));
        }
        adjacency.push(cols);
    }
    let (col_of, row_of) = maximum_matching(&adjacency, unknowns.len());
    let free: Vec<usize> = (0..unknowns.len()).filter(|&c| row_of[c] == usize::MAX).collect();
    let extra: Vec<usize> = (0..residuals.len()).filter(|&r| col_of[r] == usize::MAX).collect();
    if !extra.is_empty() {
        // The equations an unmatched one competes with: reachable through its unknowns.
        let mut seen = vec![false; residuals.len()];
        let mut stack = extra.clone();
        let mut involved = Vec::new();
        while let Some(r) = stack.pop() {
            if std::mem::replace(&mut seen[r], true) {
                continue;
            }
            involved.push(r);
            for &c in &adjacency[r] {
                if row_of[c] != usize::MAX {
                    stack.push(row_of[c]);
                }
            }
        }
        involved.sort_unstable();
        let mut vars: Vec<String> = Vec::new();
        for &r in &involved {
            for &c in &adjacency[r] {
                let name = pending.vars[unknowns[c]].name.clone();
                if !vars.contains(&name) {
                    vars.push(name);
                }
            }
        }
        if !free.is_empty() {
            // Equations that fix what is decided already, beside unknowns
            // that nothing decides: the unknowns act only through what the
            // equations fix (a motion prescribed with its forces unknown),
            // a problem of higher index, not one of too many equations.
            let undecided: Vec<String> = free.iter().map(|&c| pending.vars[unknowns[c]].name.clone()).collect();
            return Err(problem(
                format!(
                    "these equations fix {} that the other equations decide already, while nothing decides `{}`: \
                     the unknowns act on what the equations fix only through the motion (through its derivatives), \
                     a problem of higher index (a motion prescribed with unknown forces); it is solved where the \
                     equations set coordinates of one frame's position to formulas of time and as many unknowns \
                     drive 1-D sources on the joints, which is not the case here",
                    vars.join(", "),
                    undecided.join("`, `")
                ),
                involved.iter().map(|&r| pending.origins[kept[r]].clone()).collect(),
                undecided,
                "prescribe as many coordinates of the frame's position as there are unknown efforts, each a formula \
                 of time, or prescribe the motion on the joints (RotationalComponents.Position), or give the unknown \
                 forces by equations of their own",
            ));
        }
        return Err(problem(
            format!(
                "too many equations: {} equation{} for {} unknown{} ({})",
                involved.len(),
                if involved.len() == 1 { "" } else { "s" },
                vars.len(),
                if vars.len() == 1 { "" } else { "s" },
                vars.join(", ")
            ),
            involved.iter().map(|&r| pending.origins[kept[r]].clone()).collect(),
            vars,
            "remove one of these equations, or declare another variable they decide",
        ));
    }
    if !free.is_empty() {
        let names: Vec<String> = free.iter().map(|&c| pending.vars[unknowns[c]].name.clone()).collect();
        let written = free.iter().any(|&c| matches!(pending.vars[unknowns[c]].role, Role::Written { .. }));
        // The under-determined part (Dulmage-Mendelsohn): the equations
        // that could decide an undecided unknown, were their own unknown
        // decided elsewhere (alternating paths from the free columns).
        let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); unknowns.len()];
        for (r, cols) in adjacency.iter().enumerate() {
            for &c in cols {
                rows_of[c].push(r);
            }
        }
        let (mut seen, mut stack, mut part) = (vec![false; unknowns.len()], free.clone(), Vec::new());
        while let Some(c) = stack.pop() {
            if std::mem::replace(&mut seen[c], true) {
                continue;
            }
            for &r in &rows_of[c] {
                if !part.contains(&r) {
                    part.push(r);
                    stack.push(col_of[r]);
                }
            }
        }
        part.sort_unstable();
        let mut also: Vec<String> = part.iter().map(|&r| pending.vars[unknowns[col_of[r]]].name.clone()).collect();
        also.dedup();
        return Err(problem(
            format!(
                "too few equations: nothing decides {} `{}`{}",
                if names.len() == 1 { "the unknown" } else { "the unknowns" },
                names.join("`, `"),
                if also.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; the equations that name {} decide `{}` already",
                        if names.len() == 1 { "it" } else { "them" },
                        also.join("`, `")
                    )
                }
            ),
            part.iter().map(|&r| pending.origins[kept[r]].clone()).collect(),
            names.iter().map(|n| declaration_of(pending, n)).collect(),
            if written {
                "give each an equation; a signal input needs a source or an equation that gives its value"
            } else {
                "give each an equation, or a value (`variable x::Real = ...`)"
            },
        ));
    }

    // Blocks: equation r depends on the equations that decide the unknowns it reads.
    let edges: Vec<Vec<usize>> = adjacency
        .iter()
        .enumerate()
        .map(|(r, cols)| cols.iter().map(|&c| row_of[c]).filter(|&other| other != r).collect())
        .collect();
    let blocks = strongly_connected_components(&edges)
        .into_iter()
        .map(|rows| {
            let unknowns_of: Vec<VarId> = rows.iter().map(|&r| unknowns[col_of[r]]).collect();
            (rows, unknowns_of)
        })
        .collect();
    Ok(Sorted { alias, residuals, source: kept, blocks, states, rates })
}

/// The declaration of a variable, for messages: its origin if it has one.
fn declaration_of(pending: &Pending, name: &str) -> String {
    pending.declared.iter().find(|d| d.name == name).map_or_else(|| name.to_string(), |d| d.name.clone())
}

/// `(a, b, s)` if residual `r` says `a = s b` for two unknowns.
fn alias_of(r: &S, unknown: &impl Fn(VarId) -> bool) -> Option<(VarId, VarId, f64)> {
    let mut vars = Vec::new();
    r.each_var(&mut |&v| {
        if !vars.contains(&v) {
            vars.push(v);
        }
    });
    if vars.len() != 2 || !vars.iter().all(|&v| unknown(v)) || r.mentions_time() {
        return None;
    }
    let (a, b) = (vars[0], vars[1]);
    let (slope_a, rest) = sym::affine_in(r, &a)?;
    let (slope_b, constant) = sym::affine_in(&rest, &b)?;
    let (sa, sb) = (slope_a.as_const()?, slope_b.as_const()?);
    if sa.abs() != 1.0 || sb.abs() != 1.0 || constant.as_const() != Some(0.0) {
        return None;
    }
    // sa a + sb b = 0: a = -(sb / sa) b.
    Some((a, b, -sb * sa))
}

/// The error for an equation that has no unknown left: it constrains
/// what something else decides.
fn no_unknown(pending: &Pending, reads: &[Option<Source>], r: &Sym, origin: &str) -> Error {
    let mut mechanics = Vec::new();
    let mut own_states = Vec::new();
    r.each_var(&mut |&v| {
        let name = pending.vars[v].name.clone();
        match (&pending.vars[v].role, &reads[v]) {
            (
                Role::Read(Read::Frame { .. } | Read::Axis { .. } | Read::AxisAcceleration { .. } | Read::State { .. }),
                _,
            ) if !mechanics.contains(&name) => mechanics.push(name),
            (Role::Declared(_), _) if !own_states.contains(&name) => own_states.push(name),
            _ => {}
        }
    });
    if !mechanics.is_empty() && !own_states.is_empty() {
        // A connector's quantity equal to the mechanism's, whose `der` the equations take.
        return problem(
            format!(
                "`der` is taken of `{}`, which is the mechanism's `{}`: the derivative of a connector's quantity \
                 is not supported yet",
                own_states.join("`, `"),
                mechanics.join("`, `")
            ),
            vec![origin.to_string()],
            own_states,
            "measure the velocity with a sensor (AbsoluteVelocity, RelativeVelocity, or their PlanarMechanics \
             versions) and use its output in the equations",
        );
    }
    if !mechanics.is_empty() {
        return problem(
            format!(
                "this equation constrains the motion of the mechanism (`{}`), which its joints decide",
                mechanics.join("`, `")
            ),
            vec![origin.to_string()],
            mechanics,
            "to impose a motion, drive the joint with a position source (RotationalComponents.Position on its axis, \
             PrescribedPosition); to hold frames together, connect them with a joint or a constraint component; for a \
             mass on a frame use Body or PointMass",
        );
    }
    if !own_states.is_empty() {
        return problem(
            format!(
                "`{}` is given by this equation, and its derivative is used too, and differentiating the \
                 equations does not decide it",
                own_states.join("`, `")
            ),
            vec![origin.to_string()],
            own_states,
            "take `der` of a variable that only `der` decides (a state), or use BlockComponents.Derivative for the \
             rate of a signal; if this equation holds at the start only, make it `initial`",
        );
    }
    problem(
        "this equation has no unknown: everything in it is known already",
        vec![origin.to_string()],
        vec![],
        "remove it, or make one of its names a variable the equations decide",
    )
}

/// Union-find over variables with a sign on each edge: `v = sign * parent`.
struct SignedSets {
    parent: Vec<usize>,
    sign: Vec<f64>,
}

impl SignedSets {
    fn new(n: usize) -> Self {
        Self { parent: (0..n).collect(), sign: vec![1.0; n] }
    }

    /// The root of `v` and the sign with `v = sign * root`.
    fn find(&mut self, v: usize) -> (usize, f64) {
        let mut s = 1.0;
        let mut x = v;
        while self.parent[x] != x {
            s *= self.sign[x];
            x = self.parent[x];
        }
        // Compress: point v straight at the root.
        self.parent[v] = x;
        self.sign[v] = s;
        (x, s)
    }

    /// Joins `a = s b`; false when they are already joined (the equation
    /// then stays an equation: redundant, or it says they are zero).
    fn join(&mut self, a: usize, b: usize, s: f64) -> bool {
        let (ra, sa) = self.find(a);
        let (rb, sb) = self.find(b);
        if ra == rb {
            return false;
        }
        // a = sa ra, b = sb rb, a = s b: ra = sa s sb rb.
        self.parent[ra] = rb;
        self.sign[ra] = sa * s * sb;
        true
    }
}
