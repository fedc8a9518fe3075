//! Register code for sorted equations: a closed form for a block of one
//! equation linear in its unknown, Newton with an exact Jacobian
//! otherwise; loads of the signals a block reads, stores of the signals
//! and flows it writes; and the blocks' places among the signal blocks.

use super::sort::{is_unknown, Sorted};
use super::tearing;
use super::{problem, Context, Pending, PendingAction, Read, Role, Source};
use crate::assembly::signals::Signals;
use crate::math::expr::Cmp;
use crate::math::sparse::SparseLu;
use crate::math::symbolic::{self as sym, Sym, VarId, S};
use crate::math::tape::{Leaf, Leaves, Writer};
use crate::system::equations::{EquationBlock, EquationProgram, Gather, Jacobian, Op, Reg, Solve, TIME};
use crate::system::{Attachment, EventLayout, SignalLaw, StateLayout};
use crate::Error;
use std::collections::{BinaryHeap, HashMap, HashSet};
use std::ops::Range;

/// The equations' code being written: its instructions (by the one
/// [`Writer`]) and what their events add.
struct Emitter {
    w: Writer<VarId>,
    events: Events,
}

/// What the equations' events add while their code is written.
struct Events {
    /// Whether relations are emitted without events (inside `noEvent`,
    /// and in what `when` clauses do, which runs at events only).
    live: bool,
    /// What the equations add to the indicators and the discrete state:
    /// where their numbers start, and each one's name and start value.
    first_indicator: usize,
    first_discrete: usize,
    indicators: Vec<String>,
    discrete: Vec<f64>,
    /// The discrete slot of each variable that has one.
    discrete_of: Vec<Option<usize>>,
    /// The equations being written, to name their indicators.
    label: String,
    /// The `sample`s met, each once.
    samples: Vec<crate::system::equations::Sample>,
}

impl Events {
    /// A new slot of the discrete state with its start value.
    fn discrete_slot(&mut self, start: f64) -> u32 {
        self.discrete.push(start);
        (self.first_discrete + self.discrete.len() - 1) as u32
    }
}

/// The equations' leaves: variables in their registers, time, and the
/// instructions of events.
struct Program<'a> {
    vars: &'a [Reg],
    events: &'a mut Events,
}

impl Leaves<VarId> for Program<'_> {
    fn leaf(&mut self, w: &mut Writer<VarId>, e: &S) -> Option<Leaf> {
        Some(match &**e {
            Sym::Time => Leaf::At(TIME),
            Sym::Var(v) => Leaf::At(self.vars[*v]),
            Sym::Der(_) => unreachable!("assembly gives every derivative a variable of its own"),
            // Before the event: a discrete variable's value at the start
            // of the pass; any other's is its left limit, the value now.
            Sym::Pre(v) => match self.events.discrete_of[*v] {
                Some(slot) => {
                    let d = w.register();
                    w.ops.push(Op::LoadPre(d, slot as u32));
                    Leaf::Written(d)
                }
                None => Leaf::At(self.vars[*v]),
            },
            Sym::Initial => {
                let d = w.register();
                w.ops.push(Op::Initial(d));
                Leaf::Written(d)
            }
            &Sym::Sample { start, interval } => {
                let sample = crate::system::equations::Sample { start, interval };
                let samples = &mut self.events.samples;
                let index = samples.iter().position(|s| *s == sample).unwrap_or_else(|| {
                    samples.push(sample);
                    samples.len() - 1
                });
                let dst = w.register();
                w.ops.push(Op::Sample { dst, index: index as u32 });
                Leaf::Written(dst)
            }
            Sym::NoEvent(a) => {
                let was = std::mem::replace(&mut self.events.live, true);
                let r = w.write(a, self);
                self.events.live = was;
                Leaf::At(r)
            }
            Sym::Edge(a) => {
                let cond = w.write(a, self);
                let impulse = mentions_sample(a);
                let (dst, slot) =
                    (w.register(), self.events.discrete_slot(if impulse { f64::NEG_INFINITY } else { 0.0 }));
                w.ops.push(Op::Fire { dst, cond, slot, at_start: false, impulse });
                Leaf::Written(dst)
            }
            Sym::Change(a) => {
                let value = w.write(a, self);
                let (dst, slot) = (w.register(), self.events.discrete_slot(0.0));
                w.ops.push(Op::Change { dst, value, slot });
                Leaf::Written(dst)
            }
            Sym::Compare(cmp @ (Cmp::Lt | Cmp::Le | Cmp::Gt | Cmp::Ge), a, b) if !self.events.live => {
                let (a, b) = (w.write(a, self), w.write(b, self));
                let dst = w.register();
                let events = &mut *self.events;
                let indicator = (events.first_indicator + events.indicators.len()) as u32;
                events.indicators.push(format!("the relation in {}", events.label));
                let slot = events.discrete_slot(0.0);
                w.ops.push(Op::Relation { cmp: *cmp, dst, a, b, indicator, slot });
                Leaf::Written(dst)
            }
            _ => return None,
        })
    }
}

impl Emitter {
    fn register(&mut self) -> Reg {
        self.w.register()
    }

