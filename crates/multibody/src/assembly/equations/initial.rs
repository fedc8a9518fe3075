//! Initial equations (`initial der(x) = 0`, `initial y = 1`): they hold at
//! the start only. Their unknowns are the states of the equations whose
//! start values the model did not fix; Newton's method (least-norm steps,
//! a finite-difference Jacobian through the whole right-hand side) moves
//! those start values as little as it can until they hold.

use super::problem;
use crate::dynamics::Workspace;
use crate::math::dense::{cholesky, cholesky_solve};
use crate::math::symbolic::{evaluate, S};
use crate::system::equations::Reg;
use crate::{Error, Mechanism};

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
}

/// The residuals of the initial equations at the state `y`.
fn residuals(m: &Mechanism, ws: &mut Workspace, init: &Initial, y: &[f64], out: &mut [f64]) -> Result<(), Error> {
    let mut dy = vec![0.0; y.len()];
    let t0 = 0.0;
    // At the start relations hold as they are (as in the first event iteration).
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
    newton(mechanism, init, &free, &names)
}

/// The start values of the mechanism that the initial equations may move:
/// positions and velocities of joints with one coordinate (revolute,
/// prismatic, 1-D inertias and masses) that the model did not fix and that
/// no motion drives; none while loops are closed (moving one joint would
/// open them).
fn mechanical_free(mechanism: &Mechanism) -> Vec<(usize, String)> {
    let system = &mechanism.system;
    if system.constraint_rows > 0 {
        return Vec::new();
    }
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

/// Newton's method with least-norm steps over the start values `free`.
fn newton(mechanism: &mut Mechanism, init: &Initial, free: &[usize], free_names: &[String]) -> Result<(), Error> {
    let (m, k) = (init.residuals.len(), free.len());
    let mut ws = mechanism.workspace();
    let mut y = mechanism.system.states.start.clone();
    let (mut r, mut trial) = (vec![0.0; m], vec![0.0; m]);
    let mut jac = vec![0.0; m * k];
    for _ in 0..ITERATIONS {
        residuals(mechanism, &mut ws, init, &y, &mut r)?;
        if r.iter().all(|x| x.abs() <= TOLERANCE) {
            mechanism.system.states.start = y;
            return Ok(());
        }
        for (j, &i) in free.iter().enumerate() {
            let h = 1e-7 * (1.0 + y[i].abs());
            let keep = y[i];
            y[i] += h;
            residuals(mechanism, &mut ws, init, &y, &mut trial)?;
            y[i] = keep;
            for row in 0..m {
                jac[row * k + j] = (trial[row] - r[row]) / h;
            }
        }
        // Least-norm step: dz = -J' (J J')^-1 r.
        let mut jjt = vec![0.0; m * m];
        for a in 0..m {
            for b in 0..m {
                jjt[a * m + b] = (0..k).map(|j| jac[a * k + j] * jac[b * k + j]).sum();
            }
        }
        if !cholesky(&mut jjt, m) {
            return Err(problem(
                "the initial equations do not determine the free start values (their Jacobian is singular)",
                init.origins.clone(),
                free_names.to_vec(),
                "check that each initial equation involves a state whose start value is free",
            ));
        }
        let mut w = r.clone();
        cholesky_solve(&jjt, m, &mut w);
        for (j, &i) in free.iter().enumerate() {
            y[i] -= (0..m).map(|a| jac[a * k + j] * w[a]).sum::<f64>();
        }
    }
    Err(problem(
        "Newton's method found no start that satisfies the initial equations",
        init.origins.clone(),
        free_names.to_vec(),
        "give the states better start values (`guess`), or check the initial equations",
    ))
}
