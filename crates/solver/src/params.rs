//! The model's parameters (SPEC section 2) and their validation.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::error::{NameError, ParamError};

/// One fiber (spindle cells) or two parallel fibers at spacing `L`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Geometry {
    One,
    Two,
}

impl std::str::FromStr for Geometry {
    type Err = NameError;
    fn from_str(s: &str) -> Result<Self, NameError> {
        match s {
            "one" | "1" => Ok(Geometry::One),
            "two" | "2" => Ok(Geometry::Two),
            _ => Err(NameError::Geometry(s.to_string())),
        }
    }
}

impl std::fmt::Display for Geometry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Geometry::One => "one",
            Geometry::Two => "two",
        })
    }
}

/// Every symbol of SPEC section 2, in simulation units (l0 = tau0 = eps0 = 1).
///
/// Serialized with the SPEC's symbols as keys (`R0`, `E0`, `A_ref`, `A`, `L`); the transport
/// coefficient 1/gamma is `inv_gamma`. Defaults are the paper's Table I, with `alpha = 0.1`,
/// `beta = 10`, `L = 90`, `sigma = 5` and two fibers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Params {
    /// Line-tension parameter (swept).
    pub alpha: f64,
    /// Polarity positive feedback (swept).
    pub beta: f64,
    /// Fiber spacing, center to center, an even number of lattice sites (swept).
    pub L: u32,
    /// Cell-cell adhesion (swept).
    pub sigma: f64,
    /// One or two fibers.
    pub geometry: Geometry,
    /// Boundary width.
    pub d: f64,
    /// Target radius.
    pub R0: f64,
    /// Area constraint.
    pub lambda: f64,
    /// Cell-fiber adhesion.
    pub E0: f64,
    /// Adhesion reference area.
    pub A_ref: f64,
    /// Cell-cell exclusion.
    pub g: f64,
    /// Transport coefficient 1/gamma.
    pub inv_gamma: f64,
    /// Friction.
    pub eta: f64,
    /// Velocity-noise strength.
    pub v0: f64,
    /// Motility force.
    pub A: f64,
    /// Polarity decay time.
    pub tau: f64,
    /// Time step.
    pub dt: f64,
    /// Noise sampling period (a whole multiple of dt).
    pub t_sample: f64,
    /// Polarity cut-off.
    pub phi_min: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            alpha: 0.1,
            beta: 10.0,
            L: 90,
            sigma: 5.0,
            geometry: Geometry::Two,
            d: 20f64.sqrt(),
            R0: 40.0,
            lambda: 1000.0,
            E0: 2000.0,
            A_ref: 1.0,
            g: 1.0,
            inv_gamma: 50.0,
            eta: 1.0,
            v0: 0.1,
            A: 200.0,
            tau: 100.0,
            dt: 0.002,
            t_sample: 0.002,
            phi_min: 0.001,
        }
    }
}

/// Names of every settable parameter, as written in sweep files and on the command line.
pub const PARAM_NAMES: &[&str] = &[
    "alpha",
    "beta",
    "L",
    "sigma",
    "geometry",
    "d",
    "R0",
    "lambda",
    "E0",
    "A_ref",
    "g",
    "inv_gamma",
    "eta",
    "v0",
    "A",
    "tau",
    "dt",
    "t_sample",
    "phi_min",
];

impl Params {
    /// The diffusive number of the explicit scheme, (1/gamma) alpha d^2/2 dt (must be <= 0.25).
    pub fn diffusive_number(&self) -> f64 {
        self.inv_gamma * self.alpha * self.d * self.d / 2.0 * self.dt
    }

    /// Target area pi R0^2.
    pub fn target_area(&self) -> f64 {
        PI * self.R0 * self.R0
    }

    /// Steps between two noise draws (t_sample / dt, checked to be whole by `validate`).
    pub fn sample_every(&self) -> u64 {
        (self.t_sample / self.dt).round().max(1.0) as u64
    }

