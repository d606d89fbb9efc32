//! Running a scene's [`Model`]: from the start or from a checkpoint, its fingerprint
//! (what a checkpoint or a sweep row was made from) and its history's columns.

use super::Analysis;
use super::build::Model;
use crate::output::stress_percentile::VonMisesPercentile;
use crate::output::{HistoryColumns, RigidBodyFrame};

impl Model {
    /// The rigid bodies as the frames show them (`rigid.pvd`, see
    /// [`crate::output::rigid_frames`]).
    pub fn rigid_body_frames(&self) -> Vec<RigidBodyFrame<'_>> {
        self.rigid_bodies
            .iter()
            .map(|body| RigidBodyFrame {
                name: &body.name,
                vertices: &body.vertices,
                triangles: &body.triangles,
                motion: body.motion.clone(),
            })
            .collect()
    }

    /// Run the model under its own analysis, showing `observer` every recorded instant.
    pub fn run(
        &self,
        observer: &mut dyn musclefem_core::solver::Observer,
    ) -> Result<musclefem_core::solver::Outcome, musclefem_core::solver::SolverError> {
        self.run_with(&self.analysis, observer)
    }

    /// Run the model under `analysis` (another solver or step setting than its own).
    pub fn run_with(
        &self,
        analysis: &Analysis,
        observer: &mut dyn musclefem_core::solver::Observer,
    ) -> Result<musclefem_core::solver::Outcome, musclefem_core::solver::SolverError> {
        self.solve(analysis, None, observer)
    }

    /// Go on with the model under `analysis` from `checkpoint` (taken by a run of the
    /// same model and analysis; see `musclefem_core::solver::resume`).
    pub fn resume_with(
        &self,
        analysis: &Analysis,
        checkpoint: &musclefem_core::solver::Checkpoint,
        observer: &mut dyn musclefem_core::solver::Observer,
    ) -> Result<musclefem_core::solver::Outcome, musclefem_core::solver::SolverError> {
        self.solve(analysis, Some(checkpoint), observer)
    }

    /// The problem (with fresh interactions) run from the start or from `checkpoint`.
    fn solve(
        &self,
        analysis: &Analysis,
        checkpoint: Option<&musclefem_core::solver::Checkpoint>,
        observer: &mut dyn musclefem_core::solver::Observer,
    ) -> Result<musclefem_core::solver::Outcome, musclefem_core::solver::SolverError> {
        let mut interactions: Vec<_> = self.interactions.iter().map(|i| i.boxed()).collect();
        let problem = musclefem_core::solver::Problem {
            mesh: &self.mesh,
            parts: &self.parts,
            loads: &self.loads,
            interactions: &mut interactions,
        };
        match checkpoint {
            Some(checkpoint) => {
                musclefem_core::solver::resume(problem, analysis, checkpoint, observer)
            }
            None => musclefem_core::solver::run(problem, analysis, observer),
        }
    }

    /// A fingerprint of what the model computes ([`crate::fingerprint::model_fingerprint`]
    /// of the scene text, the analysis as it will run, and the mesh):
    /// a checkpoint resumes only the model whose fingerprint it carries.
    /// The recorded activations enter by their samples (their files are not in the text).
    pub fn fingerprint(&self, scene_text: &str, analysis: &Analysis) -> u64 {
        let mut settings = format!("{scene_text}{analysis:?}");
        for history in self.activation_histories.iter().flatten() {
            let bytes: Vec<u8> = history
                .samples()
                .iter()
                .flat_map(|(t, a)| t.to_le_bytes().into_iter().chain(a.to_le_bytes()))
                .collect();
            settings += &format!("{}{:x}", history.source, crate::fingerprint::fnv1a(&bytes));
        }
        crate::fingerprint::model_fingerprint(&settings, &self.mesh)
    }

    /// The names of the columns of this model's `history.csv`: a reaction per prescribed
    /// displacement, the rigid ties' forces and moments, the interactions, and each
    /// part's von Mises percentile when the scene asks for it.
    pub fn history_columns(&self) -> HistoryColumns {
        let mut columns = HistoryColumns::new(
            self.displacement_names.clone(),
            self.loads
                .rigid_ties
                .iter()
                .map(|t| t.name.clone())
                .collect(),
        )
        .with_interactions(
            self.interactions
                .iter()
                .map(|i| i.name().to_string())
                .collect(),
        );
        columns.von_mises_percentile =
            self.von_mises_percentile.map(|percent| VonMisesPercentile {
                percent,
                parts: self
                    .part_names
                    .iter()
                    .zip(&self.parts)
                    .map(|(name, part)| (name.clone(), part.block))
                    .collect(),
            });
        columns
    }
}
