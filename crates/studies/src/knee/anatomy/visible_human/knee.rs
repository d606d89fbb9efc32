//! The Visible Human knee placed in the knee frame ([`super::landmarks`]): the four
//! quadriceps' tet10 meshes as one mesh, the bones, and the tendinous tissue that joins
//! the muscles to the patella.
//!
//! **Tendinous tissue as strands.** The segmentation has no tendons, and between the
//! muscles' ends and the patella it leaves no room for a solid quadriceps tendon that
//! would not cut into a neighbour: the vasti lateralis and intermedius end beside the
//! lateral condyle, 35–40 mm behind the patella's base, the rectus 80 mm above it (data
//! README). The aponeuroses and the quadriceps tendon are therefore a fan of 1-D tendon
//! strands (toe-then-linear springs, as knee models represent ligaments: Blankevoort &
//! Huiskes 1991, J Biomech Eng 113:263): one from every mid-edge node of a muscle's
//! fiber outlets (its `aponeurosis` and `insertion` faces, where the fibers' flow ends)
//! to that muscle's attachment on the patella, an extra node the patella carries. Each
//! strand is slack at its length in the data's pose (extension) and takes the share of
//! the muscle's strain stiffness that its node's tributary area takes of the outlets' area
//! (a tet10 face hands a uniform traction to its mid-edge nodes only, a third of its area
//! each). The strands do not touch anything on their way; the muscles they pull do.
//!
//! **Stiffness.** The four muscles' strands together have the strain stiffness of the
//! patellar tendon, K ℓ₀ = 1076 N/mm × ℓ₀ (O'Brien et al. 2010, J Biomech 43:1190; see
//! [`super::super::tendon`]), shared among the muscles by volume (their force capacity):
//! the quadriceps tendon carries about the patellar tendon's force (0.5–1.1 times it,
//! Huberti et al. 1984), so the two strain about alike.
//!
//! **Attachments** on the patella's base, at the corners of its superior border: the
//! patella's vertex farthest along proximal + anterior for the rectus femoris (the
//! superficial layer of the quadriceps tendon), proximal + posterior for the vastus
//! intermedius (the deep layer), proximal + lateral for the vastus lateralis and
//! proximal + medial for the vastus medialis (each direction at 45° between the two).
//!
//! **The rectus femoris's origin** is a pin at the anterior inferior iliac spine, joined
//! to the muscle by strands too. Its segmented origin band is 58 mm tall (y 329–387 mm in
//! the knee frame); held by the pelvis without turning, the whole band could not turn
//! with the thigh, and the first passive squat (explicit, 2026-11-27) bent the muscle
//! below it to a von Mises stress of 2.4 MPa (median, 20–40 mm below the band's centre)
//! at 71° of flexion. The pin is one node [`ORIGIN_PIN_OFFSET`] beyond the band's
//! proximal end, along the muscle's axis (from its outlets' centroid to the band's); a
//! strand runs to it from every mid-edge node of the origin faces, slack at its length
//! in the data's pose, the strands together as stiff as the muscle's distal ones. The
//! node set `rectus_femoris_origin` is the pin (the pelvis carries it without turning);
//! `rectus_femoris_belly_start` stays the band (the fiber flow's inlet).

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};
use nalgebra::{Isometry3, Vector3};

use musclefem_core::mesh::{ElementRef, Face, Mesh};

use super::super::tendon::{PATELLAR_TENDON_STIFFNESS, PATELLAR_TENDON_TOE_STRAIN};
use super::super::{BlockRole, Quadriceps, Tissue, TriangleSurface};
use super::landmarks::Landmarks;
use super::{FIBER_INLETS, FIBER_OUTLETS, MeshResolution, load_muscle, load_surface};

/// Which end of a muscle a strand joins to a bone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MuscleEnd {
    /// The origin (the rectus femoris's pin at the anterior inferior iliac spine).
    Origin,
    /// The insertion on the patella.
    Insertion,
}

/// How far beyond the proximal end of the rectus femoris's origin band its pin lies,
/// along the muscle's axis [m]: the length of its shortest origin strand, about that of
/// its direct head's tendon.
pub const ORIGIN_PIN_OFFSET: f64 = 0.02;

