//! The transmission line (TLM) that stands for the shaft between the journal and the disk in
//! coupling mode tlm: plain Rust, no FMI.
//!
//! The shaft of stiffness `k_s` and damping `c_s` becomes, per lateral axis `a ∈ {y, z}`, a
//! lossless line of delay `T` (the communication step) and characteristic impedance
//! `Z_c = k_s T`, plus the damper `c_s` acting on the velocities across it one delay apart.
//! With the wave variables `o_j` (sent by the journal end) and `o_d` (sent by the disk end):
//!
//! ```text
//!   force of the line on the journal:  g_j(t) − Z_c v_j(t) + c_s (v_d(t − T) − v_j(t))
//!   force of the line on the disk:     g_d(t) − Z_c v_d(t) + c_s (v_j(t − T) − v_d(t))
//!   g_j(t) = o_d(t − T),   g_d(t) = o_j(t − T)
//!   o_j = 2 Z_c v_j − g_j,  o_d = 2 Z_c v_d − g_d
//! ```
//!
//! At rest `g_j = −g_d` (equal and opposite); over `2T` the journal's force grows by
//! `2 Z_c v_d = k_s (2T v_d)`, `k_s` times the disk's displacement in that time: the line is
//! the shaft's spring, with a parasitic mass `Z_c T = k_s T²` along it (its error, second order
//! in `T`). The damper acts across the line one delay apart; its error, `c_s T` times the
//! acceleration, is first order in `T`, a mass-like `c_s T` next to the line's `k_s T²` (their
//! ratio `2ζ/(ωT)` for the damping ratio ζ at ω = sqrt(k_s/m_d)): without shaft damping the
//! coupling converges at second order, with it the first-order term takes over at fine delays.
//! The line is passive (the delayed damper dissipates too): stable at any delay.
//!
//! Sampled at the communication points `t_k` (step `k` runs from `t_k` to `t_{k+1} = t_k + T`),
//! given the journal velocity `v_j(t_k)` at the start of the step:
//!
//! ```text
//!   1. g_j(t_k) = o_d(t_{k−1});   o_j(t_k) = 2 Z_c v_j(t_k) − g_j(t_k)
//!   2. over [t_k, t_{k+1}]: g_d(t) = o_j(t − T) and v_j(t − T), each linear between their
//!      samples at t_{k−1} and t_k, drive the disk ([`LineStep::disk_force`])
//!   3. at t_{k+1}: g_d(t_{k+1}) = o_j(t_k);   o_d(t_{k+1}) = 2 Z_c v_d(t_{k+1}) − g_d(t_{k+1})
//!   4. for the journal's next step [t_{k+1}, t_{k+2}] the line's force on the journal is
//!      F(t) = c0 + (c1 − c0)(t − t_{k+1})/T − (Z_c + c_s) v_j(t)
//!      with c0 = w(t_k), c1 = w(t_{k+1}) and w = o_d + c_s v_d
//! ```
//!
//! `c0`, `c1` and `Z_c + c_s` depend only on the disk's state and the line's history, not on
//! the journal velocity just received: a Jacobi master reads the same values whatever order
//! it sets and reads in.
//!
//! Start (history for `t ≤ t_0`): the disk at rest in its static equilibrium, the line carrying
//! the static force `F_0` onto the disk (its weight `m_d g ẑ` under gravity):
//! `o_j(t ≤ t_0) = F_0`, `o_d(t ≤ t_0) = −F_0`, `v_j(t < t_0) = 0`, so `c0 = c1 = −F_0` (the
//! journal carries the disk's weight from the first step).

/// Lateral axes of the line: y and z of the bearing's frame, in that order.
pub const AXES: usize = 2;

/// The largest delay whose parasitic mass `k_s T²` stays within 1 % of the disk mass:
/// `T_acc = sqrt(0.01 m_d / k_s)` \[s\]. It bounds the accuracy, not the stability.
pub fn accurate_delay(shaft_k: f64, disk_mass: f64) -> f64 {
    (0.01 * disk_mass / shaft_k).sqrt()
}

