//! Signal connections and the signal graph: each signal node carries the
//! value of its one source (a block's output), inputs with no source read
//! zero, and the blocks are put in the order the right-hand side evaluates
//! them (each after the blocks it reads). A cycle of blocks is an
//! algebraic loop.

use super::axis::{self, Places};
use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use crate::components::{ConnectorType, Part};
use crate::math::Transform;
use crate::system::{Attachment, FlangeRef, SignalBlock, SignalLaw};
use crate::Error;

pub struct Signals {
    /// The blocks in evaluation order, those of time only first.
    pub blocks: Vec<SignalBlock>,
    /// How many blocks depend on time only.
    pub time_signals: usize,
    /// Per slot (the zero slot included), whether its value depends on
    /// time only. Slots are numbered in the order of the parts, not in the
    /// evaluation order, so `time_signals` says nothing about a slot.
    pub of_time: Vec<bool>,
    /// For every connector, its signal slot (the last slot reads zero).
    pub of_connector: Vec<usize>,
    /// How many slots there are, the zero slot included.
    pub slots: usize,
    /// The model's inputs (components of kind `Input`), by their number.
    pub inputs: Vec<(String, f64)>,
    pub warnings: Vec<String>,
}

pub fn resolve(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
    places: &Places,
    plane: &Transform,
) -> Result<Signals, Error> {
    // Every block writes its own slot, in the order of the parts.
    let mut owners = Vec::new();
    let mut slot_of_output = vec![usize::MAX; conn.infos.len()];
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            if let Part::Signal { output, .. } = part {
                slot_of_output[Connectors::id(components, ci, *output)] = owners.len();
                owners.push(ci);
            }
        }
    }
    let zero = owners.len();
    let (of_connector, warnings) = connect(components, conn, &slot_of_output, zero)?;

    let mut blocks = Vec::with_capacity(owners.len());
    let mut model_inputs = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        let id = |local: usize| Connectors::id(components, ci, local);
        for part in &c.parts {
            let Part::Signal { output, law, inputs, frames, flanges } = part else { continue };
            let attach = |local: usize| {
                let node = &tree.nodes[conn.node(id(local))];
                Attachment { anchor: node.anchor, pose: node.pose }
            };
            let flange = |local: Option<usize>| -> Result<FlangeRef, Error> {
                local.map_or(Ok(FlangeRef::FIXED), |l| axis::flange(components, conn, places, id(l)))
            };
            let law = match *law {
                SignalLaw::Input { start, .. } => {
                    model_inputs.push((c.name.clone(), start));
                    SignalLaw::Input { index: model_inputs.len() - 1, start }
                }
                ref law => law.clone(),
            };
            blocks.push(SignalBlock {
                law,
                output: slot_of_output[id(*output)],
                inputs: inputs.map(|i| i.map_or(zero, |l| of_connector[id(l)])),
                frames: frames.map(|f| f.map(attach)),
                flanges: [flange(flanges[0])?, flange(flanges[1])?],
                in_plane: super::links::in_placed_plane(c, plane),
            });
        }
    }
    let order = evaluation_order(&blocks, zero).map_err(|cycle| Error::AlgebraicLoop {
        components: cycle.into_iter().map(|slot| components[owners[slot]].name.clone()).collect(),
    })?;
    let mut slots: Vec<Option<SignalBlock>> = blocks.into_iter().map(Some).collect();
    let blocks: Vec<SignalBlock> = order.into_iter().filter_map(|slot| slots[slot].take()).collect();
    // Blocks of time only read only blocks of time only: putting them
    // first keeps every block after those it reads.
    let mut of_time = vec![false; zero + 1];
    of_time[zero] = true;
    for b in &blocks {
        of_time[b.output] = match b.law {
            SignalLaw::Source(_) => true,
            SignalLaw::Affine { .. } | SignalLaw::Product | SignalLaw::Division => b.inputs.iter().all(|&i| of_time[i]),
            _ => false,
        };
    }
    let (mut blocks, rest): (Vec<_>, Vec<_>) = blocks.into_iter().partition(|b| of_time[b.output]);
    let time_signals = blocks.len();
    blocks.extend(rest);
    Ok(Signals { blocks, time_signals, of_time, of_connector, slots: zero + 1, inputs: model_inputs, warnings })
}