    /// Code that leaves the value of `e` in a register, which it returns.
    fn emit(&mut self, e: &S, vars: &[Reg]) -> Reg {
        self.w.write(e, &mut Program { vars, events: &mut self.events })
    }

    /// Code that leaves the value of `e` in register `target`.
    fn emit_into(&mut self, e: &S, vars: &[Reg], target: Reg) {
        let before = self.w.ops.len();
        let r = self.emit(e, vars);
        // Write the last op's result straight into the target when it made it.
        let last = self.w.ops.len().checked_sub(1).filter(|&i| i >= before);
        match last.and_then(|i| Op::dst_mut(&mut self.w.ops[i])).filter(|d| **d == r) {
            Some(d) => {
                *d = target;
                // The temporary is never written now: later uses read the target.
                self.w.remember(e, target);
            }
            None => self.w.ops.push(Op::Copy(target, r)),
        }
    }

    fn new_block(&mut self) {
        self.w.forget();
    }
}

/// The signal slot of the connector `local` of the hidden component `extra`.
fn slot_of(ctx: &Context, signals: &Signals, extra: &str, local: &str) -> usize {
    let id = super::connector_id(ctx, &format!("{extra}.{local}")).expect("hidden components are built");
    signals.of_connector[id]
}

pub(super) fn generate(
    pending: &Pending,
    reads: &[Option<Source>],
    sorted: &Sorted,
    ctx: &Context,
    signals: &mut Signals,
    states: &mut StateLayout,
    events: &mut EventLayout,
) -> Result<(EquationProgram, Vec<Reg>), Error> {
    let n = pending.vars.len();
    let mut discrete_of = vec![None; n];
    for (k, &v) in pending.discrete.iter().enumerate() {
        discrete_of[v] = Some(events.discrete_start.len() + k);
    }
    let mut em = Emitter {
        // Register 0 is time.
        w: Writer::new(1),
        events: Events {
            live: false,
            first_indicator: events.indicators.len(),
            first_discrete: events.discrete_start.len(),
            indicators: Vec::new(),
            discrete: pending
                .discrete
                .iter()
                .map(|&v| match pending.vars[v].role {
                    Role::Declared(d) => pending.declared[d].start.unwrap_or(0.0),
                    _ => 0.0,
                })
                .collect(),
            discrete_of,
            label: String::new(),
            samples: Vec::new(),
        },
    };
    let mut reg = vec![Reg::MAX; n];
    let mut slot_reads: Vec<Option<usize>> = vec![None; n];
    let mut frames: Vec<(usize, Vec<_>)> = Vec::new();
    let mut gathers = Vec::new();
    let mut flange_gathers: HashMap<String, usize> = HashMap::new();
    let mut reactions = Vec::new();
    for (v, source) in reads.iter().enumerate() {
        let Some(source) = source else { continue };
        reg[v] = em.register();
        match source {
            Source::Slot(slot) => slot_reads[v] = Some(*slot),
            Source::Frame { node, quantity } => match frames.iter_mut().find(|(n, _)| n == node) {
                Some((_, list)) => list.push((*quantity, reg[v])),
                None => frames.push((*node, vec![(*quantity, reg[v])])),
            },
            Source::Axis { flange, speed } => {
                // A connector's position and speed come from one motion.
                let k = *flange_gathers.entry(format!("{flange:?}")).or_insert_with(|| {
                    gathers.push(Gather::Flange { at: *flange, position: None, speed: None });
                    gathers.len() - 1
                });
                if let Gather::Flange { position, speed: rate, .. } = &mut gathers[k] {
                    // Two names of one quantity share its register.
                    reg[v] = *if *speed { rate } else { position }.get_or_insert(reg[v]);
                }
            }
            Source::State(index) => gathers.push(Gather::State { index: *index, register: reg[v] }),
            Source::Discrete(k) => {
                gathers.push(Gather::Discrete { slot: em.events.first_discrete + k, register: reg[v] })
            }
            Source::Reaction(row) => reactions.push((*row, reg[v])),
            // Filled by the initialization from the accelerations.
            Source::Rate(_) => {}
        }
    }
    let reads_frames = !frames.is_empty();
    for (node, reads) in frames {
        let at = Attachment { anchor: ctx.tree.nodes[node].anchor, pose: ctx.tree.nodes[node].pose };
        if let crate::system::Anchor::Massless(_) = at.anchor {
            return Err(problem(
                "equations read the motion of a frame without mass, which force elements alone hold",
                vec![],
                vec![],
                "give that frame mass, or read another frame",
            ));
        }
        gathers.insert(0, Gather::Frame { at, reads });
    }

    // States, then unknowns; an alias shares its unknown's register, or
    // (negated) gets its own.
    let first_state = em.w.registers as Reg;
    for &s in &sorted.states {
        reg[s] = em.register();
    }
    let mut is_state = vec![false; n];
    for &s in &sorted.states {
        is_state[s] = true;
    }
    for (v, r) in VarId::all(n).zip(reg.iter_mut()) {
        if is_unknown(pending, &is_state, v) && sorted.alias[v].is_none() {
            *r = em.register();
            if let Role::Declared(d) = pending.vars[v].role {
                if let Some(start) = pending.declared[d].start {
                    em.w.preset.push((*r, start));
                }
            }
        }
    }
    let mut negated = Vec::new();
    for v in 0..n {
        match sorted.alias[v] {
            Some((of, s)) if s > 0.0 => reg[v] = reg[of],
            Some((of, _)) => {
                reg[v] = em.register();
                negated.push((v, of));
            }
            None => {}
        }
    }

    // Each unknown with its aliases.
    let mut members: Vec<Vec<usize>> = (0..n).map(|v| vec![v]).collect();
    for v in 0..n {
        if let Some((of, _)) = sorted.alias[v] {
            members[of].push(v);
        }
    }
    // What each unknown's block must store: written inputs and flows.
    let mut stores_of: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (v, var) in pending.vars.iter().enumerate() {
        if let Role::Written { extra } = &var.role {
            stores_of[v].push(slot_of(ctx, signals, extra, "y"));
        }
    }
    for (v, extra, local) in &pending.stores {
        stores_of[*v].push(slot_of(ctx, signals, extra, local));
    }

    let mut blocks: Vec<EquationBlock> = Vec::with_capacity(sorted.blocks.len());
    let mut block_reads: Vec<Vec<usize>> = Vec::with_capacity(sorted.blocks.len());
    let mut block_writes: Vec<Vec<usize>> = Vec::with_capacity(sorted.blocks.len());
    let mut block_of_unknown = vec![usize::MAX; n];
    let mut block_deps: Vec<Vec<usize>> = Vec::with_capacity(sorted.blocks.len());
    let mut reads_reaction = Vec::with_capacity(sorted.blocks.len());
    let mut largest_block = 0;
    let mut largest_factors = 0;
    for (b, (rows, unknowns)) in sorted.blocks.iter().enumerate() {
        em.new_block();
        for &u in unknowns {
            block_of_unknown[u] = b;
        }
        let residuals: Vec<&S> = rows.iter().map(|&r| &sorted.residuals[r]).collect();
        let mut mentioned = Vec::new();
        let mut seen = HashSet::new();
        for r in &residuals {
            r.each_var(&mut |&v| {
                if seen.insert(v) {
                    mentioned.push(v);
                }
            });
        }
        reads_reaction.push(mentioned.iter().any(|&v| matches!(reads[v], Some(Source::Reaction(_)))));
        let before = em.w.ops.len();
        let mut loads = Vec::new();
        let mut deps = Vec::new();
        for &v in &mentioned {
            if let Some(slot) = slot_reads[v] {
                em.w.ops.push(Op::Load(reg[v], slot));
                loads.push(slot);
            }
            let other = block_of_unknown[v];
            if other != usize::MAX && other != b && !deps.contains(&other) {
                deps.push(other);
            }
        }
        // Each equation once: the rows of a `for` share their origin.
        let mut label: Vec<&str> = Vec::new();
        let mut labelled = HashSet::new();
        for &r in rows {
            let origin = pending.origins[sorted.source[r]].as_str();
            if labelled.insert(origin) {
                label.push(origin);
            }
        }
        let label = label.join("; ");
        em.events.label.clone_from(&label);
        let solve = match (residuals.as_slice(), unknowns.as_slice()) {
            ([r], [x]) if explicit(r, *x).is_some() => {
                let value = explicit(r, *x).expect("checked");
                match &*value {
                    // `x` is what the mechanics gives (a connector's position
                    // written as its own variable): it reads the same register,
                    // and so do its aliases, rather than copying it.
                    Sym::Var(w) if reads[*w].is_some() => {
                        let (from, to) = (reg[*x], reg[*w]);
                        for &v in &members[*x] {
                            if reg[v] == from {
                                reg[v] = to;
                            }
                        }
                    }
                    _ => em.emit_into(&value, &reg, reg[*x]),
                }
                Solve::Explicit
            }
            _ => {
                // Linear in every unknown (then one Newton step solves it,
                // torn or not).
                let column: HashMap<VarId, usize> = unknowns.iter().enumerate().map(|(j, &x)| (x, j)).collect();
                // The unknowns each residual mentions, and its derivatives by them.
                let mut linear = true;
                let mut partials: Vec<Vec<(VarId, S)>> = Vec::with_capacity(residuals.len());
                for r in &residuals {
                    let mut own = Vec::new();
                    r.each_var(&mut |&v| {
                        if column.contains_key(&v) && !own.contains(&v) {
                            own.push(v);
                        }
                    });
                    let mut row = Vec::with_capacity(own.len());
                    for x in own {
                        let d = sym::derivative(r, &x);
                        let mut on_unknowns = false;
                        d.each_var(&mut |&y| on_unknowns |= column.contains_key(&y));
                        linear &= !on_unknowns && sym::affine_in(r, &x).is_some();
                        row.push((x, d));
                    }
                    partials.push(row);
                }
                let residual_start = em.w.ops.len();
                // A linear block is solved in one step of its sparse, pivoted
                // factorization; torn, its chains of closed forms could
                // amplify rounding (a 40-step doubling chain loses 5e-5).
                let torn = if linear { None } else { tearing::tear(&residuals, unknowns) };
                let (newton_unknowns, newton_rows, entries, torn) = match torn {
                    Some(t) => {
                        for (_, x, value) in &t.assigned {
                            em.emit_into(value, &reg, reg[*x]);
                        }
                        let torn = em.w.ops.len() - residual_start;
                        let entries = t.jacobian(&residuals);
                        (t.tears, t.residuals, entries, torn)
                    }
                    None => {
                        // Only the unknowns a residual mentions have a derivative
                        // other than zero: a long loop (a `for` over an array) has
                        // a few per row, and compiles in about its size, not k^3.
                        let mut entries: Vec<(usize, usize, S)> = Vec::new();
                        for (i, row) in partials.into_iter().enumerate() {
                            for (x, d) in row {
                                if d.as_const() != Some(0.0) {
                                    entries.push((i, column[&x], d));
                                }
                            }
                        }
                        (unknowns.clone(), (0..residuals.len()).collect(), entries, 0)
                    }
                };
                let k = newton_unknowns.len();
                largest_block = largest_block.max(k);
                let residual_regs: Vec<Reg> = newton_rows.iter().map(|&i| em.emit(residuals[i], &reg)).collect();
                let residual_ops = residual_start..em.w.ops.len();
                let layout = JacobianLayout::of(k, &entries);
                let block_rows: Vec<usize> = newton_rows.iter().map(|&i| rows[i]).collect();
                refuse_constant_singular(&layout, &entries, &block_rows, &newton_unknowns, pending, sorted)?;
                let jacobian_start = em.w.ops.len();
                let jacobian = match layout {
                    JacobianLayout::Dense => {
                        let mut dense = vec![sym::constant(0.0); k * k];
                        for (i, j, d) in entries {
                            dense[i * k + j] = d;
                        }
                        largest_factors = largest_factors.max(k * k);
                        match constant_inverse(&dense, k, linear) {
                            Some(inverse) => Jacobian::Constant { inverse },
                            None => Jacobian::Dense(dense.iter().map(|d| em.emit(d, &reg)).collect()),
                        }
                    }
                    JacobianLayout::Sparse(lu) => {
                        largest_factors = largest_factors.max(lu.stored());
                        Jacobian::Sparse { entries: entries.iter().map(|(_, _, d)| em.emit(d, &reg)).collect(), lu }
                    }
                };
                Solve::Newton {
                    unknowns: newton_unknowns.iter().map(|&x| reg[x]).collect(),
                    residuals: residual_regs,
                    jacobian,
                    residual_ops,
                    jacobian_ops: jacobian_start..em.w.ops.len(),
                    linear,
                    torn,
                }
            }
        };
        let before = match solve {
            Solve::Explicit => before..em.w.ops.len(),
            Solve::Newton { ref residual_ops, .. } => before..residual_ops.start,
        };
        let after = em.w.ops.len();
        let mut writes = Vec::new();
        for &u in unknowns {
            for &v in &members[u] {
                if let Some(&(_, of)) = negated.iter().find(|(w, _)| *w == v) {
                    em.w.ops.push(Op::Neg(reg[v], reg[of]));
                }
                for &slot in &stores_of[v] {
                    em.w.ops.push(Op::Store(slot, reg[v]));
                    writes.push(slot);
                }
            }
        }
        let reduced = unknowns.iter().filter(|&&u| pending.dummy[u]).map(|&u| pending.vars[u].name.clone()).collect();
        blocks.push(EquationBlock { before, solve, after: after..em.w.ops.len(), label, reduced });
        block_reads.push(loads);
        block_writes.push(writes);
        block_deps.push(deps);
    }

    let fed = |slot: usize| owner_of_slot(ctx, signals, slot);
    let after_dynamics = after_the_accelerations(&reads_reaction, &block_deps, &block_writes, pending, sorted, fed)?;
    let post_decided: Vec<bool> = VarId::all(n)
        .map(|v| {
            let rep = sorted.alias[v].map_or(v, |(of, _)| of);
            block_of_unknown[rep] != usize::MAX && after_dynamics[block_of_unknown[rep]]
        })
        .collect();
    refuse_events_on_reactions(pending, &post_decided)?;
    let positions =
        place(&mut blocks, &block_reads, &block_writes, &block_deps, &after_dynamics, signals, ctx, pending, sorted)?;
    let (blocks, positions) = fuse_explicit(&mut em.w.ops, blocks, positions);
    let first_post = positions.iter().position(|&p| p == AFTER_DYNAMICS).unwrap_or(positions.len());
    let (when_conditions, when_actions, reinits) = when_clauses(&mut em, pending, reads, sorted, &reg, states)?;

    // The states of the equations join the state vector.
    for &s in &sorted.states {
        states.names.push(pending.vars[s].name.clone());
        match pending.vars[s].role {
            Role::Declared(d) => {
                let v = &pending.declared[d];
                states.start.push(v.start.unwrap_or(0.0));
                states.fixed.push(v.start.is_some() && v.fixed);
            }
            // A derivative integrated (`der(der(x))` written): free at the
            // start, from 0, unless initial equations fix it.
            _ => {
                states.start.push(0.0);
                states.fixed.push(false);
            }
        }
    }
    states.nx = sorted.states.len();

    let outputs = pending
        .vars
        .iter()
        .enumerate()
        .filter(|(_, v)| matches!(v.role, Role::Declared(_)))
        .map(|(i, v)| (v.name.clone(), reg[i]))
        .collect();
    let mut program = EquationProgram {
        registers: em.w.registers,
        constants: em.w.preset,
        gathers,
        first_state,
        rates: sorted.rates.iter().map(|&d| reg[d]).collect(),
        ops: em.w.ops,
        blocks,
        positions,
        largest_block,
        largest_factors,
        outputs,
        notes: Vec::new(),
        reads_frames,
        reactions,
        first_post,
        when_conditions,
        when_actions,
        reinits,
        samples: em.events.samples,
        output_ops: Vec::new(),
    };
    super::fold::fold(&mut program, &mut reg);
    super::liveness::split_output_code(&mut program, &reg);
    events.indicators.append(&mut em.events.indicators);
    events.discrete_start.append(&mut em.events.discrete);
    Ok((program, reg))
}

