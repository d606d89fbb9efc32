//! Parameters of the Hill-type active muscle: Table 1 of the seed paper (SI units) plus
//! the activation constants of Eqs. 12–13.

use std::collections::BTreeMap;

use super::functions::{Activation, ForceVelocity};
use crate::MaterialError;
use crate::parameters::{Bound, ParameterSet, ParameterSpec};

use Bound::{Exclusive, Inclusive, Unbounded};

/// Declared parameters, defaults from Table 1 (activation: passive unless n2 > 0).
pub const HILL_PARAMETERS: [ParameterSpec; 20] = [
    ParameterSpec::new(
        "D",
        "1/Pa",
        5.0e-9,
        Exclusive(0.0),
        Unbounded,
        "compressibility: W_V = (J - 1)^2 / D",
    ),
    ParameterSpec::new(
        "b",
        "1",
        15.0,
        Exclusive(0.0),
        Unbounded,
        "matrix exponent: W_I = c [exp(b (I1bar - 3)) - 1]",
    ),
    ParameterSpec::new(
        "c",
        "Pa",
        3.79e2,
        Inclusive(0.0),
        Unbounded,
        "matrix stress scale",
    ),
    ParameterSpec::new(
        "A",
        "1",
        4.0,
        Inclusive(0.0),
        Unbounded,
        "parallel element: sigma_PE = sigma0 A (lambda_f - 1)^2",
    ),
    ParameterSpec::new(
        "lambda_pe",
        "1",
        1.0,
        Exclusive(0.0),
        Unbounded,
        "parallel element slack stretch: sigma_PE = sigma0 A (lambda_f - lambda_pe)^2 beyond it (1 in the paper)",
    ),
    ParameterSpec::new(
        "lambda_matrix",
        "1",
        1.0,
        Inclusive(1.0),
        Unbounded,
        "matrix slack stretch along the fiber: the matrix resists a stretch along the fiber only beyond it, as the paper's matrix beyond 1 (1 in the paper)",
    ),
    ParameterSpec::new(
        "sigma0",
        "Pa",
        7.0e5,
        Inclusive(0.0),
        Unbounded,
        "maximum isometric stress",
    ),
    ParameterSpec::new(
        "alpha",
        "1",
        10.0,
        Exclusive(0.0),
        Unbounded,
        "series element exponent: sigma_SEE = beta [exp(alpha (lambda_s - 1)) - 1]",
    ),
    ParameterSpec::new(
        "beta",
        "Pa",
        1.0e3,
        Exclusive(0.0),
        Unbounded,
        "series element stress scale",
    ),
    ParameterSpec::new(
        "lambda_opt",
        "1",
        1.05,
        Exclusive(0.0),
        Unbounded,
        "optimal fiber stretch of the force-length relation",
    ),
    ParameterSpec::new(
        "k",
        "1",
        0.3,
        Exclusive(0.0),
        Unbounded,
        "CE/SEE length ratio: (1 + k) lambda_f = lambda_m + k lambda_s",
    ),
    ParameterSpec::new(
        "k_c",
        "1",
        4.0,
        Exclusive(0.0),
        Unbounded,
        "force-velocity curvature, shortening",
    ),
    ParameterSpec::new(
        "k_e",
        "1",
        5.0,
        Exclusive(0.0),
        Unbounded,
        "force-velocity curvature factor, lengthening",
    ),
    ParameterSpec::new(
        "d",
        "1",
        1.45,
        Inclusive(1.0),
        Unbounded,
        "force-velocity eccentric offset",
    ),
    ParameterSpec::new(
        "lambda_dot_min",
        "1/s",
        -17.0,
        Unbounded,
        Exclusive(0.0),
        "minimum (fastest shortening) CE stretch rate",
    ),
    ParameterSpec::new(
        "S",
        "1/s",
        50.0,
        Exclusive(0.0),
        Unbounded,
        "activation rate",
    ),
    ParameterSpec::new(
        "n1",
        "1",
        0.0,
        Inclusive(0.0),
        Inclusive(1.0),
        "activation level before t0 and after t1",
    ),
    ParameterSpec::new(
        "n2",
        "1",
        0.0,
        Inclusive(0.0),
        Inclusive(1.0),
        "activation level between t0 and t1",
    ),
    ParameterSpec::new("t0", "s", 0.0, Unbounded, Unbounded, "activation time"),
    ParameterSpec::new(
        "t1",
        "s",
        f64::INFINITY,
        Unbounded,
        Unbounded,
        "deactivation time (inf: never)",
    )
    .allowing_infinity(),
];

