//! Whether a study's muscles are activated: the one passive/active choice of the knee
//! squat, the elongation tests, sweeps and fits. Each study says when and how much (the
//! knee: 50 % from 35° of flexion; the elongation: full activation during a 0.5 s hold);
//! the Hill material receives it as its typed activation parameters.

/// Passive or active muscle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, clap::ValueEnum)]
pub enum Activation {
    /// No activation: the Hill model's matrix and parallel element only.
    Passive,
    /// Activated as the study prescribes.
    Active,
}

impl Activation {
    /// `passive` or `active`: as on the command line, in directory names and in the CSVs'
    /// `activation` column.
    pub fn name(self) -> &'static str {
        match self {
            Activation::Passive => "passive",
            Activation::Active => "active",
        }
    }
}
