//! The integration methods offered by the engine.

use super::methods;
use super::tableau::Tableau;

/// An explicit Runge–Kutta method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Method {
    /// Fehlberg 4(5), propagating the 4th-order solution (as in the paper); cubic Hermite dense output.
    Rkf45,
    /// Dormand–Prince 5(4), FSAL, Hairer's 4th-order continuous extension.
    Dopri5,
    /// Hairer's DOP853: 8th order, 5th/3rd-order combined error estimate, 7th-order dense output.
    Dop853,
    /// Classic 4th-order Runge–Kutta; fixed step only; cubic Hermite dense output.
    Rk4,
}

impl Method {
    /// All methods, in a fixed order.
    pub const ALL: [Method; 4] = [Method::Rkf45, Method::Dopri5, Method::Dop853, Method::Rk4];

    /// Lower-case name: "rkf45", "dopri5", "dop853", "rk4".
    pub fn name(self) -> &'static str {
        match self {
            Method::Rkf45 => "rkf45",
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
            Method::Rk4 => "rk4",
        }
    }

    /// Inverse of [`Method::name`] (ASCII case-insensitive); `None` for an unknown name.
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
    }

    /// Order of the propagated solution (RKF45 4, DOPRI5 5, DOP853 8, RK4 4).
    pub fn order(self) -> u32 {
        self.tableau().order
    }

    /// Whether the method has an embedded error estimator (can run adaptively).
    pub fn is_adaptive(self) -> bool {
        self.tableau().has_error_estimate()
    }

    /// The Butcher tableau of the method.
    pub fn tableau(self) -> &'static Tableau {
        match self {
            Method::Rkf45 => &methods::rkf45::RKF45,
            Method::Dopri5 => &methods::dopri5::DOPRI5,
            Method::Dop853 => &methods::dop853::DOP853,
            Method::Rk4 => &methods::rk4::RK4,
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Some(m));
        }
        assert_eq!(Method::from_name("DOP853"), Some(Method::Dop853));
        assert_eq!(Method::from_name("euler"), None);
        assert_eq!(Method::Rkf45.order(), 4);
        assert_eq!(Method::Dopri5.order(), 5);
        assert_eq!(Method::Dop853.order(), 8);
        assert_eq!(Method::Rk4.order(), 4);
        assert!(!Method::Rk4.is_adaptive());
    }
}