/// The code of the `when` clauses: their conditions (ops run on every
/// evaluation, whose relations make events), then at events which branch
/// fires and what it does. Returns the two ranges of ops and the number
/// of `reinit`s.
fn when_clauses(
    em: &mut Emitter,
    pending: &Pending,
    reads: &[Option<Source>],
    sorted: &Sorted,
    reg: &[Reg],
    states: &StateLayout,
) -> Result<(Range<usize>, Range<usize>, usize), Error> {
    em.new_block();
    let start = em.w.ops.len();
    let mut conditions = Vec::with_capacity(pending.whens.len());
    for w in &pending.whens {
        em.events.label.clone_from(&w.origin);
        conditions.push(w.branches.iter().map(|(c, _)| em.emit(c, reg)).collect::<Vec<Reg>>());
    }
    let conditions_end = em.w.ops.len();
    let mut reinits = 0;
    em.events.live = true;
    for (w, regs) in pending.whens.iter().zip(&conditions) {
        // The first branch whose condition became true, only.
        let mut taken: Option<Reg> = None;
        for ((condition, actions), &cond) in w.branches.iter().zip(regs) {
            let fired = em.register();
            let impulse = mentions_sample(condition);
            let slot = em.events.discrete_slot(if impulse { f64::NEG_INFINITY } else { 0.0 });
            em.w.ops.push(Op::Fire { dst: fired, cond, slot, at_start: mentions_initial(condition), impulse });
            let fire = match taken {
                None => {
                    taken = Some(fired);
                    fired
                }
                Some(before) => {
                    let (not_before, fire, now_taken) = (em.register(), em.register(), em.register());
                    em.w.ops.push(Op::Not(not_before, before));
                    em.w.ops.push(Op::And(fire, fired, not_before));
                    em.w.ops.push(Op::Or(now_taken, before, fired));
                    taken = Some(now_taken);
                    fire
                }
            };
            for action in actions {
                match action {
                    PendingAction::Assign { slot, value } => {
                        let src = em.emit(value, reg);
                        em.w.ops.push(Op::Assign { slot: (em.events.first_discrete + slot) as u32, src, fire });
                    }
                    PendingAction::Reinit { variable, value, origin } => {
                        let state = reinit_target(pending, reads, sorted, states, *variable, origin)?;
                        let src = em.emit(value, reg);
                        em.w.ops.push(Op::Reinit { state: state as u32, src, fire });
                        reinits += 1;
                    }
                }
            }
        }
    }
    em.events.live = false;
    Ok((start..conditions_end, conditions_end..em.w.ops.len(), reinits))
}