/// One tendon strand: from a node of a muscle's fiber outlets to the muscle's attachment
/// node on the patella, or from a node of its origin faces to its pin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TendonStrand {
    pub muscle: Quadriceps,
    /// The end of the muscle it joins.
    pub end: MuscleEnd,
    /// The node on the muscle's outlet (or origin) faces.
    pub node: u32,
    /// The attachment node (carried by the patella, or the pelvis for an origin).
    pub attachment: u32,
    /// Length at which the strand is slack [m]: its length in the data's pose.
    pub slack_length: f64,
    /// Force per unit strain in the linear region, E A [N].
    pub strain_stiffness: f64,
    /// Spread strain of the toe region.
    pub toe_strain: f64,
}

/// The Visible Human knee in the knee frame, at 0° of flexion (the data's pose).
#[derive(Clone, Debug)]
pub struct VisibleHumanKnee {
    pub landmarks: Landmarks,
    /// The map from the data's frame to the knee frame [m].
    pub frame: Isometry3<f64>,
    /// One tet10 block per muscle (named [`Quadriceps::name`], in [`Quadriceps::ALL`]
    /// order), then one node per muscle at its patellar attachment (in no element). Every
    /// surface of muscle `m`'s mesh is `<m>_<surface>`; node sets `<m>_origin` and
    /// `<m>_belly_start` (its origin faces' nodes: the fiber flow's inlet), `<m>_belly_end`
    /// (its aponeurosis and insertion faces' nodes: the outlets), `<m>_insertion` (its
    /// attachment node); element set `<m>`.
    pub mesh: Mesh,
    pub roles: Vec<BlockRole>,
    pub muscles: Vec<Quadriceps>,
    /// The femoral shaft and the distal femoral cartilage, as one surface.
    pub femur: TriangleSurface,
    pub tibia: TriangleSurface,
    pub patella: TriangleSurface,
    /// Every muscle's strands, muscle by muscle.
    pub strands: Vec<TendonStrand>,
}

impl VisibleHumanKnee {
    /// The knee at `resolution`, from the committed meshes, surfaces and landmarks.
    pub fn load(resolution: MeshResolution) -> Result<VisibleHumanKnee> {
        let landmarks = Landmarks::load()?;
        let frame = landmarks.knee_frame();
        let surface =
            |name: &str| -> Result<TriangleSurface> { Ok(load_surface(name)?.transformed(&frame)) };
        let mut femur = surface("femur_shaft")?;
        let cartilage = surface("femur_cartilage_distal")?;
        let offset = femur.vertices.len() as u32;
        femur.vertices.extend(cartilage.vertices);
        femur
            .triangles
            .extend(cartilage.triangles.iter().map(|t| t.map(|v| v + offset)));
        let patella = surface("patella")?;
        let muscles = Quadriceps::ALL.to_vec();
        let mut meshes = Vec::new();
        for &muscle in &muscles {
            let mut mesh = load_muscle(muscle, resolution)?;
            for i in 0..mesh.nodes.len() {
                let moved = frame.transform_point(&mesh.nodes.position(i).into()).coords;
                mesh.nodes.set_position(i, moved);
            }
            meshes.push(mesh);
        }
        let (mut mesh, roles) = combine(&muscles, &meshes)?;
        let mut strands = Vec::new();
        let total_volume: f64 = meshes
            .iter()
            .map(|m| m.total_volume())
            .sum::<Result<f64, _>>()?;
        let stiffness = PATELLAR_TENDON_STIFFNESS * patellar_tendon_length(&landmarks);
        for (b, (&muscle, own)) in muscles.iter().zip(&meshes).enumerate() {
            let point = attachment(muscle, &patella)?;
            let attachment = mesh.nodes.push(point);
            mesh.node_sets
                .insert(format!("{}_insertion", muscle.name()), vec![attachment]);
            let share = own.total_volume()? / total_volume;
            let end = MuscleEnd::Insertion;
            let outlets =
                muscle_strands(&mesh, b as u32, muscle, end, attachment, share * stiffness)?;
            strands.extend(outlets);
            if muscle == Quadriceps::RectusFemoris {
                let pin = mesh.nodes.push(origin_pin(&mesh, muscle, &strands)?);
                mesh.node_sets
                    .insert(format!("{}_origin", muscle.name()), vec![pin]);
                let end = MuscleEnd::Origin;
                strands.extend(muscle_strands(
                    &mesh,
                    b as u32,
                    muscle,
                    end,
                    pin,
                    share * stiffness,
                )?);
            }
        }
        Ok(VisibleHumanKnee {
            tibia: surface("tibia")?,
            landmarks,
            frame,
            mesh,
            roles,
            muscles,
            femur,
            patella,
            strands,
        })
    }
}