/// The line's history at a communication point `t_k` (between two steps): everything the next
/// steps need. All values per axis (y, z).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LineHistory {
    /// `o_j(t_{k−1})`: the wave the journal end sent at the previous communication point \[N\].
    pub oj_prev: [f64; AXES],
    /// `v_j(t_{k−1})`: the journal velocity received then \[m/s\].
    pub vj_prev: [f64; AXES],
    /// `o_d(t_{k−1})`: the disk end's wave at the previous communication point \[N\].
    pub od_prev: [f64; AXES],
    /// `o_d(t_k)`: the disk end's wave now \[N\].
    pub od: [f64; AXES],
    /// `w(t_{k−1}) = o_d + c_s v_d` at the previous communication point (output `c0`) \[N\].
    pub w_prev: [f64; AXES],
    /// `w(t_k)` (output `c1`) \[N\].
    pub w: [f64; AXES],
}

/// A transmission line standing for the shaft: its constants and its sampled history.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TlmLine {
    zc: f64,
    cs: f64,
    delay: f64,
    h: LineHistory,
}

/// The line's part of one communication step `[t_k, t_k + T]`, fixed at its start by
/// [`TlmLine::begin_step`]: what drives the disk inside the step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LineStep {
    /// `g_d` at the step's start and end: `o_j(t_{k−1})`, `o_j(t_k)` \[N\].
    gd: [[f64; AXES]; 2],
    /// `v_j(t − T)` at the step's start and end: `v_j(t_{k−1})`, `v_j(t_k)` \[m/s\].
    vj: [[f64; AXES]; 2],
    /// `Z_c + c_s` \[N·s/m\].
    z: f64,
    /// `c_s` \[N·s/m\].
    cs: f64,
}

impl LineStep {
    /// Force of the line on the disk \[N\] (y, z) at the fraction `s ∈ [0, 1]` of the step, for
    /// the disk velocity `vd`: `g_d(t) − (Z_c + c_s) v_d + c_s v_j(t − T)`, with `g_d` and
    /// `v_j(t − T)` linear over the step. Does not allocate.
    pub fn disk_force(&self, s: f64, vd: [f64; AXES]) -> [f64; AXES] {
        let mut f = [0.0; AXES];
        for (a, fa) in f.iter_mut().enumerate() {
            let g = self.gd[0][a] + s * (self.gd[1][a] - self.gd[0][a]);
            let vj = self.vj[0][a] + s * (self.vj[1][a] - self.vj[0][a]);
            *fa = g - self.z * vd[a] + self.cs * vj;
        }
        f
    }
}

impl TlmLine {
    /// A line for the shaft `shaft_k` \[N/m\], `shaft_c` \[N·s/m\] with delay `delay` \[s\]
    /// (`Z_c = shaft_k · delay`), at rest carrying the static force `disk_force` \[N\] (y, z)
    /// onto the disk (see the module docs). The error names the offending argument.
    pub fn at_rest(
        shaft_k: f64,
        shaft_c: f64,
        delay: f64,
        disk_force: [f64; AXES],
    ) -> Result<Self, String> {
        if !(shaft_k.is_finite() && shaft_k > 0.0) {
            return Err(format!(
                "shaft.k = {shaft_k} N/m must be finite and > 0 for a TLM line"
            ));
        }
        if !(shaft_c.is_finite() && shaft_c >= 0.0) {
            return Err(format!(
                "shaft.c = {shaft_c} N.s/m must be finite and >= 0 for a TLM line"
            ));
        }
        if !(delay.is_finite() && delay > 0.0) {
            return Err(format!("tlm.delay = {delay} s must be finite and > 0"));
        }
        if let Some(f) = disk_force.iter().find(|f| !f.is_finite()) {
            return Err(format!("the line's static force {f} N is not finite"));
        }
        let f0 = disk_force;
        let back = f0.map(|f| -f);
        Ok(TlmLine {
            zc: shaft_k * delay,
            cs: shaft_c,
            delay,
            h: LineHistory {
                oj_prev: f0,
                vj_prev: [0.0; AXES],
                od_prev: back,
                od: back,
                w_prev: back,
                w: back,
            },
        })
    }