/// Whether `e` holds `sample`, true only at its own events.
fn mentions_sample(e: &S) -> bool {
    e.find(&mut |node| matches!(node, Sym::Sample { .. }).then_some(())).is_some()
}

fn mentions_initial(e: &S) -> bool {
    match &**e {
        Sym::Initial => true,
        Sym::Not(a) | Sym::NoEvent(a) => mentions_initial(a),
        Sym::And(a, b) | Sym::Or(a, b) => mentions_initial(a) || mentions_initial(b),
        _ => false,
    }
}

/// The index in the state of what `reinit` sets: a state of the equations
/// or of the mechanics.
fn reinit_target(
    pending: &Pending,
    reads: &[Option<Source>],
    sorted: &Sorted,
    states: &StateLayout,
    v: VarId,
    origin: &str,
) -> Result<usize, Error> {
    if let Some(k) = sorted.states.iter().position(|&s| s == v) {
        return Ok(states.nq + states.nv + k);
    }
    if let (Some(Source::State(index)), Role::Read(Read::State { rate: false, .. })) =
        (&reads[v], &pending.vars[v].role)
    {
        return Ok(*index);
    }
    let name = &pending.vars[v].name;
    let what = match &pending.vars[v].role {
        Role::Declared(_) if pending.discrete_slot(v).is_some() => "a variable that a `when` assigns",
        Role::Declared(_) => "a variable the equations solve for, not a state (its `der` appears nowhere)",
        Role::Derivative { .. } | Role::Read(Read::State { rate: true, .. }) => "a derivative",
        Role::Read(Read::Signal { .. }) | Role::Written { .. } => "a signal",
        Role::Read(
            Read::Frame { .. }
            | Read::Axis { .. }
            | Read::AxisAcceleration { .. }
            | Read::Reaction { .. }
            | Read::Effort { .. },
        ) => "a quantity of a connector that the mechanics decides",
        Role::Read(Read::State { .. }) => "not a state",
    };
    let mut names: Vec<&str> = sorted.states.iter().map(|&s| pending.vars[s].name.as_str()).collect();
    names.extend(states.names[..states.nq + states.nv].iter().map(String::as_str));
    Err(problem(
        format!("`reinit` of `{name}`, which is {what}: only states jump"),
        vec![origin.to_string()],
        vec![name.clone()],
        format!(
            "reinit a state: a variable whose `der` appears in the equations, or a state of the mechanics{}",
            if names.is_empty() { String::new() } else { format!(" ({})", names.join(", ")) }
        ),
    ))
}

