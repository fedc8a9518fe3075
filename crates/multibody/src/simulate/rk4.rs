//! The classical fixed-step Runge-Kutta method, with cubic Hermite dense
//! output between steps.

use super::integrator::{finish_step, DenseStep, Failure, Observer, OdeSystem, Reached, Stats, Stopped};

pub struct Rk4 {
    dt: f64,
    k: [Vec<f64>; 4],
    y: Vec<f64>,
    y_old: Vec<f64>,
    f_old: Vec<f64>,
    f_new: Vec<f64>,
    stage: Vec<f64>,
    t_old: f64,
    h_old: f64,
    /// Where the integration stands.
    t: f64,
    stats: Stats,
}

impl DenseStep for Rk4 {
    fn span(&self) -> (f64, f64) {
        (self.t_old, self.t_old + self.h_old)
    }
    fn y(&self) -> &[f64] {
        &self.y
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let h = self.h_old;
        let s = (t - self.t_old) / h;
        let (h00, h10, h01, h11) = (
            2.0 * s * s * s - 3.0 * s * s + 1.0,
            s * s * s - 2.0 * s * s + s,
            -2.0 * s * s * s + 3.0 * s * s,
            s * s * s - s * s,
        );
        // The step's end from its stages, not `self.y`: the system may be
        // moving that (onto constraints) while it reads this output.
        let [k1, k2, k3, k4] = &self.k;
        for (i, x) in out.iter_mut().enumerate() {
            let y_end = self.y_old[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            *x = h00 * self.y_old[i] + h10 * h * self.f_old[i] + h01 * y_end + h11 * h * self.f_new[i];
        }
    }
}

impl Rk4 {
    pub fn new(n: usize, dt: f64) -> Self {
        let v = || vec![0.0; n];
        Self {
            dt,
            k: [v(), v(), v(), v()],
            y: v(),
            y_old: v(),
            f_old: v(),
            f_new: v(),
            stage: v(),
            t_old: 0.0,
            h_old: 0.0,
            t: 0.0,
            stats: Stats::default(),
        }
    }

    /// Starts at `(t, y)`, or starts again there after an event.
    pub fn start<S: OdeSystem>(&mut self, sys: &mut S, t: f64, y: &[f64]) -> Result<(), Stopped<S::Error>> {
        self.y.copy_from_slice(y);
        self.t = t;
        if let Err(e) = sys.rhs(t, &self.y, &mut self.f_new) {
            return Err(Stopped { t, failure: Failure::Rhs(e), stats: self.stats });
        }
        Ok(())
    }

    /// Steps from the current time to exactly `tf` in equal steps of
    /// about `dt`, or to the first event inside a step.
    pub fn advance<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stopped<S::Error>> {
        let n = self.y.len();
        let t0 = self.t;
        if t0 >= tf {
            return Ok(Reached::End);
        }
        let steps = ((tf - t0) / self.dt).round().max(1.0) as usize;
        let h = (tf - t0) / steps as f64;
        for step in 0..steps {
            let t = t0 + step as f64 * h;
            std::mem::swap(&mut self.y_old, &mut self.y);
            std::mem::swap(&mut self.f_old, &mut self.f_new);
            if let Err(e) = self.step(sys, t, h, n) {
                return Err(Stopped { t, failure: Failure::Rhs(e), stats: self.stats });
            }
            self.stats.evaluations += 4;
            self.stats.accepted += 1;
            self.t_old = t;
            self.h_old = h;
            self.t = if step + 1 == steps { tf } else { t + h };
            let end = finish_step(sys, self, t + h, |s| (&mut s.y, &mut s.f_new, &mut s.stats), observe, true)?;
            if let Some(te) = end {
                self.t = te;
                return Ok(Reached::Event(te));
            }
        }
        Ok(Reached::End)
    }

    /// The counts of the work done so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    fn step<S: OdeSystem>(&mut self, sys: &mut S, t: f64, h: f64, n: usize) -> Result<(), S::Error> {
        let [k1, k2, k3, k4] = &mut self.k;
        let (y0, s) = (&self.y_old, &mut self.stage);
        k1.copy_from_slice(&self.f_old);
        for i in 0..n {
            s[i] = y0[i] + 0.5 * h * k1[i];
        }
        sys.rhs(t + 0.5 * h, s, k2)?;
        for i in 0..n {
            s[i] = y0[i] + 0.5 * h * k2[i];
        }
        sys.rhs(t + 0.5 * h, s, k3)?;
        for i in 0..n {
            s[i] = y0[i] + h * k3[i];
        }
        sys.rhs(t + h, s, k4)?;
        for i in 0..n {
            self.y[i] = y0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        // The derivative at the new point serves the next step and the dense output.
        sys.rhs(t + h, &self.y, &mut self.f_new)
    }
}