/// The slot of every connector: each signal node reads its one output.
fn connect(
    components: &[CompiledComponent],
    conn: &Connectors,
    slot_of_output: &[usize],
    zero: usize,
) -> Result<(Vec<usize>, Vec<String>), Error> {
    let mut of_connector = vec![zero; conn.infos.len()];
    let mut warnings = Vec::new();
    for members in &conn.flange_nodes {
        if !conn.types[members[0]].is_signal() {
            continue;
        }
        let outputs: Vec<usize> =
            members.iter().copied().filter(|&c| conn.types[c] == ConnectorType::RealOutput).collect();
        let slot = match outputs.as_slice() {
            [] => {
                for &c in members {
                    warnings.push(format!(
                        "the input `{}` is not connected to a source; it reads 0",
                        conn.name(components, c)
                    ));
                }
                zero
            }
            [one] => {
                refuse_unavailable(components, conn, *one, members)?;
                slot_of_output[*one]
            }
            [first, second, ..] => {
                return Err(Error::Unsupported {
                    component: components[conn.infos[*second].component].name.clone(),
                    what: format!(
                        "two outputs (`{}` and `{}`) driving one signal",
                        conn.name(components, *first),
                        conn.name(components, *second)
                    ),
                    fix: "connect each input to one output".into(),
                })
            }
        };
        for &c in members {
            of_connector[c] = slot;
        }
    }
    Ok((of_connector, warnings))
}

/// An error when a signal node whose source is an output the signal graph
/// cannot compute (`SignalLaw::Unavailable`: cut forces, accelerations, or
/// an output switched off) has a reader.
fn refuse_unavailable(
    components: &[CompiledComponent],
    conn: &Connectors,
    output: usize,
    members: &[usize],
) -> Result<(), Error> {
    let Some(&reader) = members.iter().find(|&&c| conn.types[c] == ConnectorType::RealInput) else { return Ok(()) };
    let ci = conn.infos[output].component;
    let local = output - components[ci].first_connector;
    let reason = components[ci].parts.iter().find_map(|p| match p {
        Part::Signal { output, law: SignalLaw::Unavailable { reason }, .. } if *output == local => Some(*reason),
        _ => None,
    });
    match reason {
        None => Ok(()),
        Some(reason) => Err(Error::Unsupported {
            component: components[ci].name.clone(),
            what: format!(
                "reading the output `{}` in the model (by `{}`): it {reason}",
                conn.name(components, output),
                conn.name(components, reader)
            ),
            fix: "leave it unconnected and read it from the results, or measure a position or velocity instead".into(),
        }),
    }
}

/// The blocks' slots in an order where each block comes after the blocks
/// whose outputs it reads (blocks are indexed by the slot they write), or
/// the slots of a cycle.
fn evaluation_order(blocks: &[SignalBlock], zero: usize) -> Result<Vec<usize>, Vec<usize>> {
    let n = blocks.len();
    let mut by_slot = vec![0; n];
    for (i, b) in blocks.iter().enumerate() {
        by_slot[b.output] = i;
    }
    // 0: not visited, 1: on the current path, 2: done.
    let mut mark = vec![0u8; n];
    let mut order = Vec::with_capacity(n);
    let mut path = Vec::new();
    for start in 0..n {
        if mark[start] != 0 {
            continue;
        }
        // Depth first over the inputs, with an explicit stack of (slot, next input).
        let mut stack = vec![(start, 0usize)];
        mark[start] = 1;
        path.push(start);
        while let Some(&mut (slot, ref mut next)) = stack.last_mut() {
            let inputs = &blocks[by_slot[slot]].inputs;
            if *next < inputs.len() {
                let input = inputs[*next];
                *next += 1;
                if input == zero {
                    continue;
                }
                match mark[input] {
                    0 => {
                        mark[input] = 1;
                        path.push(input);
                        stack.push((input, 0));
                    }
                    1 => {
                        let from = path.iter().position(|&s| s == input).unwrap_or(0);
                        return Err(path[from..].to_vec());
                    }
                    _ => {}
                }
            } else {
                mark[slot] = 2;
                order.push(slot);
                path.pop();
                stack.pop();
            }
        }
    }
    Ok(order)
}