/// The inverse of a linear block's Jacobian whose entries are all
/// numbers, or `None` (entries that vary, a nonlinear block, or singular:
/// left to the evaluation, which reports it where it happens).
fn constant_inverse(dense: &[S], k: usize, linear: bool) -> Option<Vec<f64>> {
    if !linear {
        return None;
    }
    let mut factors = dense.iter().map(|d| d.as_const()).collect::<Option<Vec<f64>>>()?;
    let mut pivots = vec![0; k];
    if !crate::math::dense::lu(&mut factors, k, &mut pivots) {
        return None;
    }
    // Column by column from the factors; stored row-major.
    let (mut inverse, mut column, mut work) = (vec![0.0; k * k], vec![0.0; k], vec![0.0; k]);
    for j in 0..k {
        column.fill(0.0);
        column[j] = 1.0;
        crate::math::dense::lu_solve(&factors, k, &pivots, &mut column, &mut work);
        for (i, x) in column.iter().enumerate() {
            inverse[i * k + j] = *x;
        }
    }
    Some(inverse)
}

/// The closed form of unknown `x` from residual `r = 0`, if `r` is
/// linear in it with a slope that cannot vanish structurally.
fn explicit(r: &S, x: VarId) -> Option<S> {
    let (slope, rest) = sym::affine_in(r, &x)?;
    match slope.as_const() {
        Some(0.0) => None,
        Some(1.0) => Some(sym::neg(rest)),
        Some(-1.0) => Some(rest),
        _ => Some(sym::div(sym::neg(rest), slope)),
    }
}

