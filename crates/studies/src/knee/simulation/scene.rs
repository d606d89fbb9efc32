//! A squat as a scene (issue 30, step 4): `musclefem knee` writes `scene.toml` and the
//! files it names into each squat's directory, so that `musclefem run DIR/scene.toml`
//! runs the same squat. The pieces are those of the `scene_*` modules: the muscles'
//! mesh, fibers and the patella's table ([`super::scene_files`]), one Hill material per
//! muscle and the tendon ([`super::scene_materials`]), a part per block of `muscles.inp`
//! sharing its nodes, the bone ties ([`super::scene_ties`]), the bones
//! ([`super::scene_bones`]), the interfaces and contacts that the squat's model has
//! ([`super::scene_interactions`]) and the step ([`super::scene_step`]); `[output]` asks
//! for the frames of the squat and the 95th percentile of every part's von Mises stress
//! in `history.csv` (the muscles' vm95).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use musclefem_core::mesh::Mesh;
use musclefem_io::csv::format_number;
use musclefem_io::strand_csv::{StrandRow, format_strands_csv};

use super::interactions::{InterfaceLaw, KneeInteractions, STRANDS_NAME};
use super::model::{
    Activation, FiberReference, KneeGeometry, MUSCLE_DENSITY, TENDON_DENSITY, block_element,
};
use super::run::SquatSettings;
use super::scene_bones::{FEMUR_BODY, bone_files, knee_bone_entries};
use super::scene_files::{FIBERS_CSV, MUSCLES_INP, model_files};
use super::scene_interactions::knee_interaction_entries;
use super::scene_materials::knee_material_entries;
use super::scene_step::squat_step_entry;
use super::scene_ties::knee_tie_entries;
use crate::knee::anatomy::Tissue;

/// The percentile P of the von Mises stress in the scene's `history.csv`
/// (`von_mises_p95_<part>_pa`): the paper's peak stress of a muscle, vm95.
pub const SCENE_VON_MISES_PERCENTILE: f64 = 95.0;

/// The strands' file.
pub const STRANDS_CSV: &str = "strands.csv";

/// `strands.csv` of `geometry`'s tendon strands, their nodes labelled as `muscles.inp`
/// labels them (node n is label n + 1).
pub fn strands_csv(geometry: &KneeGeometry) -> String {
    let rows: Vec<StrandRow> = (geometry.strands.iter())
        .map(|s| StrandRow {
            node_a: i64::from(s.node) + 1,
            node_b: i64::from(s.attachment) + 1,
            slack_length: s.slack_length,
            strain_stiffness: s.strain_stiffness,
            toe_strain: s.toe_strain,
        })
        .collect();
    format_strands_csv(&rows)
}

/// One squat as a scene: what [`SquatScene::text`] and [`SquatScene::write_files`] write.
pub struct SquatScene<'a> {
    pub geometry: &'a KneeGeometry,
    /// The muscles' mesh with fibers (the squat's model's).
    pub mesh: &'a Mesh,
    pub activation: Activation,
    pub settings: &'a SquatSettings,
    /// The `[[interactions]]` entries: those the squat's model has (see [`Self::new`]),
    /// or none.
    pub interactions: String,
}

impl<'a> SquatScene<'a> {
    /// The scene of the squat of `activation` with `settings` on `geometry`, whose model
    /// has the muscles' mesh `mesh` and the interactions `built` (bonded by
    /// `settings.interfaces`).
    pub fn new(
        geometry: &'a KneeGeometry,
        mesh: &'a Mesh,
        built: &KneeInteractions,
        activation: Activation,
        settings: &'a SquatSettings,
    ) -> Result<Self> {
        let law: InterfaceLaw = settings.interfaces;
        Ok(SquatScene {
            geometry,
            mesh,
            activation,
            settings,
            interactions: knee_interaction_entries(geometry, built, law)?,
        })
    }

    /// The files the scene names, (file name, text) each: `muscles.inp`, `fibers.csv`,
    /// `patella_table.csv`, `femur.obj`, `tibia.obj` and `patella.obj`, and
    /// `strands.csv` when the knee has tendon strands.
    pub fn files(&self) -> Vec<(&'static str, String)> {
        let mut files = model_files(self.mesh, &self.geometry.patella_table);
        files.extend(bone_files(self.geometry));
        if !self.geometry.strands.is_empty() {
            files.push((STRANDS_CSV, strands_csv(self.geometry)));
        }
        files
    }

    /// Write the [`Self::files`] into `directory` (atomically, each).
    pub fn write_files(&self, directory: &Path) -> Result<()> {
        for (name, text) in self.files() {
            let path = directory.join(name);
            musclefem_io::atomic::write_atomically(&path, text.as_bytes())
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Ok(())
    }

    /// `scene.toml`, with frames every `frame_interval` [s] (none for 0).
    pub fn text(&self, frame_interval: f64) -> Result<String> {
        let (geometry, settings) = (self.geometry, self.settings);
        let description = format!(
            "musclefem knee: the {} squat 0° → {}° → 0° in {} s",
            self.activation.name(),
            format_number(settings.squat.peak_flexion.to_degrees()),
            format_number(settings.squat.duration)
        );
        let muscles: Vec<(&str, FiberReference)> = (0..geometry.muscles.len())
            .map(|m| (geometry.block_name(m), geometry.fiber_reference[m]))
            .collect();
        let mut text = format!(
            "# {description}\n# Written by `musclefem knee`; `musclefem run` reruns it.\n\
             schema_version = 1\ndescription = {description:?}\n\n{}\n",
            knee_material_entries(&muscles, self.activation, &settings.squat)
        );
        for (b, role) in geometry.roles.iter().enumerate() {
            let muscle = (geometry.muscles.iter())
                .position(|&m| m == role.muscle)
                .with_context(|| format!("block {b}'s muscle is not one of the squat's"))?;
            let (material, density) = match role.tissue {
                Tissue::Muscle => (
                    format!("{}_muscle", geometry.block_name(muscle)),
                    MUSCLE_DENSITY,
                ),
                Tissue::Tendon => ("tendon".to_string(), TENDON_DENSITY),
            };
            let _ = writeln!(
                text,
                "[[parts]]\nname = {name:?}\nmaterial = {material:?}\nelement = {element:?}\n\
                 density = {}\nmesh = {{ file = {MUSCLES_INP:?}, block = {name:?}, \
                 shared_nodes = true }}\nfibers = {{ file = {FIBERS_CSV:?} }}\n",
                format_number(density),
                name = geometry.block_name(b),
                element = block_element(settings.element, geometry.mesh.blocks[b].shape)?.name(),
            );
        }
        text.push_str(&knee_tie_entries(geometry)?);
        text.push_str(&knee_bone_entries(geometry));
        text.push_str(&self.interactions);
        if !geometry.strands.is_empty() {
            // The strands' nodes are labelled by `muscles.inp`, which every part shares.
            let _ = writeln!(
                text,
                "[[strands]]\nname = {STRANDS_NAME:?}\npart = {:?}\nfile = {STRANDS_CSV:?}\n",
                geometry.block_name(0)
            );
        }
        text.push_str(&squat_step_entry(settings, FEMUR_BODY));
        let _ = write!(
            text,
            "\n[output]\nvon_mises_percentile = {}\nframes = {}\n",
            format_number(SCENE_VON_MISES_PERCENTILE),
            frame_interval > 0.0
        );
        if frame_interval > 0.0 {
            let _ = writeln!(text, "frame_interval = {}", format_number(frame_interval));
        }
        Ok(text)
    }
}