    /// Characteristic impedance `Z_c = k_s T` \[N·s/m\].
    pub fn zc(&self) -> f64 {
        self.zc
    }

    /// The impedance the journal side applies, `Z_c + c_s` \[N·s/m\] (output `tlm.Zc`).
    pub fn impedance(&self) -> f64 {
        self.zc + self.cs
    }

    /// Shaft damping `c_s` \[N·s/m\].
    pub fn damping(&self) -> f64 {
        self.cs
    }

    /// Delay `T` \[s\].
    pub fn delay(&self) -> f64 {
        self.delay
    }

    /// The line's parasitic mass `Z_c T = k_s T²` \[kg\].
    pub fn parasitic_mass(&self) -> f64 {
        self.zc * self.delay
    }

    /// `c0 = w(t_{k−1})`: the line's force on the journal at the start of the journal's next
    /// step, before the impedance term \[N\] (y, z).
    pub fn c0(&self) -> [f64; AXES] {
        self.h.w_prev
    }

    /// `c1 = w(t_k)`: the same at the end of the journal's next step \[N\] (y, z).
    pub fn c1(&self) -> [f64; AXES] {
        self.h.w
    }

    /// The line's force on the journal \[N\] (y, z) at the fraction `s ∈ [0, 1]` of the
    /// journal's next step, for its velocity `vj` then: `c0 + (c1 − c0) s − (Z_c + c_s) v_j`
    /// (what the bearing side applies).
    pub fn journal_force(&self, s: f64, vj: [f64; AXES]) -> [f64; AXES] {
        let (c0, c1, z) = (self.c0(), self.c1(), self.impedance());
        let mut f = [0.0; AXES];
        for (a, fa) in f.iter_mut().enumerate() {
            *fa = c0[a] + (c1[a] - c0[a]) * s - z * vj[a];
        }
        f
    }

    /// The history (for saving a state).
    pub fn history(&self) -> LineHistory {
        self.h
    }

    /// Replaces the history (restoring a [`TlmLine::history`] of a line with the same
    /// constants).
    pub fn set_history(&mut self, h: LineHistory) {
        self.h = h;
    }

    /// Step 1: the line's part of the step that starts now, given the journal velocity `vj`
    /// received for this communication point. Changes nothing (the history moves on only at
    /// [`TlmLine::end_step`], so a failed step leaves no trace).
    pub fn begin_step(&self, vj: [f64; AXES]) -> LineStep {
        let mut oj = [0.0; AXES];
        for (a, o) in oj.iter_mut().enumerate() {
            // g_j(t_k) = o_d(t_{k−1})
            *o = 2.0 * self.zc * vj[a] - self.h.od_prev[a];
        }
        LineStep {
            gd: [self.h.oj_prev, oj],
            vj: [self.h.vj_prev, vj],
            z: self.zc + self.cs,
            cs: self.cs,
        }
    }

    /// Step 3: the step `step` (from [`TlmLine::begin_step`] on this line) ended with the disk
    /// velocity `vd`: the disk end's new wave, and the history moves on by one point.
    #[allow(clippy::needless_range_loop)] // one axis index into several arrays
    pub fn end_step(&mut self, step: &LineStep, vd: [f64; AXES]) {
        let h = &mut self.h;
        for a in 0..AXES {
            // g_d(t_{k+1}) = o_j(t_k)
            let od = 2.0 * self.zc * vd[a] - step.gd[1][a];
            h.oj_prev[a] = step.gd[1][a];
            h.vj_prev[a] = step.vj[1][a];
            h.od_prev[a] = h.od[a];
            h.od[a] = od;
            h.w_prev[a] = h.w[a];
            h.w[a] = od + self.cs * vd[a];
        }
    }