/// Puts the equation blocks among the signal blocks so that each runs
/// after what it reads; drops the placeholders of written signals;
/// returns each block's place (blocks are renumbered in that order).
#[allow(clippy::too_many_arguments)]
fn place(
    blocks: &mut Vec<EquationBlock>,
    reads: &[Vec<usize>],
    writes: &[Vec<usize>],
    deps: &[Vec<usize>],
    after_dynamics: &[bool],
    signals: &mut Signals,
    ctx: &Context,
    pending: &Pending,
    sorted: &Sorted,
) -> Result<Vec<usize>, Error> {
    let library: Vec<_> =
        std::mem::take(&mut signals.blocks).into_iter().filter(|b| b.law != SignalLaw::Written).collect();
    let nl = library.len();
    let total = nl + blocks.len();
    // Who writes each slot: a library block or an equation block.
    let mut writer: HashMap<usize, usize> = HashMap::new();
    for (i, b) in library.iter().enumerate() {
        writer.insert(b.output, i);
    }
    for (k, slots) in writes.iter().enumerate() {
        for &s in slots {
            writer.insert(s, nl + k);
        }
    }
    let mut needs: Vec<Vec<usize>> = vec![Vec::new(); total];
    for (i, b) in library.iter().enumerate() {
        needs[i] = b.inputs.iter().filter_map(|s| writer.get(s).copied()).filter(|&w| w != i).collect();
    }
    debug_assert!(
        (0..nl).all(|i| needs[i].iter().all(|&w| w < nl || !after_dynamics[w - nl])),
        "blocks after the accelerations write no slot"
    );
    for k in 0..blocks.len() {
        let mut list: Vec<usize> = reads[k].iter().filter_map(|s| writer.get(s).copied()).collect();
        list.extend(deps[k].iter().map(|&d| nl + d));
        needs[nl + k] = list;
    }
    // Kahn's algorithm, taking the lowest ready node first: library blocks
    // of time alone stay first, everything else keeps its order where it can.
    let mut waiting: Vec<usize> = needs.iter().map(Vec::len).collect();
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); total];
    for (node, list) in needs.iter().enumerate() {
        for &w in list {
            users[w].push(node);
        }
    }
    let mut ready: BinaryHeap<std::cmp::Reverse<usize>> =
        (0..total).filter(|&i| waiting[i] == 0).map(std::cmp::Reverse).collect();
    let mut order = Vec::with_capacity(total);
    while let Some(std::cmp::Reverse(node)) = ready.pop() {
        order.push(node);
        for &u in &users[node] {
            waiting[u] -= 1;
            if waiting[u] == 0 {
                ready.push(std::cmp::Reverse(u));
            }
        }
    }
    if order.len() < total {
        let stuck: Vec<usize> = (0..total).filter(|&i| waiting[i] > 0).collect();
        let mut names: Vec<String> = Vec::new();
        for &i in &stuck {
            if i < nl {
                let owner = owner_of_slot(ctx, signals, library[i].output);
                if !names.contains(&owner) {
                    names.push(owner);
                }
            }
        }
        let equations: Vec<String> = stuck
            .iter()
            .filter(|&&i| i >= nl)
            .flat_map(|&i| sorted.blocks[i - nl].0.iter().map(|&r| pending.origins[sorted.source[r]].clone()))
            .collect();
        return Err(problem(
            format!(
                "these equations and the block{} `{}` depend on each other at the same instant (an algebraic loop \
                 through library blocks)",
                if names.len() == 1 { "" } else { "s" },
                names.join("`, `")
            ),
            equations,
            vec![],
            "write the loop in equations alone, or break it with a block that has a state",
        ));
    }
    let mut old: Vec<Option<EquationBlock>> = std::mem::take(blocks).into_iter().map(Some).collect();
    let mut positions = Vec::new();
    let mut kept = Vec::with_capacity(nl);
    let mut library: Vec<Option<_>> = library.into_iter().map(Some).collect();
    // The blocks that read reactions run last, after the accelerations.
    let (before, after): (Vec<usize>, Vec<usize>) = order.into_iter().partition(|&i| i < nl || !after_dynamics[i - nl]);
    for node in before {
        if node < nl {
            kept.push(library[node].take().expect("each node once"));
        } else {
            positions.push(kept.len());
            blocks.push(old[node - nl].take().expect("each node once"));
        }
    }
    for node in after {
        positions.push(AFTER_DYNAMICS);
        blocks.push(old[node - nl].take().expect("each node once"));
    }
    signals.blocks = kept;
    Ok(positions)
}

