//! The impact test's measurement (docs/model.md#ref-dynamic, #c14), shared by the lumped and full-level tests:
//! the amplitude spectrum of the pedestal-acceleration pulse response.

use raceway::signal::{self, Window};
use raceway::{out, Scene, Simulation};

/// `pedestal.a.z` of the scene (sampled at its `output.sample_rate`) minus the same run without
/// the pulse, over `window` seconds from the pulse's start (which removes the running ball-pass
/// vibration), zero-padded to 1 s (1 Hz bins), rectangular window: the response has decayed
/// long before the record ends, so this is its Fourier transform.
pub fn pulse_response_spectrum(sc: &Scene, window: f64) -> signal::Spectrum {
    let fs = sc.output.sample_rate;
    let t0 = sc.pulse.as_ref().expect("a scene with a pulse").t0;
    let pedestal_az = |sc: &Scene| {
        let mut sim = Simulation::new(sc).expect("simulation builds");
        let mut a = Vec::new();
        sim.advance_sampled(t0 + window, 1.0 / fs, &mut |t, o| {
            if t >= t0 {
                a.push(o[out::PEDESTAL_A_Z]);
            }
        })
        .expect("simulation runs");
        a
    };
    let mut quiet = sc.clone();
    quiet.pulse = None;
    let (with, without) = (pedestal_az(sc), pedestal_az(&quiet));
    // Sample for sample: the pulse's corners are stops of the first run only, and a sample
    // written twice at a stop would shift every later one (tests/sampling.rs).
    assert_eq!(
        with.len(),
        without.len(),
        "the two records must share their sample times"
    );
    let mut d: Vec<f64> = with.iter().zip(&without).map(|(a, b)| a - b).collect();
    d.resize(fs as usize, 0.0);
    signal::amplitude_spectrum(&d, fs, Window::Rectangular).unwrap()
}