impl VisibleHumanKnee {
    /// Where `muscle`'s strands start on average, weighted by their stiffness (the
    /// outlets' tributary areas) [m]: the point the muscle's pull on the patella comes
    /// from, the release point of its line of action in the knee's mechanism.
    pub fn outlet_centroid(&self, muscle: Quadriceps) -> Vector3<f64> {
        outlet_centroid(&self.mesh, &self.strands, muscle)
    }

    /// The attachment of `muscle`'s strands on the patella [m] (knee frame, at 0°).
    pub fn attachment_point(&self, muscle: Quadriceps) -> Result<Vector3<f64>> {
        let set = format!("{}_insertion", muscle.name());
        let node = self.mesh.node_set(&set)?[0];
        Ok(self.mesh.nodes.position(node as usize))
    }
}

/// Where `muscle`'s insertion strands among `strands` start on average, weighted by
/// their stiffness [m] (nodes of `mesh`).
fn outlet_centroid(mesh: &Mesh, strands: &[TendonStrand], muscle: Quadriceps) -> Vector3<f64> {
    let (sum, weight) = (strands.iter())
        .filter(|s| s.muscle == muscle && s.end == MuscleEnd::Insertion)
        .fold((Vector3::zeros(), 0.0), |(sum, weight), s| {
            let x = mesh.nodes.position(s.node as usize);
            (sum + s.strain_stiffness * x, weight + s.strain_stiffness)
        });
    sum / weight
}

/// The pin of `muscle`'s origin (module documentation): [`ORIGIN_PIN_OFFSET`] beyond the
/// proximal end of its origin nodes (`<m>_origin` in `mesh`), along the axis from its
/// outlets' centroid (its insertion strands among `strands`) to their centroid [m].
fn origin_pin(mesh: &Mesh, muscle: Quadriceps, strands: &[TendonStrand]) -> Result<Vector3<f64>> {
    let band = mesh.node_set(&format!("{}_origin", muscle.name()))?;
    let points: Vec<Vector3<f64>> = band
        .iter()
        .map(|&n| mesh.nodes.position(n as usize))
        .collect();
    let centre = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    let axis = (centre - outlet_centroid(mesh, strands, muscle))
        .try_normalize(1e-9)
        .context("the muscle's origin and outlets coincide")?;
    let reach = points
        .iter()
        .map(|x| (x - centre).dot(&axis))
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(centre + (reach + ORIGIN_PIN_OFFSET) * axis)
}

/// Length of the patellar tendon in the data's pose, apex to tuberosity [m].
pub fn patellar_tendon_length(landmarks: &Landmarks) -> f64 {
    (landmarks.patella_apex.point - landmarks.tibial_tuberosity.point).norm()
}

/// The four meshes as one: blocks renamed, surfaces `<muscle>_<surface>`, the node sets
/// of the fiber flow and the origin, and an element set per muscle.
fn combine(muscles: &[Quadriceps], meshes: &[Mesh]) -> Result<(Mesh, Vec<BlockRole>)> {
    let mut combined = Mesh::default();
    let mut roles = Vec::new();
    for (b, (&muscle, mesh)) in muscles.iter().zip(meshes).enumerate() {
        if mesh.blocks.len() != 1 {
            bail!(
                "the {} mesh has {} blocks, not one",
                muscle.abbreviation(),
                mesh.blocks.len()
            );
        }
        let offset = combined.nodes.len() as u32;
        for i in 0..mesh.nodes.len() {
            combined.nodes.push(mesh.nodes.position(i));
        }
        let mut block = mesh.blocks[0].clone();
        block.name = muscle.name().to_string();
        block.connectivity.iter_mut().for_each(|id| *id += offset);
        let elements = block.len() as u32;
        combined.blocks.push(block);
        roles.push(BlockRole {
            muscle,
            tissue: Tissue::Muscle,
        });
        let name = muscle.name();
        combined.element_sets.insert(
            name.to_string(),
            (0..elements)
                .map(|e| ElementRef::new(b as u32, e))
                .collect(),
        );
        for (surface, faces) in &mesh.surfaces {
            let mut faces: Vec<Face> = faces
                .iter()
                .map(|f| Face::new(ElementRef::new(b as u32, f.element.element), f.face))
                .collect();
            faces.sort_unstable();
            combined.surfaces.insert(format!("{name}_{surface}"), faces);
        }
        let nodes_of = |names: &[&str]| -> Result<Vec<u32>> {
            let mut nodes = std::collections::BTreeSet::new();
            for surface in names {
                for &face in mesh.surface(surface)? {
                    nodes.extend(mesh.face_nodes(face)?.iter().map(|n| n + offset));
                }
            }
            Ok(nodes.into_iter().collect())
        };
        let origin = nodes_of(&FIBER_INLETS)?;
        combined
            .node_sets
            .insert(format!("{name}_origin"), origin.clone());
        combined
            .node_sets
            .insert(format!("{name}_belly_start"), origin);
        combined
            .node_sets
            .insert(format!("{name}_belly_end"), nodes_of(&FIBER_OUTLETS)?);
    }
    Ok((combined, roles))
}

