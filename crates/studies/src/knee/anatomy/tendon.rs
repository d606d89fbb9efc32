//! The patellar tendon: a nonlinear spring from the patella's apex to the tibial
//! tuberosity.
//!
//! **Law.** The toe-then-linear spring of Blankevoort & Huiskes (1991, J Biomech Eng
//! 113:263), the form the knee models the paper built on use for ligaments, with the
//! strain ε = ℓ/ℓ₀ − 1:
//!
//! ```text
//! f(ε) = 0                      ε < 0      (slack)
//!      = k ε² / (4 ε_l)         0 ≤ ε ≤ 2 ε_l  (toe: the crimped fibres straighten)
//!      = k (ε − ε_l)            ε > 2 ε_l  (linear)
//! ```
//!
//! f and its slope are continuous at 2 ε_l. The law is `musclefem-contact`'s
//! [`ToeLinearLaw`], which the tendon strands of the quadriceps evaluate too.
//!
//! **Stiffness source.** k = K ℓ₀ [N] with K = 1076 N/mm, the linear stiffness of men's
//! patellar tendons measured in vivo by O'Brien, Reeves, Baltzopoulos, Jones & Maganaris
//! (2010, J Biomech 43:1190: ultrasound of the tendon during ramped isometric knee
//! extension; maximal tendon force 5453 N at 5.0 mm elongation). ε_l = 0.03 is
//! Blankevoort's spread strain of the toe region. ℓ₀ is the knee's tendon length
//! ([`KneeDimensions::patellar_tendon_length`]; the procedural knee's
//! [`PATELLAR_TENDON_LENGTH`](super::dimensions::PATELLAR_TENDON_LENGTH)). At O'Brien's maximal force this spring is
//! 6.6 mm longer than at rest, against the 5.0 ± 0.5 mm measured: the 3 % toe region
//! adds 1.5 mm that the in-vivo measurement (which starts from a preloaded tendon) sees
//! only in part.

use musclefem_contact::ToeLinearLaw;

use super::dimensions::KneeDimensions;

/// Linear stiffness of the patellar tendon [N/m] (O'Brien et al. 2010, men).
pub const PATELLAR_TENDON_STIFFNESS: f64 = 1076.0e3;
/// Spread strain ε_l of the toe region (Blankevoort & Huiskes 1991).
pub const PATELLAR_TENDON_TOE_STRAIN: f64 = 0.03;

/// A toe-then-linear tendon spring (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TendonSpring {
    /// Slack length ℓ₀ [m]: no force at or below it.
    pub slack_length: f64,
    /// Linear-region stiffness K [N/m]: k = K ℓ₀ per unit strain.
    pub stiffness: f64,
    /// Spread strain ε_l of the toe region (the toe ends at 2 ε_l).
    pub toe_strain: f64,
}

impl TendonSpring {
    /// The procedural knee's tendon.
    pub fn procedural_knee() -> Self {
        Self::from_dimensions(&KneeDimensions::procedural_knee())
    }

    /// The patellar tendon of the knee of `dimensions`: slack at its tendon length, with
    /// O'Brien et al.'s stiffness and Blankevoort's toe strain.
    pub fn from_dimensions(dimensions: &KneeDimensions) -> Self {
        Self {
            slack_length: dimensions.patellar_tendon_length,
            stiffness: PATELLAR_TENDON_STIFFNESS,
            toe_strain: PATELLAR_TENDON_TOE_STRAIN,
        }
    }

    /// The toe-then-linear law, with k = K ℓ₀ the force per unit strain in the linear
    /// region [N].
    pub fn law(&self) -> ToeLinearLaw {
        ToeLinearLaw {
            strain_stiffness: self.stiffness * self.slack_length,
            toe_strain: self.toe_strain,
        }
    }

    /// Strain ε = ℓ/ℓ₀ − 1 at `length` [m].
    pub fn strain(&self, length: f64) -> f64 {
        length / self.slack_length - 1.0
    }

    /// Tension f(ℓ) [N] at `length` [m].
    pub fn force(&self, length: f64) -> f64 {
        self.law().force(self.strain(length))
    }

