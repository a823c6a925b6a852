//! The output vector every level fills ([`super::Model::outputs`]): the index of each fixed
//! output, then the per-ball block (inner and outer contact forces, orbital speeds, separation
//! flags), then, for a model with a cage, the cage block (the cage centre's displacement and
//! every ball's pocket force), and the name, unit and meaning of each ([`output_table`],
//! [`output_table_with_cage`]).

/// `pedestal.a.y`: pedestal acceleration along y [m/s²].
pub const PEDESTAL_A_Y: usize = 0;
/// `pedestal.a.z`: pedestal acceleration along z (the paper's radial acceleration) [m/s²].
pub const PEDESTAL_A_Z: usize = 1;
/// `pedestal.y`: pedestal (outer ring) displacement along y \[m\].
pub const PEDESTAL_Y: usize = 2;
/// `pedestal.z`: pedestal (outer ring) displacement along z \[m\].
pub const PEDESTAL_Z: usize = 3;
/// `pedestal.v.y`: pedestal velocity along y \[m/s\].
pub const PEDESTAL_V_Y: usize = 4;
/// `pedestal.v.z`: pedestal velocity along z \[m/s\].
pub const PEDESTAL_V_Z: usize = 5;
/// `ring.x`: inner-ring displacement along x (axial) \[m\].
pub const RING_X: usize = 6;
/// `ring.y`: inner-ring displacement along y \[m\].
pub const RING_Y: usize = 7;
/// `ring.z`: inner-ring displacement along z \[m\].
pub const RING_Z: usize = 8;
/// `bearing.F.x`: force of the bearing on the shaft (inner ring) along x \[N\].
pub const BEARING_F_X: usize = 9;
/// `bearing.F.y`: force of the bearing on the shaft (inner ring) along y \[N\].
pub const BEARING_F_Y: usize = 10;
/// `bearing.F.z`: force of the bearing on the shaft (inner ring) along z \[N\].
pub const BEARING_F_Z: usize = 11;
/// `torque.friction`: bearing friction (drive) torque [N m].
pub const FRICTION_TORQUE: usize = 12;
/// `cage.speed`: cage speed \[rad/s\]: the cage's own angular rate at a level with a cage,
/// else the mean orbital speed of the balls.
pub const CAGE_SPEED: usize = 13;
/// First of the z inner contact forces, then z outer ones; then the z ball orbital speeds
/// ([`orbit_speed`]) and the z separation flags ([`separated`]).
pub const CONTACT_START: usize = 14;
/// Number of bearing-level outputs (pedestal, ring, bearing force, torque, cage speed): an
/// output vector of this length has no per-ball block
/// ([`crate::simulation::Simulation::set_ball_outputs`]).
pub const BEARING_OUTPUTS: usize = CONTACT_START;

/// True when `o` has room for the per-ball block of a bearing with `z` balls (models fill
/// it only then).
#[inline]
pub fn has_ball_block(o: &[f64], z: usize) -> bool {
    o.len() >= separated(z, z)
}

/// Index of `cage.y`, the cage centre's displacement along y, in a bearing with `z` balls;
/// `cage.z` follows, then the z pocket forces ([`pocket_force`]).
#[inline]
pub fn cage_y(z: usize) -> usize {
    separated(z, z)
}

/// Index of `cage.z`, the cage centre's displacement along z.
#[inline]
pub fn cage_z(z: usize) -> usize {
    cage_y(z) + 1
}

/// Index of ball j's pocket force (j from 0) in a bearing with `z` balls.
#[inline]
pub fn pocket_force(z: usize, j: usize) -> usize {
    cage_y(z) + 2 + j
}

/// One past the cage block of a bearing with `z` balls.
#[inline]
pub fn cage_end(z: usize) -> usize {
    pocket_force(z, z)
}

/// True when `o` has room for the cage block (models with a cage fill it then, the other
/// ball-level models zero it).
#[inline]
pub fn has_cage_block(o: &[f64], z: usize) -> bool {
    o.len() >= cage_end(z)
}

/// Index of ball j's orbital speed θ̇ (j from 0) in a bearing with `z` balls.
#[inline]
pub fn orbit_speed(z: usize, j: usize) -> usize {
    CONTACT_START + 2 * z + j
}

/// Index of ball j's separation flag (j from 0) in a bearing with `z` balls.
#[inline]
pub fn separated(z: usize, j: usize) -> usize {
    CONTACT_START + 3 * z + j
}