/// Typed Hill-model parameters (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HillParameters {
    /// Compressibility D [1/Pa].
    pub compressibility: f64,
    /// Matrix exponent b [1].
    pub matrix_exponent: f64,
    /// Matrix stress scale c [Pa].
    pub matrix_stress: f64,
    /// Parallel element factor A [1].
    pub parallel_factor: f64,
    /// Parallel element slack stretch λ_PE [1] (1 in the paper): the fiber stretch from
    /// which the PE carries stress.
    pub parallel_slack: f64,
    /// Matrix slack stretch λ_M [1] (1 in the paper): the matrix's energy counts the
    /// isochoric fiber stretch only beyond it ([`super::functions::matrix_slack`]).
    pub matrix_slack: f64,
    /// Maximum isometric stress σ₀ [Pa].
    pub max_isometric_stress: f64,
    /// SEE exponent α [1].
    pub see_exponent: f64,
    /// SEE stress scale β [Pa].
    pub see_stress: f64,
    /// Optimal fiber stretch λ_opt [1].
    pub optimal_stretch: f64,
    /// CE/SEE length ratio k [1].
    pub length_ratio: f64,
    /// Force–velocity constants.
    pub force_velocity: ForceVelocity,
    /// Activation constants.
    pub activation: Activation,
}

impl HillParameters {
    /// Build from checked values; t1 < t0 is an error.
    pub fn from_set(p: &ParameterSet) -> Result<Self, MaterialError> {
        let activation = Activation {
            n1: p.get("n1")?,
            n2: p.get("n2")?,
            t0: p.get("t0")?,
            t1: p.get("t1")?,
            rate: p.get("S")?,
        };
        if activation.t1 < activation.t0 {
            return Err(MaterialError::InconsistentParameters {
                material: p.material().to_string(),
                reason: format!(
                    "deactivation time t1 = {} s is before activation time t0 = {} s",
                    activation.t1, activation.t0
                ),
            });
        }
        Ok(HillParameters {
            compressibility: p.get("D")?,
            matrix_exponent: p.get("b")?,
            matrix_stress: p.get("c")?,
            parallel_factor: p.get("A")?,
            parallel_slack: p.get("lambda_pe")?,
            matrix_slack: p.get("lambda_matrix")?,
            max_isometric_stress: p.get("sigma0")?,
            see_exponent: p.get("alpha")?,
            see_stress: p.get("beta")?,
            optimal_stretch: p.get("lambda_opt")?,
            length_ratio: p.get("k")?,
            force_velocity: ForceVelocity {
                k_c: p.get("k_c")?,
                k_e: p.get("k_e")?,
                d: p.get("d")?,
                lambda_dot_min: p.get("lambda_dot_min")?,
            },
            activation,
        })
    }
}

impl HillParameters {
    /// The values by their declared names: the inverse of [`HillParameters::from_set`],
    /// so that typed parameters pass the same range checks as named ones.
    pub fn named(&self) -> BTreeMap<String, f64> {
        let a = &self.activation;
        let v = &self.force_velocity;
        [
            ("D", self.compressibility),
            ("b", self.matrix_exponent),
            ("c", self.matrix_stress),
            ("A", self.parallel_factor),
            ("lambda_pe", self.parallel_slack),
            ("lambda_matrix", self.matrix_slack),
            ("sigma0", self.max_isometric_stress),
            ("alpha", self.see_exponent),
            ("beta", self.see_stress),
            ("lambda_opt", self.optimal_stretch),
            ("k", self.length_ratio),
            ("k_c", v.k_c),
            ("k_e", v.k_e),
            ("d", v.d),
            ("lambda_dot_min", v.lambda_dot_min),
            ("S", a.rate),
            ("n1", a.n1),
            ("n2", a.n2),
            ("t0", a.t0),
            ("t1", a.t1),
        ]
        .into_iter()
        .map(|(name, value)| (name.to_string(), value))
        .collect()
    }

    /// The values checked as the registry checks named ones (declared ranges, t1 ≥ t0).
    pub fn checked(&self) -> Result<Self, MaterialError> {
        let set = ParameterSet::resolve("hill", &HILL_PARAMETERS, &self.named())?;
        Self::from_set(&set)
    }
}

impl Default for HillParameters {
    /// Table 1 with no activation.
    fn default() -> Self {
        let set = ParameterSet::resolve("hill", &HILL_PARAMETERS, &Default::default())
            .expect("the declared defaults are within their ranges");
        HillParameters::from_set(&set).expect("the declared defaults are consistent")
    }
}
