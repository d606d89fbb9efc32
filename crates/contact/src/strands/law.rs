//! The toe-then-linear force law of ligaments and tendons (Blankevoort & Huiskes 1991,
//! J Biomech Eng 113:263), in terms of the strain ε = ℓ/ℓ₀ − 1:
//!
//! ```text
//! f(ε) = 0                      ε ≤ 0          (slack)
//!      = k ε² / (4 ε_l)         0 < ε ≤ 2 ε_l  (toe: the crimped fibres straighten)
//!      = k (ε − ε_l)            ε > 2 ε_l      (linear)
//! ```
//!
//! with k = E A [N] the force per unit strain of the linear region and ε_l the spread
//! strain of the toe. f and df/dε = k ε/(2 ε_l) (toe), k (linear) are continuous at
//! 2 ε_l. With ε_l = 0 the law is linear from slack on.
//!
//! The knee's patellar tendon (`musclefem-studies`, `TendonSpring`) and the tendon
//! strands ([`super::TendonStrands`]) both evaluate it here.

/// The toe-then-linear law f(ε) (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToeLinearLaw {
    /// k = E A: force per unit strain in the linear region [N].
    pub strain_stiffness: f64,
    /// Spread strain ε_l of the toe region (the toe ends at 2 ε_l) [-].
    pub toe_strain: f64,
}

impl ToeLinearLaw {
    /// Tension f(ε) [N] at `strain` ε.
    pub fn force(&self, strain: f64) -> f64 {
        let (k, toe) = (self.strain_stiffness, self.toe_strain);
        if strain <= 0.0 {
            0.0
        } else if strain <= 2.0 * toe {
            k * strain * strain / (4.0 * toe)
        } else {
            k * (strain - toe)
        }
    }

    /// Slope df/dε [N] at `strain` ε: 0 slack, k ε/(2 ε_l) in the toe, k beyond.
    pub fn slope(&self, strain: f64) -> f64 {
        let (k, toe) = (self.strain_stiffness, self.toe_strain);
        if strain <= 0.0 {
            0.0
        } else if strain <= 2.0 * toe {
            k * strain / (2.0 * toe)
        } else {
            k
        }
    }

    /// ∫₀^ε f dε' [N] at `strain` ε: the stored energy is ℓ₀ times this [J].
    pub fn energy_per_slack_length(&self, strain: f64) -> f64 {
        let (k, toe) = (self.strain_stiffness, self.toe_strain);
        if strain <= 0.0 {
            0.0
        } else if strain <= 2.0 * toe {
            k * strain.powi(3) / (12.0 * toe)
        } else {
            // Toe energy k (2ε_l)³/(12 ε_l) = 2 k ε_l²/3, then the linear part.
            2.0 * k * toe * toe / 3.0 + 0.5 * k * ((strain - toe).powi(2) - toe * toe)
        }
    }

    /// The strain at which the law carries `force` [N] (0 for no tension).
    pub fn strain_at_force(&self, force: f64) -> f64 {
        let (k, toe) = (self.strain_stiffness, self.toe_strain);
        if force <= 0.0 {
            0.0
        } else if force <= k * toe {
            (4.0 * toe * force / k).sqrt()
        } else {
            force / k + toe
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: ToeLinearLaw = ToeLinearLaw {
        strain_stiffness: 250.0,
        toe_strain: 0.03,
    };

    #[test]
    fn the_slope_and_the_energy_are_the_forces_derivative_and_integral() {
        let h = 1e-7;
        for strain in [-0.02, 1e-3, 0.01, 0.03, 0.059, 0.061, 0.1, 0.2] {
            let force = LAW.force(strain);
            let force_slope = (LAW.force(strain + h) - LAW.force(strain - h)) / (2.0 * h);
            let slope = LAW.slope(strain);
            assert!(
                (force_slope - slope).abs() <= 1e-6 * slope.max(1.0),
                "ε = {strain}: df/dε {force_slope} against {slope}"
            );
            let energy_slope = (LAW.energy_per_slack_length(strain + h)
                - LAW.energy_per_slack_length(strain - h))
                / (2.0 * h);
            assert!(
                (energy_slope - force).abs() <= 1e-6 * force.max(1.0),
                "ε = {strain}: dE/dε {energy_slope} against f {force}"
            );
        }
        // Where the toe meets the linear region, f = k ε_l and df/dε = k from both sides.
        let joint = 2.0 * LAW.toe_strain;
        let k = LAW.strain_stiffness;
        assert!((LAW.force(joint) - k * LAW.toe_strain).abs() < 1e-12 * k);
        assert_eq!(LAW.slope(joint), k);
        assert_eq!(LAW.slope(joint + 1e-12), k);
    }

    #[test]
    fn the_strain_at_a_force_inverts_the_law_and_a_zero_toe_is_linear() {
        for force in [0.0, 1e-3, 3.0, 7.5, 7.6, 40.0] {
            let strain = LAW.strain_at_force(force);
            assert!((LAW.force(strain) - force).abs() < 1e-12 * force.max(1.0));
        }
        assert_eq!(LAW.strain_at_force(-1.0), 0.0);
        let linear = ToeLinearLaw {
            toe_strain: 0.0,
            ..LAW
        };
        assert_eq!(linear.force(0.1), 25.0);
        assert_eq!(linear.slope(0.1), 250.0);
        assert_eq!(linear.force(-0.1), 0.0);
        assert_eq!(linear.slope(0.0), 0.0);
        assert_eq!(linear.strain_at_force(25.0), 0.1);
        assert!((linear.energy_per_slack_length(0.1) - 1.25).abs() < 1e-15);
    }
}