    /// One parameter by its SPEC name as a number (geometry: 1 or 2; L as a number), or None
    /// for a name that is not a parameter. `set(name, get(name))` changes nothing.
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "alpha" => self.alpha,
            "beta" => self.beta,
            "L" => self.L as f64,
            "sigma" => self.sigma,
            "geometry" => match self.geometry {
                Geometry::One => 1.0,
                Geometry::Two => 2.0,
            },
            "d" => self.d,
            "R0" => self.R0,
            "lambda" => self.lambda,
            "E0" => self.E0,
            "A_ref" => self.A_ref,
            "g" => self.g,
            "inv_gamma" => self.inv_gamma,
            "eta" => self.eta,
            "v0" => self.v0,
            "A" => self.A,
            "tau" => self.tau,
            "dt" => self.dt,
            "t_sample" => self.t_sample,
            "phi_min" => self.phi_min,
            _ => return None,
        })
    }

    /// Set one parameter by its SPEC name from a number (geometry takes 1 or 2).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), NameError> {
        let slot = match name {
            "alpha" => &mut self.alpha,
            "beta" => &mut self.beta,
            "sigma" => &mut self.sigma,
            "d" => &mut self.d,
            "R0" => &mut self.R0,
            "lambda" => &mut self.lambda,
            "E0" => &mut self.E0,
            "A_ref" => &mut self.A_ref,
            "g" => &mut self.g,
            "inv_gamma" => &mut self.inv_gamma,
            "eta" => &mut self.eta,
            "v0" => &mut self.v0,
            "A" => &mut self.A,
            "tau" => &mut self.tau,
            "dt" => &mut self.dt,
            "t_sample" => &mut self.t_sample,
            "phi_min" => &mut self.phi_min,
            "L" => {
                if value.fract() != 0.0 || !(0.0..=u32::MAX as f64).contains(&value) {
                    return Err(NameError::Spacing(value));
                }
                self.L = value as u32;
                return Ok(());
            }
            "geometry" => {
                self.geometry = match value as i64 {
                    1 => Geometry::One,
                    2 => Geometry::Two,
                    _ => return Err(NameError::GeometryNumber(value)),
                };
                return Ok(());
            }
            _ => {
                return Err(NameError::Parameter {
                    given: name.to_string(),
                    known: PARAM_NAMES.join(", "),
                })
            }
        };
        *slot = value;
        Ok(())
    }

    /// Check every parameter against physical sense, the fiber geometry on a lattice of height
    /// `ny`, and the explicit-scheme stability guard of SPEC section 2.
    pub fn validate(&self, ny: usize) -> Result<(), ParamError> {
        let all = [
            ("alpha", self.alpha),
            ("beta", self.beta),
            ("sigma", self.sigma),
            ("d", self.d),
            ("R0", self.R0),
            ("lambda", self.lambda),
            ("E0", self.E0),
            ("A_ref", self.A_ref),
            ("g", self.g),
            ("inv_gamma", self.inv_gamma),
            ("eta", self.eta),
            ("v0", self.v0),
            ("A", self.A),
            ("tau", self.tau),
            ("dt", self.dt),
            ("t_sample", self.t_sample),
            ("phi_min", self.phi_min),
        ];
        for (name, value) in all {
            if !value.is_finite() {
                return Err(ParamError::NotFinite { name, value });
            }
        }
        let positive = [
            ("alpha", self.alpha),
            ("d", self.d),
            ("R0", self.R0),
            ("A_ref", self.A_ref),
            ("inv_gamma", self.inv_gamma),
            ("eta", self.eta),
            ("tau", self.tau),
            ("dt", self.dt),
            ("t_sample", self.t_sample),
        ];
        for (name, value) in positive {
            if value <= 0.0 {
                return Err(ParamError::NotPositive { name, value });
            }
        }
        let non_negative = [
            ("beta", self.beta),
            ("sigma", self.sigma),
            ("lambda", self.lambda),
            ("E0", self.E0),
            ("g", self.g),
            ("v0", self.v0),
            ("A", self.A),
        ];
        for (name, value) in non_negative {
            if value < 0.0 {
                return Err(ParamError::Negative { name, value });
            }
        }
        if !(self.phi_min > 0.0 && self.phi_min < 0.5) {
            return Err(ParamError::OutOfRange {
                name: "phi_min",
                value: self.phi_min,
                range: "(0, 0.5)",
            });
        }
        if self.geometry == Geometry::Two {
            if !self.L.is_multiple_of(2) {
                return Err(ParamError::OddSpacing(self.L));
            }
            if self.L < 4 {
                return Err(ParamError::SpacingTooSmall { spacing: self.L });
            }
            if self.L as usize + 2 > ny {
                return Err(ParamError::SpacingTooLarge {
                    spacing: self.L,
                    ny,
                });
            }
        }
        let number = self.diffusive_number();
        if number > 0.25 {
            return Err(ParamError::Unstable {
                number,
                inv_gamma: self.inv_gamma,
                alpha: self.alpha,
                d: self.d,
                dt: self.dt,
            });
        }
        let ratio = self.t_sample / self.dt;
        if (ratio - ratio.round()).abs() > 1e-9 * ratio.max(1.0) || ratio.round() < 1.0 {
            return Err(ParamError::SampleNotMultiple {
                t_sample: self.t_sample,
                dt: self.dt,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_gets_what_set_gave_it() {
        for (i, name) in PARAM_NAMES.iter().enumerate() {
            let mut p = Params::default();
            let value = match *name {
                "geometry" => 1.0,
                "L" => 64.0,
                _ => 0.5 + i as f64,
            };
            p.set(name, value).unwrap();
            assert_eq!(p.get(name), Some(value), "{name}");
            let mut q = Params::default();
            q.set(name, p.get(name).unwrap()).unwrap();
            assert_eq!(p, q, "{name}: set(get) changes nothing else");
            assert_ne!(q, Params::default(), "{name}: set reached its own field");
        }
        assert_eq!(Params::default().get("radius"), None);
    }
}