/// How a Newton block's Jacobian is stored and factored.
enum JacobianLayout {
    Dense,
    Sparse(Box<SparseLu>),
}

/// Blocks above this size with few entries a row are factored sparse.
const DENSE_UP_TO: usize = 16;

impl JacobianLayout {
    /// Dense for a small block or one with many entries a row; otherwise
    /// sparse, with its pivots and fill chosen now: from the values when
    /// they are constants, else from the pattern (and again at run time
    /// if the values then make a pivot too small).
    fn of(k: usize, entries: &[(usize, usize, S)]) -> JacobianLayout {
        if k <= DENSE_UP_TO || entries.len() * 4 > k * k {
            return JacobianLayout::Dense;
        }
        let pattern: Vec<(usize, usize)> = entries.iter().map(|&(i, j, _)| (i, j)).collect();
        let constants: Option<Vec<f64>> = entries.iter().map(|(_, _, d)| d.as_const()).collect();
        SparseLu::analyse(k, &pattern, constants.as_deref())
            .or_else(|| SparseLu::analyse(k, &pattern, None))
            .map_or(JacobianLayout::Dense, |lu| JacobianLayout::Sparse(Box::new(lu)))
    }
}

/// A block whose Jacobian is constant and singular never determines its
/// unknowns: its equations repeat or contradict each other (`x + y = 1`,
/// `x + y = 2`; `x = x + 1`). Refused here, with the equations, rather than
/// when the run starts.
fn refuse_constant_singular(
    layout: &JacobianLayout,
    entries: &[(usize, usize, S)],
    rows: &[usize],
    unknowns: &[VarId],
    pending: &Pending,
    sorted: &Sorted,
) -> Result<(), Error> {
    let Some(values) = entries.iter().map(|(_, _, d)| d.as_const()).collect::<Option<Vec<f64>>>() else {
        return Ok(());
    };
    let n = unknowns.len();
    if let JacobianLayout::Sparse(lu) = layout {
        let mut factors = vec![0.0; lu.stored()];
        lu.load(values.iter().copied(), &mut factors);
        // A failed static pivot proves nothing; partial pivoting decides,
        // where n^2 memory is affordable.
        if lu.factor(&mut factors) || n > DENSE_CHECK_UP_TO {
            return Ok(());
        }
    }
    let mut matrix = vec![0.0; n * n];
    for ((i, j, _), x) in entries.iter().zip(&values) {
        matrix[i * n + j] = *x;
    }
    if crate::math::dense::lu(&mut matrix, n, &mut vec![0; n]) {
        return Ok(());
    }
    let names: Vec<String> = unknowns.iter().map(|&v| pending.vars[v].name.clone()).collect();
    Err(problem(
        format!(
            "these equations do not determine {}: they repeat or contradict each other (with the others fixed, \
             no unique value satisfies them)",
            crate::error::list(&names)
        ),
        rows.iter().map(|&r| pending.origins[sorted.source[r]].clone()).collect(),
        names,
        "remove the equation that repeats another, or give one of these variables another equation",
    ))
}

