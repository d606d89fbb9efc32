//! The solver choice of every study and command: one enum, named on the command line.

/// Which solver runs a study or a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Solver {
    /// Central differences with lumped mass (the paper's method), mass-scaled where the
    /// study or scene says so.
    Explicit,
    /// Newton on the consistent tangent with automatic step cutting, quasi-static or
    /// with Newmark inertia (the motions here are slow).
    Implicit,
}
