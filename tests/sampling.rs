//! Fixed-rate output sampling across stops: every grid point k·dt is written exactly once, in
//! order, even when a stop (a pulse corner, an input change) falls on it within rounding.

use raceway::solver::grid_points;
use raceway::{Fidelity, Scene, Simulation};

/// Consecutive steps [a, b] and [b, c] split the grid points of [a, c] between them, with b a
/// stop computed as a sum (t0 + 100 µs) that lands within rounding of a grid point.
#[test]
fn grid_points_of_adjacent_steps_partition_the_grid() {
    let mut checked_on_grid = 0;
    for dt in [1.0 / 51_200.0, 1.0 / 102_400.0, 5e-6, 2.5e-6, 1.25e-6, 1e-5] {
        for t0 in [2e-3, 20e-3, 0.1, 0.37] {
            for d in [5e-5, 1e-4, 1e-3] {
                let (a, b) = (t0 - 3e-4, t0 + d);
                let c = b + 2e-4;
                let whole: Vec<f64> = grid_points(dt, a, c).collect();
                let mut split: Vec<f64> = grid_points(dt, a, b).collect();
                split.extend(grid_points(dt, b, c));
                assert_eq!(
                    split, whole,
                    "dt {dt}, stop at {b}: the two steps' points are not the grid's"
                );
                assert!(whole.windows(2).all(|w| w[1] > w[0]));
                if ((b / dt) - (b / dt).round()).abs() < 1e-6 {
                    checked_on_grid += 1;
                }
            }
        }
    }
    // The cases that matter: stops within rounding of a grid point.
    assert!(checked_on_grid >= 20, "{checked_on_grid}");
}

/// The impact scene's pulse corners (stops at t0, t0 + 50 µs, t0 + 100 µs) fall on the 200 kHz
/// grid: the sampled record still has one sample per grid point, at k·dt.
#[test]
fn samples_at_a_stop_on_the_grid_are_written_once() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/impact-test-fa4000.toml");
    let mut sc = Scene::load(&path).unwrap();
    sc.fidelity = Fidelity::Lumped;
    let pulse = sc.pulse.as_mut().unwrap();
    pulse.t0 = 2e-3;
    let end = pulse.t0 + pulse.duration + 1e-3;
    let fs = 200_000.0;
    let mut sim = Simulation::new(&sc).unwrap();
    let mut times = Vec::new();
    sim.advance_sampled(end, 1.0 / fs, &mut |t, _| times.push(t))
        .unwrap();
    let expected = (end * fs).round() as usize;
    assert_eq!(times.len(), expected, "one sample per grid point");
    for (i, t) in times.iter().enumerate() {
        let k = (i + 1) as f64;
        assert!(
            (t * fs - k).abs() < 1e-6,
            "sample {i} at {t} s, expected {} s",
            k / fs
        );
    }
}

/// `raceway simulate` advances in 1 % chunks of the run; on the default scene (0.5 s at
/// 51.2 kHz) the chunk ends fall on the sample grid, and three of them (0.235, 0.285, 0.47 s)
/// rounded so that a sample was written twice, which `raceway spectrum` then refused as
/// non-uniform sampling. Chunk ends of consecutive advances partition the grid like stops.
#[test]
fn chunked_advances_write_every_sample_once() {
    let mut sc = Scene::default_scene();
    sc.fidelity = Fidelity::Kinematic;
    let duration = sc.output.duration;
    let dt = 1.0 / sc.output.sample_rate;
    let mut sim = Simulation::new(&sc).unwrap();
    let mut times = Vec::new();
    let chunks = 100;
    for c in 1..=chunks {
        let t_end = duration * c as f64 / chunks as f64;
        sim.advance_sampled(t_end, dt, &mut |t, _| times.push(t))
            .unwrap();
    }
    assert_eq!(times.len(), (duration / dt).round() as usize);
    for w in times.windows(2) {
        assert!(w[1] > w[0], "sample at {} s written twice", w[0]);
    }
}
