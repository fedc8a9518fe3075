//! Friction elements with modes: their flanges placed, their normal-force
//! signal, a constraint row each (after the couplings'), and their slots
//! among the indicators and the discrete state.

use super::axis::{self, Places};
use super::connections::Connectors;
use super::mechanism::CompiledComponent;
use crate::components::Part;
use crate::system::friction::{Friction, FrictionFlags, FRICTION_DISCRETE, FRICTION_INDICATORS};
use crate::system::EventLayout;
use crate::Error;

/// The friction elements, their rows numbered from `first_row`, with what
/// they add to `events` (indicators and discrete state, after what it has).
pub fn elements(
    components: &mut [CompiledComponent],
    conn: &Connectors,
    places: &Places,
    signal_of_connector: &[usize],
    first_row: usize,
    events: &mut EventLayout,
) -> Result<Vec<Friction>, Error> {
    let mut frictions = Vec::new();
    for ci in 0..components.len() {
        let mut own = Vec::new();
        for part in &components[ci].parts {
            let Part::Friction { a, b, law, normal } = part else { continue };
            let id = |local: usize| Connectors::id(components, ci, local);
            // Without a flange a, against the fixed ground.
            let a = match a {
                Some(a) => axis::flange(components, conn, places, id(*a))?,
                None => crate::system::FlangeRef::FIXED,
            };
            let b = axis::flange(components, conn, places, id(*b))?;
            if a.on_line() || b.on_line() {
                return Err(axis::on_a_line(components, ci, "friction"));
            }
            let name = &components[ci].name;
            let indicator = events.indicators.len();
            events.indicators.extend([
                format!("{name}: relative speed, or holding force against its upper limit"),
                format!("{name}: holding force against its lower limit"),
                format!("{name}: normal force"),
            ]);
            debug_assert_eq!(events.indicators.len() - indicator, FRICTION_INDICATORS);
            let stop_indicator = law.stops.map(|_| {
                events.indicators.extend([format!("the upper stop of {name}"), format!("the lower stop of {name}")]);
                events.indicators.len() - 2
            });
            if law.stops.is_some() && b.coordinate().is_none() {
                return Err(crate::Error::Unsupported {
                    component: name.clone(),
                    what: "hard stops on a flange that no coordinate of its own moves".into(),
                    fix: "let the sliding mass move freely between its stops (no joint or gear drives it)".into(),
                });
            }
            let discrete = events.discrete_start.len();
            events.discrete_start.extend(FrictionFlags::START);
            debug_assert_eq!(events.discrete_start.len() - discrete, FRICTION_DISCRETE);
            own.push(frictions.len());
            frictions.push(Friction {
                a,
                b,
                law: law.clone(),
                normal: normal.map(|n| signal_of_connector[id(n)]),
                row: first_row + frictions.len(),
                discrete,
                indicator,
                stop_indicator,
            });
        }
        components[ci].frictions = own;
    }
    Ok(frictions)
}
