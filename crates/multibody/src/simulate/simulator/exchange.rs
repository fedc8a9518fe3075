//! The simulator driven by a host that integrates itself (FMI's model
//! exchange) or only asks for steps (co-simulation), so records nothing.
//!
//! Model exchange: the host sets the time and the state, reads the
//! derivatives and the event indicators, and integrates; where an
//! indicator changes sign, or at a time event, it calls
//! [`Simulator::update_at_event`], which runs the simulator's own event
//! handling at the time and state the host set. Between events the sources
//! show their values before the next time event up to it, as in a run.

use super::{Shared, Simulator};
use crate::simulate::{SampleSink, SimulationOptions, Stopped};

/// What an event changed, for the host.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventUpdate {
    /// Whether the state moved (a `reinit`, the state put back onto the
    /// constraints, or an Euler-angle joint moved to a chart): the host
    /// reads it again.
    pub state_changed: bool,
    /// The next time a source switches, if one does.
    pub next_time_event: Option<f64>,
}

/// A sink that keeps nothing (the recorder is off for hosts).
struct Nothing;

impl SampleSink for Nothing {
    fn sample(&mut self, _: f64, _: &[f64]) -> Result<(), String> {
        Ok(())
    }
    fn columns(&self) -> Option<&[usize]> {
        Some(&[])
    }
}

impl<'m> Simulator<'m> {
    /// A simulator that records nothing: the host reads the values it
    /// wants with [`Simulator::values`] (an FMU, a controller).
    pub fn for_host(mechanism: impl Into<Shared<'m>>, options: &SimulationOptions) -> Result<Self, Stopped> {
        let mechanism = mechanism.into();
        let y0 = mechanism.system.states.start.clone();
        let mut sim = Self::from_state(mechanism, &y0, options, Some(&[]))?;
        sim.recorder.off = true;
        Ok(sim)
    }

    /// Integrates to exactly `t`, handling the events on the way, as
    /// [`Simulator::step_until`] does but recording nothing.
    pub fn advance_to(&mut self, t: f64) -> Result<(), Stopped> {
        self.run_to(t, &mut Nothing, None, true)
    }

    /// How many event indicators a host watches: the model's (its
    /// relations, friction and stops) and one per Euler-angle joint (its
    /// distance from the singular configuration).
    pub fn indicator_count(&self) -> usize {
        self.mechanism.system.events.indicators.len() + self.charts.len()
    }

    /// The indicators' names, in the order of [`Simulator::indicators`].
    pub fn indicator_names(&self) -> Vec<String> {
        (0..self.indicator_count()).map(|k| self.indicator_name(k)).collect()
    }

    /// Sets the time (model exchange: the host integrates).
    pub fn set_time(&mut self, t: f64) {
        if t != self.t {
            self.t = t;
            self.started = false;
            self.ahead = false;
        }
    }

    /// Sets the state as the host integrates it: no event, no chart
    /// change (the host finds those with the indicators).
    pub fn set_continuous_state(&mut self, y: &[f64]) -> Result<(), String> {
        if y.len() != self.y.len() {
            return Err(format!("the state has {} values, not {}", self.y.len(), y.len()));
        }
        self.y.copy_from_slice(y);
        self.started = false;
        self.ahead = false;
        Ok(())
    }

    /// The state's derivative at the time and state set.
    pub fn derivatives(&mut self, dy: &mut [f64]) -> Result<(), String> {
        if dy.len() != self.y.len() {
            return Err(format!("the state has {} values, not {}", self.y.len(), dy.len()));
        }
        self.mechanism.rhs(&mut self.ws, self.t, &self.y, dy).map_err(|e| self.mechanism.describe(&e))
    }

    /// The event indicators at the time and state set: an event is where
    /// one changes sign (see [`Simulator::indicator_count`]).
    pub fn indicators(&mut self, g: &mut [f64]) -> Result<(), String> {
        let model = self.mechanism.system.events.indicators.len();
        if g.len() != model + self.charts.len() {
            return Err(format!("the model has {} event indicators, not {}", self.indicator_count(), g.len()));
        }
        if model > 0 {
            let mut dy = std::mem::take(&mut self.indicators.dy);
            dy.resize(self.y.len(), 0.0);
            let evaluated = self.mechanism.rhs(&mut self.ws, self.t, &self.y, &mut dy);
            self.indicators.dy = dy;
            evaluated.map_err(|e| self.mechanism.describe(&e))?;
            g[..model].copy_from_slice(&self.ws.indicators);
        }
        for (gk, c) in g[model..].iter_mut().zip(&self.charts) {
            *gk = c.indicator(&self.y);
        }
        Ok(())
    }

    /// Handles an event at the time and state set, as a run does: the
    /// modes settle, `reinit`s apply, the state goes back onto the
    /// constraints, and an Euler-angle joint near its singular
    /// configuration moves to a chart. Then the sources show their values
    /// before the next time event again.
    pub fn update_at_event(&mut self) -> Result<EventUpdate, String> {
        let before = self.y.clone();
        self.ws.left_limit_at = f64::NAN;
        self.last_event = Some((self.t, self.indicators.last.take()));
        self.event().map_err(|e| self.stopped(e, self.t).reason)?;
        let next = self.mechanism.next_time_event(self.t);
        self.ws.left_limit_at = next;
        Ok(EventUpdate { state_changed: before != self.y, next_time_event: next.is_finite().then_some(next) })
    }
}
