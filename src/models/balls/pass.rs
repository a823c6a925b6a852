//! The contacts of one RHS evaluation of a per-ball model (full or reduced), in stages: every
//! ball's kinematics and normal contacts ([`ball_contact::evaluate_normal`]), then the strip
//! traction of all loaded contacts in one [`TractionBatch`], which lets the independent
//! contacts overlap. The models then read each ball's frame and finished contacts. The buffers
//! are sized once per model; an evaluation never allocates.

use super::ball_contact::{
    self, BallKin, ContactOut, GroovePos, RaceConst, RingPose, SlipField, Strips, TractionBatch, V3,
};
use crate::contact::TractionCurve;
use crate::vecmath;

/// A ball's kinematics with its cylindrical triad (e_r, e_θ), radius and orbital rate, as the
/// models' `ball_kin` return them.
pub type BallFrame = (BallKin, V3, V3, f64, f64);

/// The slip field and frame (n, c1, c2) of a loaded contact, where traction is wanted.
pub type Loaded = (SlipField, [V3; 3]);

/// One contact from [`ball_contact::evaluate_normal`]: the contact and, where loaded and traction
/// is wanted, its slip field and frame.
pub type Normal = (ContactOut, Option<Loaded>);

/// Scratch of the staged contact evaluation (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct ContactPass {
    /// Each ball's frame.
    pub frames: Vec<BallFrame>,
    /// Each ball's azimuth, and its sine and cosine.
    azimuths: Vec<f64>,
    sin: Vec<f64>,
    cos: Vec<f64>,
    /// Each ball's place in the (inner, outer) groove.
    grooves: Vec<[GroovePos; 2]>,
    /// Each ball's (inner, outer) contact, traction included.
    pub contacts: Vec<(ContactOut, ContactOut)>,
    batch: TractionBatch,
}

impl ContactPass {
    /// Scratch for `z` balls.
    pub fn new(z: usize) -> Self {
        let still = BallKin {
            p: [0.0; 3],
            v: [0.0; 3],
            omega: [0.0; 3],
        };
        Self {
            frames: vec![(still, [0.0; 3], [0.0; 3], 0.0, 0.0); z],
            azimuths: vec![0.0; z],
            sin: vec![0.0; z],
            cos: vec![0.0; z],
            grooves: vec![Default::default(); z],
            contacts: vec![Default::default(); z],
            batch: TractionBatch::new(2 * z),
        }
    }

    /// Evaluates the contacts of balls `0..z` with the (inner, outer) rings `rings` and race
    /// constants `races`: `azimuth(j)` gives ball j's azimuth, and `frame(j, (sin, cos))` its
    /// frame from the azimuth's sine and cosine (computed for all balls at once); then every
    /// ball's place in both grooves ([`ball_contact::groove_pos`]), for all balls at once; then
    /// `normals(j, kin, w, slip, grooves, out)` writes ball j's (inner, outer) normal contacts
    /// into `out` and returns the slip fields of the loaded ones when `slip` (traction on). The
    /// strip traction of every loaded contact follows in one batch.
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    #[inline(always)]
    pub fn evaluate(
        &mut self,
        z: usize,
        traction: Option<(&TractionCurve, &Strips)>,
        rings: [&RingPose; 2],
        races: [&RaceConst; 2],
        mut azimuth: impl FnMut(usize) -> f64,
        mut frame: impl FnMut(usize, (f64, f64)) -> BallFrame,
        mut normals: impl FnMut(
            usize,
            &BallKin,
            f64,
            bool,
            &[GroovePos; 2],
            &mut (ContactOut, ContactOut),
        ) -> [Option<Loaded>; 2],
    ) {
        self.batch.clear();
        let slip = traction.is_some();
        for (j, a) in self.azimuths[..z].iter_mut().enumerate() {
            *a = azimuth(j);
        }
        vecmath::sin_cos_into(&self.azimuths[..z], &mut self.sin, &mut self.cos);
        for (j, f) in self.frames[..z].iter_mut().enumerate() {
            *f = frame(j, (self.sin[j], self.cos[j]));
        }
        for (g, f) in self.grooves[..z].iter_mut().zip(&self.frames[..z]) {
            *g = [
                ball_contact::groove_pos(f.0.p, rings[0], races[0]),
                ball_contact::groove_pos(f.0.p, rings[1], races[1]),
            ];
        }
        for j in 0..z {
            let f = &self.frames[j];
            let [li, lo] = normals(j, &f.0, f.4, slip, &self.grooves[j], &mut self.contacts[j]);
            if let Some((sf, fr)) = li {
                self.batch.push(2 * j, sf, fr);
            }
            if let Some((sf, fr)) = lo {
                self.batch.push(2 * j + 1, sf, fr);
            }
        }
        if let Some((curve, strips)) = traction {
            let contacts = &mut self.contacts;
            self.batch.run(curve, strips, |slot, fr, sums| {
                let pair = &mut contacts[slot / 2];
                let c = if slot % 2 == 0 {
                    &mut pair.0
                } else {
                    &mut pair.1
                };
                ball_contact::apply_traction(c, fr, sums);
            });
        }
    }
}
