//! Tendon strands: tension-only nonlinear springs between pairs of nodes, the 1-D model
//! of aponeuroses and tendons that knee models use for ligaments (Blankevoort & Huiskes
//! 1991, J Biomech Eng 113:263).
//!
//! A strand joins node a (a muscle's end) to node b (e.g. a node carried with the
//! patella by a rigid tie). At the current length ℓ = |x_b − x_a| it pulls with the
//! tension f(ℓ) of the toe-then-linear law ([`ToeLinearLaw`], ε = ℓ/ℓ₀ − 1) along
//! e = (x_b − x_a)/ℓ: a is pulled by +f e, b by −f e, so the interaction force
//! (`musclefem_core::solver::interaction`'s sign, like an internal force) is
//! f_c,a = −f e, f_c,b = +f e. Its consistent tangent, with
//! K = (df/dℓ) e⊗e + (f/ℓ)(I − e⊗e) [N/m]:
//!
//! ```text
//! ∂f_c,a/∂x_a = K,  ∂f_c,a/∂x_b = −K,  ∂f_c,b/∂x_a = −K,  ∂f_c,b/∂x_b = K
//! ```
//!
//! symmetric, zero while the strand is slack (ℓ ≤ ℓ₀). Strands keep no history.
//!
//! - [`law`]: the force law, shared with the knee's patellar tendon;
//! - `interaction.rs`: [`TendonStrands`] as a `musclefem_core::solver::Interaction`;
//! - `error.rs`: [`StrandError`], naming the strand.

mod error;
mod interaction;
pub mod law;
#[cfg(test)]
mod tests;

use nalgebra::{Matrix3, Vector3};

pub use error::StrandError;
pub use law::ToeLinearLaw;

/// One strand: its end nodes and its law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strand {
    /// Node a (the side whose resultant the report gives, e.g. a muscle's end).
    pub node_a: u32,
    /// Node b (e.g. a node carried with the patella).
    pub node_b: u32,
    /// Slack length ℓ₀ [m]: no tension at or below it.
    pub slack_length: f64,
    /// k = E A: tension per unit strain in the linear region [N].
    pub strain_stiffness: f64,
    /// Spread strain ε_l of the toe region (the toe ends at 2 ε_l).
    pub toe_strain: f64,
}

impl Strand {
    /// The strand's force law.
    pub fn law(&self) -> ToeLinearLaw {
        ToeLinearLaw {
            strain_stiffness: self.strain_stiffness,
            toe_strain: self.toe_strain,
        }
    }

    /// Its state when node b lies at `separation` = x_b − x_a [m] from node a.
    pub fn state(&self, separation: Vector3<f64>) -> StrandState {
        let length = separation.norm();
        let strain = length / self.slack_length - 1.0;
        let law = self.law();
        let tension = law.force(strain);
        StrandState {
            separation,
            length,
            tension,
            slope: law.slope(strain) / self.slack_length,
            energy: law.energy_per_slack_length(strain) * self.slack_length,
        }
    }
}

/// A strand at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StrandState {
    /// x_b − x_a [m].
    pub separation: Vector3<f64>,
    /// Length ℓ [m].
    pub length: f64,
    /// Tension f(ℓ) [N].
    pub tension: f64,
    /// df/dℓ [N/m].
    pub slope: f64,
    /// Stored energy ℓ₀ ∫₀^ε f dε [J].
    pub energy: f64,
}

impl StrandState {
    /// Whether the strand carries tension.
    pub fn is_taut(&self) -> bool {
        self.tension > 0.0
    }

    /// The force f e the strand puts on node a [N] (node b takes the opposite).
    pub fn pull_on_a(&self) -> Vector3<f64> {
        if self.is_taut() {
            self.separation * (self.tension / self.length)
        } else {
            Vector3::zeros()
        }
    }

    /// K = (df/dℓ) e⊗e + (f/ℓ)(I − e⊗e) [N/m] (zero while slack): the derivative of the
    /// pull on a, f e, with respect to x_b.
    pub fn stiffness(&self) -> Matrix3<f64> {
        if !self.is_taut() {
            return Matrix3::zeros();
        }
        let e = self.separation / self.length;
        let axial = e * e.transpose();
        axial * self.slope + (Matrix3::identity() - axial) * (self.tension / self.length)
    }
}

/// Tendon strands as one interaction (see the module documentation).
#[derive(Clone, Debug)]
pub struct TendonStrands {
    name: String,
    strands: Vec<Strand>,
    /// The strands at the last [`musclefem_core::solver::Interaction::forces`] call.
    states: Vec<StrandState>,
}

impl TendonStrands {
    /// The interaction `name` of `strands`, each checked: ℓ₀ > 0, k > 0, ε_l ≥ 0 (all
    /// finite), a ≠ b, and, given the mesh's `node_count`, both nodes in it. Every strand
    /// starts slack.
    pub fn new(
        name: &str,
        strands: Vec<Strand>,
        node_count: Option<usize>,
    ) -> Result<Self, StrandError> {
        let interaction = || name.to_string();
        if strands.is_empty() {
            return Err(StrandError::Empty {
                interaction: interaction(),
            });
        }
        for (strand, s) in strands.iter().enumerate() {
            if !(s.slack_length > 0.0 && s.slack_length.is_finite()) {
                return Err(StrandError::SlackLength {
                    interaction: interaction(),
                    strand,
                    value: s.slack_length,
                });
            }
            if !(s.strain_stiffness > 0.0 && s.strain_stiffness.is_finite()) {
                return Err(StrandError::StrainStiffness {
                    interaction: interaction(),
                    strand,
                    value: s.strain_stiffness,
                });
            }
            if !(s.toe_strain >= 0.0 && s.toe_strain.is_finite()) {
                return Err(StrandError::ToeStrain {
                    interaction: interaction(),
                    strand,
                    value: s.toe_strain,
                });
            }
            if s.node_a == s.node_b {
                return Err(StrandError::SameNode {
                    interaction: interaction(),
                    strand,
                    node: s.node_a,
                });
            }
            if let Some(node_count) = node_count
                && let Some(&node) = [s.node_a, s.node_b]
                    .iter()
                    .find(|&&n| n as usize >= node_count)
            {
                return Err(StrandError::NodeOutOfRange {
                    interaction: interaction(),
                    strand,
                    node,
                    node_count,
                });
            }
        }
        let states = vec![StrandState::default(); strands.len()];
        Ok(Self {
            name: name.to_string(),
            strands,
            states,
        })
    }

    /// The strands, in the order given.
    pub fn strands(&self) -> &[Strand] {
        &self.strands
    }

    /// Each strand at the last evaluation, in the order of [`Self::strands`].
    pub fn states(&self) -> &[StrandState] {
        &self.states
    }

    /// Σ f over the strands at the last evaluation [N].
    pub fn total_tension(&self) -> f64 {
        self.states.iter().map(|s| s.tension).sum()
    }

    /// Strands carrying tension at the last evaluation.
    pub fn taut_count(&self) -> usize {
        self.states.iter().filter(|s| s.is_taut()).count()
    }

    /// Evaluates every strand at nodal `positions` [m].
    fn evaluate(&mut self, positions: &[Vector3<f64>]) {
        for (state, strand) in self.states.iter_mut().zip(&self.strands) {
            let separation = positions[strand.node_b as usize] - positions[strand.node_a as usize];
            *state = strand.state(separation);
        }
    }
}
