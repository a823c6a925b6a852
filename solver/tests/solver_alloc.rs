//! The stepping loop does not allocate: a counting global allocator watches `advance` and
//! `advance_with_events` after the first call (which may size the event buffers).

use raceway_solver::*;
#[path = "../../tests/common/alloc_counter.rs"]
mod alloc_counter;
use alloc_counter::allocations_during;

struct Ball;
impl System for Ball {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = y[1];
        d[1] = -9.81 - 0.1 * y[1];
    }
}
impl EventSystem for Ball {
    fn n_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn handle_event(&mut self, _i: usize, _t: f64, y: &mut [f64]) -> EventAction {
        y[1] *= -0.9;
        EventAction::Continue
    }
}

#[test]
fn stepping_does_not_allocate() {
    for m in Method::ALL {
        let o = if m == Method::Rk4 {
            Options::fixed(m, 1e-3)
        } else {
            Options::new(m, 1e-8, vec![1e-8])
        };
        let mut it = Integrator::new(o, 0.0, &[1.0, 0.0]).unwrap();
        let mut sum = 0.0;
        let mut buf = [0.0; 2];
        let mut obs = |v: &StepView| {
            v.interpolate(0.5 * (v.t_start() + v.t_end()), &mut buf);
            sum += buf[0];
        };
        it.advance_with_events(&mut Ball, 0.1, Some(&mut obs))
            .unwrap();
        let (n, ()) = allocations_during(|| {
            it.advance_with_events(&mut Ball, 5.0, Some(&mut obs))
                .unwrap();
            it.advance(&mut Ball, 6.0, None).unwrap();
            it.advance(&mut Ball, 7.0, Some(&mut obs)).unwrap();
        });
        assert!(
            it.stats().events > 2,
            "{m}: {:?} y={:?}",
            it.stats(),
            it.y()
        );
        assert_eq!(n, 0, "{m}: {n} allocations while stepping");
    }
}

/// A checkpoint puts the integrator back exactly: after work that is then discarded, the
/// continuation from the rollback equals (bit for bit, work counters included) the continuation
/// of a copy that never did that work, events included; taking and restoring checkpoints does
/// not allocate once the checkpoint has its size.
#[test]
fn rollback_to_a_checkpoint_continues_bit_identically_without_allocating() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let mut a = Integrator::new(Options::new(m, 1e-8, vec![1e-8]), 0.0, &[1.0, 0.0]).unwrap();
        // Stop just after a bounce, so the event memory is part of the state.
        a.advance_with_events(&mut Ball, 0.7, None).unwrap();
        let mut c = Checkpoint::default();
        a.checkpoint(&mut c);
        let mut reference = a.clone();
        reference.advance_with_events(&mut Ball, 2.3, None).unwrap();
        let (n, ()) = allocations_during(|| {
            a.checkpoint(&mut c);
            a.advance_with_events(&mut Ball, 1.9, None).unwrap();
            a.rollback(&c);
        });
        assert_eq!(n, 0, "{m}: {n} allocations in checkpoint/rollback");
        assert_eq!(a.t(), 0.7, "{m}");
        a.advance_with_events(&mut Ball, 2.3, None).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a.y()), bits(reference.y()), "{m}");
        assert_eq!(a.h_next().to_bits(), reference.h_next().to_bits(), "{m}");
        assert_eq!(a.stats(), reference.stats(), "{m}");
    }
}
