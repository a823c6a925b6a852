//! Ball bouncing between the races, counted from sampled contact forces (shared by the full and
//! reduced spall tests).

/// Number of changes between inner-only and outer-only contact of one ball over the samples
/// `from..to` of its inner (`qi`) and outer (`qo`) contact forces; instants with both or no
/// contact do not count as a state.
pub fn inner_outer_alternations(qi: &[f64], qo: &[f64], from: usize, to: usize) -> usize {
    let (mut switches, mut last) = (0, 0i8);
    for k in from..to.min(qi.len()).min(qo.len()) {
        let state = match (qi[k] > 0.0, qo[k] > 0.0) {
            (true, false) => 1,
            (false, true) => -1,
            _ => 0,
        };
        if state != 0 && state != last {
            switches += usize::from(last != 0);
            last = state;
        }
    }
    switches
}
