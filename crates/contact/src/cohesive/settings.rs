//! The parameters of a cohesive interface: the traction–separation law (seed §2.4) and
//! the distance within which nodes bond.

use super::error::CohesiveError;

/// What the law does with the tangential (in-plane) separations δ_s, δ_t.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TangentialMode {
    /// Shear tractions t_s = (1 − D) K_ss δ_s, t_t = (1 − D) K_tt δ_t, and the tangential
    /// separations count in the effective separation that drives damage (the paper's
    /// K_ss = K_tt = 0.05 N/mm³).
    #[default]
    Elastic,
    /// No shear traction: bonded surfaces slide freely, only the normal cohesion acts and
    /// only the normal opening drives damage (the paper's "restricts separation by
    /// tension, but permits relative sliding"). The gap and the direction of the normal
    /// traction are those of the closest point of the faceted main surface (`slide.rs`).
    FreeSlide,
    /// As [`TangentialMode::FreeSlide`], but the gap and the direction of the normal
    /// traction are measured along the smooth field of averaged vertex normals of the main
    /// surface (`smooth_slide.rs`), so the force stays a continuous function of the
    /// positions when a node slides over the edges and vertices of the faceted main
    /// surface, concave ones included (where the closest point, and FreeSlide's force
    /// direction, jump).
    SmoothSlide,
}

/// Parameters of a [`super::CohesiveInterface`], in SI units.
///
/// The defaults are the paper's (seed §2.4): K_nn = K_ss = K_tt = 0.05 N/mm³ = 5e7 N/m³,
/// damage initiation at 30 mm = 0.03 m of separation. The paper gives no failure
/// separation; the default is δ_f = 2 δ_0 = 0.06 m (fracture energy
/// G_c = ½ K_nn δ_0 δ_f = 4.5e4 J/m² in mode I).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveSettings {
    /// K_nn: normal traction per normal separation [N/m³ = Pa/m].
    pub normal_stiffness: f64,
    /// K_ss: shear traction per separation along the first in-plane direction s [N/m³]
    /// (s follows the first edge of each main triangle, so with K_ss ≠ K_tt the in-plane
    /// axes depend on the mesh; the paper has K_ss = K_tt).
    pub shear_stiffness: f64,
    /// K_tt: shear traction per separation along the second in-plane direction t = n × s
    /// [N/m³].
    pub tangential_stiffness: f64,
    /// δ_0: effective separation at which damage starts [m].
    pub initiation_separation: f64,
    /// δ_f: effective separation at which the bond has failed (D = 1) [m], > δ_0.
    pub failure_separation: f64,
    /// Shear response: [`TangentialMode::Elastic`], [`TangentialMode::FreeSlide`] or
    /// [`TangentialMode::SmoothSlide`].
    pub tangential: TangentialMode,
    /// A secondary node bonds if it lies within this distance of the main surface in the
    /// reference configuration [m]. The bond forms stress-free: its separation is
    /// measured from where the node lay then, so an initial gap is the bond's rest state.
    pub bond_tolerance: f64,
}

impl Default for CohesiveSettings {
    /// The paper's values (K = 5e7 N/m³, δ_0 = 0.03 m), δ_f = 2 δ_0, elastic shear, bond
    /// tolerance 0.1 mm.
    fn default() -> Self {
        CohesiveSettings {
            normal_stiffness: 5e7,
            shear_stiffness: 5e7,
            tangential_stiffness: 5e7,
            initiation_separation: 0.03,
            failure_separation: 0.06,
            tangential: TangentialMode::Elastic,
            bond_tolerance: 1e-4,
        }
    }
}

impl CohesiveSettings {
    /// Checks that stiffnesses are finite and non-negative (K_nn positive), that
    /// 0 < δ_0 < δ_f are finite and that the bond tolerance is finite and non-negative.
    /// `interface` names the interface in the error.
    pub fn validate(&self, interface: &str) -> Result<(), CohesiveError> {
        let bad = |reason: String| {
            Err(CohesiveError::InvalidSettings {
                interface: interface.to_string(),
                reason,
            })
        };
        if !(self.normal_stiffness.is_finite() && self.normal_stiffness > 0.0) {
            return bad(format!(
                "normal stiffness {} N/m³ must be finite and positive",
                self.normal_stiffness
            ));
        }
        for (name, value) in [
            ("shear", self.shear_stiffness),
            ("tangential", self.tangential_stiffness),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return bad(format!(
                    "{name} stiffness {value} N/m³ must be finite and non-negative"
                ));
            }
        }
        let (initiation, failure) = (self.initiation_separation, self.failure_separation);
        if !(initiation.is_finite() && failure.is_finite() && initiation > 0.0) {
            return bad(format!(
                "initiation separation {initiation} m and failure separation {failure} m must \
                 be finite and positive"
            ));
        }
        if failure <= initiation {
            return bad(format!(
                "failure separation {failure} m must exceed the initiation separation \
                 {initiation} m"
            ));
        }
        if !(self.bond_tolerance.is_finite() && self.bond_tolerance >= 0.0) {
            return bad(format!(
                "bond tolerance {} m must be finite and non-negative",
                self.bond_tolerance
            ));
        }
        Ok(())
    }

    /// Mode-I fracture energy of the linear law, G_c = ½ K_nn δ_0 δ_f [J/m²].
    pub fn fracture_energy(&self) -> f64 {
        0.5 * self.normal_stiffness * self.initiation_separation * self.failure_separation
    }

    /// Peak normal traction σ_max = K_nn δ_0 [Pa].
    pub fn strength(&self) -> f64 {
        self.normal_stiffness * self.initiation_separation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_papers_values_in_si() {
        let s = CohesiveSettings::default();
        // 0.05 N/mm³ = 0.05 N / 1e-9 m³.
        assert_eq!(s.normal_stiffness, 0.05 / 1e-9);
        assert_eq!(s.shear_stiffness, 0.05 / 1e-9);
        assert_eq!(s.tangential_stiffness, 0.05 / 1e-9);
        assert_eq!(s.initiation_separation, 30e-3);
        assert_eq!(s.failure_separation, 2.0 * s.initiation_separation);
        assert!(s.validate("i").is_ok());
        assert!((s.strength() - 1.5e6).abs() < 1e-6);
        assert!((s.fracture_energy() - 4.5e4).abs() < 1e-8);
    }

    #[test]
    fn bad_settings_are_refused_with_the_interface_name() {
        let s = CohesiveSettings {
            failure_separation: 0.02,
            ..CohesiveSettings::default()
        };
        let message = s.validate("glue").unwrap_err().to_string();
        assert!(message.contains("'glue'"), "{message}");
        assert!(message.contains("must exceed"), "{message}");
        let s = CohesiveSettings {
            normal_stiffness: 0.0,
            ..CohesiveSettings::default()
        };
        assert!(s.validate("glue").is_err());
        let s = CohesiveSettings {
            bond_tolerance: f64::NAN,
            ..CohesiveSettings::default()
        };
        assert!(s.validate("glue").is_err());
    }
}