/// The largest constant block checked for singularity with a dense LU.
const DENSE_CHECK_UP_TO: usize = 2000;

/// The place of the blocks that run after the accelerations.
const AFTER_DYNAMICS: usize = usize::MAX;

/// Which blocks run after the accelerations: those that read a measured
/// coupling's multiplier, and what depends on them. They may decide
/// variables and states' rates, but give the mechanics nothing (no flow,
/// no input of a library component), since it moved before them.
fn after_the_accelerations(
    reads_reaction: &[bool],
    deps: &[Vec<usize>],
    writes: &[Vec<usize>],
    pending: &Pending,
    sorted: &Sorted,
    fed: impl Fn(usize) -> String,
) -> Result<Vec<bool>, Error> {
    // Blocks come in dependency order.
    let mut after = reads_reaction.to_vec();
    for b in 0..after.len() {
        after[b] = after[b] || deps[b].iter().any(|&d| after[d]);
        if after[b] && !writes[b].is_empty() {
            let origins = sorted.blocks[b].0.iter().map(|&r| pending.origins[sorted.source[r]].clone()).collect();
            let names = sorted.blocks[b].1.iter().map(|&v| pending.vars[v].name.clone()).collect();
            let mut fed: Vec<String> = writes[b].iter().map(|&slot| fed(slot)).collect();
            fed.dedup();
            return Err(problem(
                format!(
                    "this equation gives `{}` a value from a flow measured through a rigid part, which is known only \
                     once the accelerations are: it cannot act on the motion",
                    fed.join("`, `")
                ),
                origins,
                names,
                "record the measured flow, or use it in equations of your own (a filter with a state works); to \
                 feed it back, measure the force of a compliant element (a spring's or damper's `tau` or `f`)",
            ));
        }
    }
    Ok(after)
}

/// A `when` clause watches its conditions before the accelerations, so it
/// cannot read what is decided after them.
fn refuse_events_on_reactions(pending: &Pending, post_decided: &[bool]) -> Result<(), Error> {
    for w in &pending.whens {
        let mut names = Vec::new();
        let mut note = |&v: &VarId| {
            if post_decided[v] && !names.contains(&pending.vars[v].name) {
                names.push(pending.vars[v].name.clone());
            }
        };
        for (condition, actions) in &w.branches {
            condition.each_var(&mut note);
            for action in actions {
                match action {
                    PendingAction::Assign { value, .. } | PendingAction::Reinit { value, .. } => {
                        value.each_var(&mut note)
                    }
                }
            }
        }
        if !names.is_empty() {
            return Err(problem(
                format!(
                    "this `when` reads `{}`, which depends on a flow measured through a rigid part: events cannot \
                     watch it yet",
                    names.join("`, `")
                ),
                vec![w.origin.clone()],
                names,
                "watch a quantity of the motion, or the force of a compliant element",
            ));
        }
    }
    Ok(())
}

/// Lays the ops out in evaluation order and fuses each run of blocks in
/// closed form that sit at one place among the signal blocks into one
/// block: one call per run instead of one per equation.
fn fuse_explicit(
    ops: &mut Vec<Op>,
    blocks: Vec<EquationBlock>,
    positions: Vec<usize>,
) -> (Vec<EquationBlock>, Vec<usize>) {
    let old = std::mem::take(ops);
    let copy = |range: &std::ops::Range<usize>, ops: &mut Vec<Op>| {
        let start = ops.len();
        ops.extend_from_slice(&old[range.clone()]);
        start..ops.len()
    };
    let mut fused: Vec<EquationBlock> = Vec::with_capacity(blocks.len());
    let mut fused_positions: Vec<usize> = Vec::with_capacity(blocks.len());
    for (block, position) in blocks.into_iter().zip(positions) {
        let before = copy(&block.before, ops);
        let solve = match block.solve {
            Solve::Explicit => Solve::Explicit,
            Solve::Newton { unknowns, residuals, jacobian, residual_ops, jacobian_ops, linear, torn } => {
                Solve::Newton {
                    unknowns,
                    residuals,
                    jacobian,
                    residual_ops: copy(&residual_ops, ops),
                    jacobian_ops: copy(&jacobian_ops, ops),
                    linear,
                    torn,
                }
            }
        };
        let after = copy(&block.after, ops);
        let explicit = matches!(solve, Solve::Explicit);
        if let (true, Some(last)) = (explicit, fused.last_mut()) {
            if matches!(last.solve, Solve::Explicit) && fused_positions.last() == Some(&position) {
                // Both run straight through: one range covers them.
                last.before = last.before.start..after.end;
                last.after = after.end..after.end;
                continue;
            }
        }
        fused.push(EquationBlock { before, solve, after, label: block.label, reduced: block.reduced });
        fused_positions.push(position);
    }
    (fused, fused_positions)
}

/// The component that owns a signal slot, for messages.
fn owner_of_slot(ctx: &Context, signals: &Signals, slot: usize) -> String {
    signals
        .of_connector
        .iter()
        .position(|&s| s == slot)
        .map(|id| ctx.components[ctx.conn.infos[id].component].name.clone())
        .unwrap_or_default()
}