    /// Energy of the waves travelling on the line at this communication point \[J\], given the
    /// journal velocity `vj` now: `T/(12 Z_c) Σ (a² + a b + b²)` over the two linear wave
    /// segments in transit per axis (towards the disk from `o_j(t_{k−1})` to
    /// `o_j(t_k) = 2 Z_c v_j − o_d(t_{k−1})`, towards the journal from `o_d(t_{k−1})` to
    /// `o_d(t_k)`). Carrying a static force `F` it is `F²/(2 k_s)`, the spring's energy.
    #[allow(clippy::needless_range_loop)] // one axis index into several arrays
    pub fn wave_energy(&self, vj: [f64; AXES]) -> f64 {
        let q = |a: f64, b: f64| a * a + a * b + b * b;
        let h = &self.h;
        let mut e = 0.0;
        for a in 0..AXES {
            let oj = 2.0 * self.zc * vj[a] - h.od_prev[a];
            e += q(h.oj_prev[a], oj) + q(h.od_prev[a], h.od[a]);
        }
        e * self.delay / (12.0 * self.zc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_at_rest_carries_its_static_force_to_the_journal() {
        let l = TlmLine::at_rest(2e6, 160.0, 1e-4, [3.0, 78.48]).unwrap();
        assert_eq!(l.zc(), 200.0);
        assert_eq!(l.impedance(), 360.0);
        assert_eq!(l.c0(), [-3.0, -78.48]);
        assert_eq!(l.c1(), [-3.0, -78.48]);
        assert!((l.parasitic_mass() - 0.02).abs() < 1e-15);
        // at rest the journal end reflects: o_j(t_0) = −o_d(t_{−1}) = F_0, the disk feels F_0
        let s = l.begin_step([0.0; AXES]);
        assert_eq!(s.disk_force(0.0, [0.0; AXES]), [3.0, 78.48]);
        assert_eq!(s.disk_force(0.5, [0.0; AXES]), [3.0, 78.48]);
        assert_eq!(s.disk_force(1.0, [0.0; AXES]), [3.0, 78.48]);
        // the spring's energy F²/(2 k_s)
        let e = (9.0 + 78.48 * 78.48) / 4e6;
        assert!((l.wave_energy([0.0; AXES]) / e - 1.0).abs() < 1e-14);
    }

    /// Two steps by hand: Zc = 1280 N/m · 1/128 s = 10 N·s/m, c_s = 2 N·s/m, F_0 = (0, 5) N.
    #[test]
    fn two_steps_follow_the_wave_equations() {
        let t = 1.0 / 128.0;
        let mut l = TlmLine::at_rest(1280.0, 2.0, t, [0.0, 5.0]).unwrap();
        assert_eq!((l.zc(), l.damping(), l.delay()), (10.0, 2.0, t));
        // step 1, v_j = (1, 2): o_j(t_0) = 2 Zc v_j − o_d(t_{−1}) = (20, 45)
        let s1 = l.begin_step([1.0, 2.0]);
        assert_eq!(
            l.history().oj_prev,
            [0.0, 5.0],
            "begin_step changes nothing"
        );
        // mid-step: g_d = (10, 25), v_j(t − T) = (0.5, 1); F = g_d − 12 v_d + 2 v_j(t − T)
        assert_eq!(s1.disk_force(0.5, [0.5, -1.0]), [5.0, 39.0]);
        assert_eq!(s1.disk_force(1.0, [0.0, 0.0]), [22.0, 49.0]);
        // end with v_d = (0.25, −0.5): o_d(t_1) = 2 Zc v_d − o_j(t_0) = (−15, −55)
        l.end_step(&s1, [0.25, -0.5]);
        let h = l.history();
        assert_eq!(h.oj_prev, [20.0, 45.0]);
        assert_eq!(h.vj_prev, [1.0, 2.0]);
        assert_eq!(h.od_prev, [0.0, -5.0]);
        assert_eq!(h.od, [-15.0, -55.0]);
        // w = o_d + c_s v_d
        assert_eq!((l.c0(), l.c1()), ([0.0, -5.0], [-14.5, -56.0]));
        assert_eq!(h.w_prev, l.c0());
        assert_eq!(h.w, l.c1());
        // the journal's force over its next step: c0 + (c1 − c0) s − (Zc + c_s) v_j
        assert_eq!(l.journal_force(0.5, [1.0, -1.0]), [-19.25, -18.5]);
        assert_eq!(l.journal_force(0.0, [0.0, 0.0]), l.c0());
        assert_eq!(l.journal_force(1.0, [0.0, 0.0]), l.c1());
        // waves in transit with v_j = (1, 0): towards the disk (20 → 20, 45 → 5), towards the
        // journal (0 → −15, −5 → −55): T/(12 Zc) (1200 + 225 + 2275 + 3325)
        let e = l.wave_energy([1.0, 0.0]);
        assert!((e - 7025.0 * t / 120.0).abs() < 1e-12, "{e}");
        // step 2, v_j = 0: o_j(t_1) = −o_d(t_0) = (0, 5); g_d from (20, 45) to (0, 5)
        let s2 = l.begin_step([0.0, 0.0]);
        assert_eq!(s2.disk_force(0.0, [0.0, 0.0]), [22.0, 49.0]);
        assert_eq!(s2.disk_force(1.0, [1.0, 1.0]), [-12.0, -7.0]);
        assert_eq!(s2.disk_force(0.25, [0.0, 0.0]), [15.0 + 1.5, 35.0 + 3.0]);
        l.end_step(&s2, [0.0, 0.0]);
        let h2 = l.history();
        assert_eq!(h2.oj_prev, [0.0, 5.0]);
        assert_eq!(h2.vj_prev, [0.0, 0.0]);
        assert_eq!(h2.od_prev, [-15.0, -55.0]);
        assert_eq!(h2.od, [0.0, -5.0]);
        assert_eq!((l.c0(), l.c1()), ([-14.5, -56.0], [0.0, -5.0]));
        // a restored history continues the same
        let mut m = TlmLine::at_rest(1280.0, 2.0, t, [0.0, 0.0]).unwrap();
        m.set_history(h);
        let s = m.begin_step([0.0, 0.0]);
        assert_eq!(s, s2);
    }

    #[test]
    fn invalid_constants_are_named() {
        assert!(TlmLine::at_rest(0.0, 0.0, 1e-4, [0.0; 2])
            .unwrap_err()
            .contains("shaft.k"));
        assert!(TlmLine::at_rest(1e6, -1.0, 1e-4, [0.0; 2])
            .unwrap_err()
            .contains("shaft.c"));
        assert!(TlmLine::at_rest(1e6, 0.0, 0.0, [0.0; 2])
            .unwrap_err()
            .contains("tlm.delay"));
        assert!(TlmLine::at_rest(1e6, 0.0, f64::NAN, [0.0; 2])
            .unwrap_err()
            .contains("tlm.delay"));
        assert!(TlmLine::at_rest(1e6, 0.0, 1e-4, [f64::INFINITY, 0.0])
            .unwrap_err()
            .contains("static force"));
    }

    #[test]
    fn accurate_delay_bounds_the_parasitic_mass_at_one_percent() {
        let (k, m) = (2e6, 8.0);
        let t = accurate_delay(k, m);
        assert!((t - 2e-4).abs() < 1e-18);
        let l = TlmLine::at_rest(k, 0.0, t, [0.0; 2]).unwrap();
        assert!((l.parasitic_mass() / m - 0.01).abs() < 1e-14);
    }
}