    /// Stored energy E(ℓ) = ∫ f dℓ from ℓ₀ [J].
    pub fn energy(&self, length: f64) -> f64 {
        self.law().energy_per_slack_length(self.strain(length)) * self.slack_length
    }

    /// The length [m] at which the tendon carries `force` [N] (ℓ₀ for no tension).
    pub fn length_at_force(&self, force: f64) -> f64 {
        self.slack_length * (1.0 + self.law().strain_at_force(force))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_force_is_the_energys_slope_and_continuous_through_the_toe() {
        let tendon = TendonSpring::procedural_knee();
        let l0 = tendon.slack_length;
        let h = 1e-7 * l0;
        for strain in [-0.02, 0.01, 0.03, 0.059, 0.061, 0.1, 0.2] {
            let length = l0 * (1.0 + strain);
            let slope = (tendon.energy(length + h) - tendon.energy(length - h)) / (2.0 * h);
            let force = tendon.force(length);
            assert!(
                (slope - force).abs() <= 1e-6 * force.max(1.0),
                "ε = {strain}: dE/dℓ {slope} against f {force}"
            );
        }
        // Value and slope match where the toe meets the linear region (ε = 2 ε_l).
        let joint = l0 * (1.0 + 2.0 * tendon.toe_strain);
        // Across 2h the force rises by K 2h, no jump.
        let (below, above) = (tendon.force(joint - h), tendon.force(joint + h));
        let rise = tendon.stiffness * 2.0 * h;
        assert!(
            (above - below - rise).abs() < 1e-3 * rise,
            "{below} {above}"
        );
        let slope = |at: f64| (tendon.force(at + h) - tendon.force(at - h)) / (2.0 * h);
        let (slope_below, slope_above) = (slope(joint - 10.0 * h), slope(joint + 10.0 * h));
        assert!(
            (slope_below - slope_above).abs() < 1e-3 * tendon.stiffness,
            "{slope_below} {slope_above}"
        );
        // In the linear region the stiffness is K.
        assert!((slope(l0 * 1.2) - tendon.stiffness).abs() < 1e-6 * tendon.stiffness);
    }

    #[test]
    fn the_length_at_a_force_inverts_the_law() {
        let tendon = TendonSpring::procedural_knee();
        for force in [0.0, 1.0, 500.0, 1600.0, 5453.0, 2.0e4] {
            let length = tendon.length_at_force(force);
            assert!(
                (tendon.force(length) - force).abs() < 1e-9 * force.max(1.0),
                "{force}"
            );
        }
        assert_eq!(tendon.length_at_force(-5.0), tendon.slack_length);
        // O'Brien et al.'s maximal force: 6.6 mm of stretch (5.0 ± 0.5 mm measured).
        let stretch = tendon.length_at_force(5453.0) - tendon.slack_length;
        assert!((stretch - 6.55e-3).abs() < 0.05e-3, "{stretch}");
    }

    /// The quadriceps' tendon strands evaluate the same law: a strand with the tendon's
    /// ℓ₀, k = K ℓ₀ and ε_l pulls with the tendon's force, bit for bit.
    #[test]
    fn a_tendon_strand_of_the_same_parameters_pulls_with_the_same_force() {
        use musclefem_contact::{Strand, TendonStrands};
        use musclefem_core::solver::Interaction;
        use nalgebra::Vector3;

        let tendon = TendonSpring::procedural_knee();
        let strand = Strand {
            node_a: 0,
            node_b: 1,
            slack_length: tendon.slack_length,
            strain_stiffness: tendon.stiffness * tendon.slack_length,
            toe_strain: tendon.toe_strain,
        };
        let mut strands = TendonStrands::new("patellar tendon", vec![strand], Some(2)).unwrap();
        for strain in [-0.02, 0.0, 0.01, 0.03, 0.06, 0.061, 0.1, 0.2] {
            let length = tendon.slack_length * (1.0 + strain);
            let positions = [Vector3::zeros(), Vector3::new(0.0, 0.0, length)];
            let mut force = [Vector3::zeros(); 2];
            strands.forces(0.0, &positions, false, &mut force).unwrap();
            assert_eq!(force[1].z, tendon.force(length), "ε = {strain}");
            assert_eq!(
                strands.states()[0].energy,
                tendon.energy(length),
                "ε = {strain}"
            );
        }
    }
}