/// Sets every ball's separation flag from its contact forces already in `o`: 1 when the
/// ball touches neither race (both normal forces zero), else 0.
#[inline]
pub fn set_separation_flags(o: &mut [f64], z: usize) {
    // One bounds check for the four blocks (inner, outer, orbit, flags), not three per ball:
    // the kinematic and quasi-static levels call this at every output sample.
    let (forces, rest) = o[CONTACT_START..separated(z, z)].split_at_mut(2 * z);
    let (q_in, q_out) = forces.split_at(z);
    let flags = &mut rest[z..];
    for ((f, qi), qo) in flags.iter_mut().zip(q_in).zip(q_out) {
        *f = if *qi == 0.0 && *qo == 0.0 { 1.0 } else { 0.0 };
    }
}

/// Name, unit and meaning of one output.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputInfo {
    /// The output's name, e.g. `pedestal.a.z` or `contact.inner.Q[3]`.
    pub name: String,
    /// Its unit, e.g. `m/s2`.
    pub unit: &'static str,
    /// What it is, in one sentence.
    pub description: String,
}

/// The outputs of a bearing with `z` balls, in output-vector order.
pub fn output_table(z: usize) -> Vec<OutputInfo> {
    let mut v: Vec<OutputInfo> = [
        ("pedestal.a.y", "m/s2", "Pedestal acceleration along y"),
        (
            "pedestal.a.z",
            "m/s2",
            "Pedestal acceleration along z (the paper's radial acceleration)",
        ),
        (
            "pedestal.y",
            "m",
            "Pedestal (outer ring) displacement along y",
        ),
        (
            "pedestal.z",
            "m",
            "Pedestal (outer ring) displacement along z",
        ),
        ("pedestal.v.y", "m/s", "Pedestal velocity along y"),
        ("pedestal.v.z", "m/s", "Pedestal velocity along z"),
        ("ring.x", "m", "Inner-ring displacement along x (axial)"),
        ("ring.y", "m", "Inner-ring displacement along y"),
        ("ring.z", "m", "Inner-ring displacement along z"),
        (
            "bearing.F.x",
            "N",
            "Force of the bearing on the shaft (inner ring) along x",
        ),
        (
            "bearing.F.y",
            "N",
            "Force of the bearing on the shaft (inner ring) along y",
        ),
        (
            "bearing.F.z",
            "N",
            "Force of the bearing on the shaft (inner ring) along z",
        ),
        (
            "torque.friction",
            "N.m",
            "Bearing friction (drive) torque; 0 at levels without traction (kinematic, lumped)",
        ),
        (
            "cage.speed",
            "rad/s",
            "Cage speed: the cage's angular rate at the reduced and full levels with a cage, \
             else the mean orbital speed of the balls",
        ),
    ]
    .into_iter()
    .map(|(n, u, d)| OutputInfo {
        name: n.to_string(),
        unit: u,
        description: d.to_string(),
    })
    .collect();
    for race in ["inner", "outer"] {
        for j in 1..=z {
            v.push(OutputInfo {
                name: format!("contact.{race}.Q[{j}]"),
                unit: "N",
                description: format!("Normal contact force of ball {j} on the {race} race"),
            });
        }
    }
    for j in 1..=z {
        v.push(OutputInfo {
            name: format!("ball.orbit_speed[{j}]"),
            unit: "rad/s",
            description: format!(
                "Orbital speed of ball {j} about the shaft axis (the cage speed at the kinematic \
                 and quasi-static levels, plus the slip-jitter rate at the lumped level)"
            ),
        });
    }
    for j in 1..=z {
        v.push(OutputInfo {
            name: format!("ball.separated[{j}]"),
            unit: "1",
            description: format!(
                "1 while ball {j} touches neither race (both contact forces zero), else 0"
            ),
        });
    }
    v
}

/// The outputs of a bearing with `z` balls and a cage: [`output_table`] and the cage block
/// (the cage centre's displacement, every ball's pocket force).
pub fn output_table_with_cage(z: usize) -> Vec<OutputInfo> {
    let mut v = output_table(z);
    for (axis, k) in [("y", cage_y(z)), ("z", cage_z(z))] {
        debug_assert_eq!(v.len(), k);
        v.push(OutputInfo {
            name: format!("cage.{axis}"),
            unit: "m",
            description: format!(
                "Cage centre displacement along {axis} (its whirl); 0 without a cage"
            ),
        });
    }
    for j in 1..=z {
        v.push(OutputInfo {
            name: format!("cage.pocket.P[{j}]"),
            unit: "N",
            description: format!(
                "Normal force between ball {j} and its pocket: > 0 when the ball presses the \
                 pocket's leading face (the ball drives the cage), < 0 the trailing face (the \
                 cage drives the ball); 0 without a cage"
            ),
        });
    }
    v
}

/// The output table of a model with (`cage`) or without a cage.
pub fn output_table_for(z: usize, cage: bool) -> Vec<OutputInfo> {
    if cage {
        output_table_with_cage(z)
    } else {
        output_table(z)
    }
}
