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
    for (r, e) in out.iter_mut().zip(&init.residuals) {
        *r = evaluate(e, t0, &|v| ws.registers[init.registers[v] as usize]);
    }
    Ok(())
}

/// Moves the free start values until the initial equations hold.
pub(crate) fn solve(mechanism: &mut Mechanism, init: &Initial) -> Result<(), Error> {
    let (m, k) = (init.residuals.len(), init.free.len());
    if m == 0 {
        return Ok(());
    }
    if m > k {
        return Err(problem(
            format!(
                "{m} initial equation{} but {k} state{} free to satisfy them{}",
                if m == 1 { "" } else { "s" },
                if k == 1 { "" } else { "s" },
                if init.free_names.is_empty() { String::new() } else { format!(" ({})", init.free_names.join(", ")) }
            ),
            init.origins.clone(),
            init.free_names.clone(),
            if k == 0 {
                "the start of the mechanism comes from its joints' and masses' start values (`initial`), which \
                 initial equations and start values of computed variables do not move yet: give the start there, \
                 or make this value a `guess`"
            } else {
                "remove initial equations, or leave more start values free (a `guess` instead of an `initial` value)"
            },
        ));
    }
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
        for (j, &i) in init.free.iter().enumerate() {
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
                init.free_names.clone(),
                "check that each initial equation involves a state whose start value is free",
            ));
        }
        let mut w = r.clone();
        cholesky_solve(&jjt, m, &mut w);
        for (j, &i) in init.free.iter().enumerate() {
            y[i] -= (0..m).map(|a| jac[a * k + j] * w[a]).sum::<f64>();
        }
    }
    Err(problem(
        "Newton's method found no start that satisfies the initial equations",
        init.origins.clone(),
        init.free_names.clone(),
        "give the states better start values (`guess`), or check the initial equations",
    ))
}
