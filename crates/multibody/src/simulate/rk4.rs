//! The classical fixed-step Runge-Kutta method, with cubic Hermite dense
//! output between steps.

use super::integrator::{finish_step, DenseStep, Failure, OdeSystem, Stats, Stopped};

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
        }
    }

    pub fn integrate<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t0: f64,
        tf: f64,
        y0: &[f64],
        mut observe: impl FnMut(&Self) -> Result<(), S::Error>,
    ) -> Result<Stats, Stopped<S::Error>> {
        let n = y0.len();
        let mut stats = Stats::default();
        self.y.copy_from_slice(y0);
        let steps = ((tf - t0) / self.dt).round().max(1.0) as usize;
        let h = (tf - t0) / steps as f64;
        if let Err(e) = sys.rhs(t0, &self.y, &mut self.f_new) {
            return Err(Stopped { t: t0, failure: Failure::Rhs(e), stats });
        }
        for step in 0..steps {
            let t = t0 + step as f64 * h;
            std::mem::swap(&mut self.y_old, &mut self.y);
            std::mem::swap(&mut self.f_old, &mut self.f_new);
            if let Err(e) = self.step(sys, t, h, n) {
                return Err(Stopped { t, failure: Failure::Rhs(e), stats });
            }
            stats.evaluations += 4;
            stats.accepted += 1;
            self.t_old = t;
            self.h_old = h;
            finish_step(sys, self, t + h, |s| (&mut s.y, &mut s.f_new), &mut observe, &mut stats)?;
        }
        Ok(stats)
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