/// The attachment of `muscle` on the patella (see the module documentation) [m].
pub fn attachment(muscle: Quadriceps, patella: &TriangleSurface) -> Result<Vector3<f64>> {
    let side = match muscle {
        Quadriceps::RectusFemoris => Vector3::x(),
        Quadriceps::VastusIntermedius => -Vector3::x(),
        Quadriceps::VastusLateralis => Vector3::z(),
        Quadriceps::VastusMedialis => -Vector3::z(),
    };
    let direction = Vector3::y() + side;
    patella
        .vertices
        .iter()
        .max_by(|a, b| a.dot(&direction).total_cmp(&b.dot(&direction)))
        .copied()
        .context("the patella has no vertices")
}

/// The strands of `muscle`'s `end` (block `block` of `mesh`): one from each mid-edge node
/// of its outlet faces (insertion) or inlet faces (origin) to `attachment`, sharing
/// `strain_stiffness` [N] by tributary area.
fn muscle_strands(
    mesh: &Mesh,
    block: u32,
    muscle: Quadriceps,
    end: MuscleEnd,
    attachment: u32,
    strain_stiffness: f64,
) -> Result<Vec<TendonStrand>> {
    let name = muscle.name();
    let faces: &[&str] = match end {
        MuscleEnd::Insertion => &FIBER_OUTLETS,
        MuscleEnd::Origin => &FIBER_INLETS,
    };
    let mut tributary: BTreeMap<u32, f64> = BTreeMap::new();
    for outlet in faces {
        for &face in mesh.surface(&format!("{name}_{outlet}"))? {
            if face.element.block != block {
                bail!("surface {name}_{outlet} has a face on another block");
            }
            let nodes = mesh.face_nodes(face)?;
            if nodes.len() != 6 {
                bail!("{name}_{outlet}: strands need tet10 faces (6 nodes)");
            }
            let [a, b, c] = [0, 1, 2].map(|k| mesh.nodes.position(nodes[k] as usize));
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            for &mid in &nodes[3..6] {
                *tributary.entry(mid).or_default() += area / 3.0;
            }
        }
    }
    let total: f64 = tributary.values().sum();
    if total <= 0.0 {
        bail!("{name} has no {end:?} faces for its tendon strands");
    }
    let anchor = mesh.nodes.position(attachment as usize);
    Ok(tributary
        .into_iter()
        .map(|(node, area)| TendonStrand {
            muscle,
            end,
            node,
            attachment,
            slack_length: (anchor - mesh.nodes.position(node as usize)).norm(),
            strain_stiffness: strain_stiffness * area / total,
            toe_strain: PATELLAR_TENDON_TOE_STRAIN,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_knee_loads_in_the_knee_frame_with_strands_to_the_patella() {
        let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
        knee.mesh.validate().unwrap();
        assert_eq!(knee.mesh.blocks.len(), 4);
        // The muscles lie above the flexion axis and around the femur.
        let (low, high) = knee.femur.bounds();
        assert!(low.y < 0.0 && high.y > 0.3, "{low} {high}");
        let inserting = |s: &&TendonStrand| s.end == MuscleEnd::Insertion;
        let strength: f64 = (knee.strands.iter().filter(inserting))
            .map(|s| s.strain_stiffness)
            .sum();
        let expected = PATELLAR_TENDON_STIFFNESS * patellar_tendon_length(&knee.landmarks);
        assert!((strength - expected).abs() < 1e-9 * expected);
        for &muscle in &knee.muscles {
            let attachment = knee
                .mesh
                .node_set(&format!("{}_insertion", muscle.name()))
                .unwrap()[0];
            let mine: Vec<_> = (knee.strands.iter().filter(inserting))
                .filter(|s| s.muscle == muscle)
                .collect();
            let stiffness: f64 = mine.iter().map(|s| s.strain_stiffness).sum();
            let (shortest, longest) = mine.iter().fold((f64::MAX, 0.0_f64), |(a, b), s| {
                (a.min(s.slack_length), b.max(s.slack_length))
            });
            println!(
                "{}: {} strands, E A = {:.1} kN, slack {:.1}–{:.1} mm, from {:.1?} mm to {:.1?} mm",
                muscle.abbreviation(),
                mine.len(),
                stiffness * 1e-3,
                shortest * 1e3,
                longest * 1e3,
                knee.outlet_centroid(muscle) * 1e3,
                knee.attachment_point(muscle).unwrap() * 1e3,
            );
            assert!(mine.len() > 20, "{muscle:?}: {} strands", mine.len());
            assert!(mine.iter().all(|s| s.attachment == attachment));
            // Strands run from the muscle's outlets to the patella: 1 to 25 cm.
            for s in &mine {
                assert!(
                    (0.005..0.25).contains(&s.slack_length),
                    "{muscle:?}: {}",
                    s.slack_length
                );
            }
        }
    }

    /// The rectus femoris's origin is one pin node, 2 cm beyond its origin band, joined
    /// to the band's mid-edge nodes by strands as stiff in all as its distal ones.
    #[test]
    fn the_rectus_femoris_hangs_from_a_pin_by_strands() {
        let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
        let rf = Quadriceps::RectusFemoris;
        let origin = knee.mesh.node_set("rectus_femoris_origin").unwrap();
        assert_eq!(origin.len(), 1);
        let pin = knee.mesh.nodes.position(origin[0] as usize);
        let band = knee.mesh.node_set("rectus_femoris_belly_start").unwrap();
        let top = band
            .iter()
            .map(|&n| knee.mesh.nodes.position(n as usize).y)
            .fold(f64::NEG_INFINITY, f64::max);
        let of = |end| -> Vec<&TendonStrand> {
            (knee.strands.iter())
                .filter(|s| s.muscle == rf && s.end == end)
                .collect()
        };
        let (origins, insertions) = (of(MuscleEnd::Origin), of(MuscleEnd::Insertion));
        let stiffness =
            |list: &[&TendonStrand]| list.iter().map(|s| s.strain_stiffness).sum::<f64>();
        let shortest = origins
            .iter()
            .map(|s| s.slack_length)
            .fold(f64::MAX, f64::min);
        println!(
            "RF origin pin at {:.1?} mm (band top y {:.1} mm): {} strands, E A {:.1} kN, \
             shortest {:.1} mm",
            pin * 1e3,
            top * 1e3,
            origins.len(),
            stiffness(&origins) * 1e-3,
            shortest * 1e3
        );
        assert!(origins.len() > 20);
        assert!(
            origins
                .iter()
                .all(|s| s.attachment == origin[0] && band.contains(&s.node))
        );
        assert!(
            (stiffness(&origins) - stiffness(&insertions)).abs() < 1e-9 * stiffness(&insertions)
        );
        assert!(pin.y > top, "the pin lies above the band");
        assert!((shortest - ORIGIN_PIN_OFFSET).abs() < 0.01, "{shortest}");
        // No other muscle hangs from a pin.
        assert!(
            knee.strands
                .iter()
                .all(|s| s.end == MuscleEnd::Insertion || s.muscle == rf)
        );
    }

    #[test]
    fn the_attachments_lie_on_the_patellas_base_around_its_middle() {
        let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
        let at = |m| attachment(m, &knee.patella).unwrap();
        let (rf, vi) = (
            at(Quadriceps::RectusFemoris),
            at(Quadriceps::VastusIntermedius),
        );
        let (vl, vm) = (
            at(Quadriceps::VastusLateralis),
            at(Quadriceps::VastusMedialis),
        );
        assert!(rf.x > vi.x + 0.01, "the rectus in front of the intermedius");
        assert!(vl.z > vm.z + 0.02, "the lateralis lateral of the medialis");
    }
}
