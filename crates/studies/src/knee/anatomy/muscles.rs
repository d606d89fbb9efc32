//! The four quadriceps as swept solids (`musclefem_core::mesh::generate::SweptSolid`)
//! and their hex8 meshes.
//!
//! Each muscle is a list of control stations (centre, width direction, semi-axes, in
//! millimetres below) from its origin to its insertion on the patella's base:
//!
//! - **vastus intermedius** (VI) on the anterior femoral shaft, from the
//!   intertrochanteric region (y = 402 mm) down the front of the shaft, its section
//!   widest across (z);
//! - **vastus lateralis** (VL) from the greater trochanter (y = 420 mm) down the lateral
//!   and posterolateral thigh, its width turned 20–40° from anteroposterior;
//! - **vastus medialis** (VM) from the medial femur (y = 352 mm), bulkiest distally
//!   (its oblique fibres), inserting on the patella's superomedial border;
//! - **rectus femoris** (RF) from the anterior inferior iliac spine on the pelvis
//!   (y = 482 mm, 37 mm above and 30 mm in front of the hip centre), crossing the hip and
//!   running over the intermedius.
//!
//! The stations were laid out level by level (y = 390, 330, 270, 210, 150, 105 and
//! 75 mm): the intermedius on the femur, the rectus on the intermedius, the lateralis
//! and medialis against both the femur and the intermedius, each placed 2.5 mm from its
//! neighbours in the horizontal plane so that, once the sections turn normal to the
//! curved centrelines, adjacent muscles touch or nearly touch without overlapping (the
//! cohesive contact will bond them); the semi-axes were then scaled so each muscle's
//! volume ∫ π a b ds is the Visible Human Male's (Andreassen et al. 2023, Sci Data
//! 10:34; the VHM's right rectus femoris is missing, its left one is used). The vasti
//! lateralis and medialis get one more, smaller station at y = 58 mm so that their
//! distal turn towards the patella stays gentle enough for their sections (curvature ×
//! section extent below the overlap limit 1, which `SweptSolid` checks). The last
//! station is placed
//! on the patella at 0° of flexion (1 mm proximal to the insertion point on the base)
//! and every muscle's semi-axes are rescaled at construction so the volume matches
//! exactly. Fibers run along the centreline.
//!
//! **Tendons** ([`Quadriceps::tendon_layout`]). Below its muscle–tendon junction each
//! muscle goes on as tendinous tissue to the patella: its lamina of the quadriceps tendon
//! with the distal aponeurosis that gathers the fibers (the vasti's segmentations end
//! 0–40 mm above the patella, the rectus femoris's about 80 mm above it: the Visible Human
//! Female data's README, `../shared/data/visible_human_female_right/`). The rectus starts
//! with its direct tendon from the anterior inferior iliac spine, each vastus with a
//! tendinous origin 32–42 mm long (its proximal aponeurosis; see
//! [`Quadriceps::tendon_layout`]). The solid stays one
//! swept solid with a layer of nodes at each junction; the mesh has a block per segment:
//! `<muscle>` (the belly, muscle material) and `<muscle>_tendon` (and
//! `<muscle>_origin_tendon`), the belly alone volume-matched to the Visible Human.

use anyhow::{Context, Result};
use nalgebra::Vector3;

use musclefem_core::mesh::generate::{
    SweptMuscleSpec, SweptSolid, SweptStation, swept_muscle_mesh,
};
use musclefem_core::mesh::{ElementBlock, ElementRef, Face, Mesh};

use super::Resolution;
use super::dimensions::{MM, PATELLA_SEMI_AXES, mm};
use super::kinematics::{PatellaPose, QuadricepsPull};

mod stations;

use stations::{RECTUS_FEMORIS, Station, VASTUS_INTERMEDIUS, VASTUS_LATERALIS, VASTUS_MEDIALIS};

/// The four heads of the quadriceps femoris.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Quadriceps {
    VastusIntermedius,
    VastusLateralis,
    VastusMedialis,
    RectusFemoris,
}

impl Quadriceps {
    /// All four, in the order of the meshes' blocks.
    pub const ALL: [Quadriceps; 4] = [
        Quadriceps::VastusIntermedius,
        Quadriceps::VastusLateralis,
        Quadriceps::VastusMedialis,
        Quadriceps::RectusFemoris,
    ];

    /// The block name: `vastus_intermedius`, ...
    pub fn name(self) -> &'static str {
        match self {
            Quadriceps::VastusIntermedius => "vastus_intermedius",
            Quadriceps::VastusLateralis => "vastus_lateralis",
            Quadriceps::VastusMedialis => "vastus_medialis",
            Quadriceps::RectusFemoris => "rectus_femoris",
        }
    }

    /// The usual abbreviation: VI, VL, VM, RF.
    pub fn abbreviation(self) -> &'static str {
        match self {
            Quadriceps::VastusIntermedius => "VI",
            Quadriceps::VastusLateralis => "VL",
            Quadriceps::VastusMedialis => "VM",
            Quadriceps::RectusFemoris => "RF",
        }
    }

    /// The Visible Human Male's muscle volume [m³] (Andreassen et al. 2023): right VI
    /// 892.4, VL 1150.6, VM 738.0 cm³; left RF 404.7 cm³ (the right one is missing from
    /// the data set).
    pub fn visible_human_volume(self) -> f64 {
        1e-6 * match self {
            Quadriceps::VastusIntermedius => 892.4,
            Quadriceps::VastusLateralis => 1150.6,
            Quadriceps::VastusMedialis => 738.0,
            Quadriceps::RectusFemoris => 404.7,
        }
    }

    /// The insertion on the patella's base [m], in the patella's frame: on the
    /// ellipsoid above the points (x, z) = VI (−4, 0) (deep), RF (4.5, 0) (superficial),
    /// VL (0, 14) (superolateral), VM (0, −16) mm (superomedial).
    pub fn insertion(self) -> Vector3<f64> {
        let (x, z) = match self {
            Quadriceps::VastusIntermedius => (-4.0, 0.0),
            Quadriceps::RectusFemoris => (4.5, 0.0),
            Quadriceps::VastusLateralis => (0.0, 14.0),
            Quadriceps::VastusMedialis => (0.0, -16.0),
        };
        let [a, b, c] = PATELLA_SEMI_AXES.map(|s| s / MM);
        let y = b * (1.0 - (x / c).powi(2) - (z / a).powi(2)).sqrt();
        mm(x, y, z)
    }

    /// The muscle's pull on the patella: from its release station (the table's station
    /// at [`RELEASE_HEIGHT`]) to its insertion, weighted by its volume. Only femur-fixed
    /// and patella-fixed points, so it is known before the patella is placed.
    pub fn pull(self) -> QuadricepsPull {
        let (table, _) = self.table();
        let release = table
            .iter()
            .find(|s| (s.0[1] * MM - RELEASE_HEIGHT).abs() < 1e-9)
            .map(|s| mm(s.0[0], s.0[1], s.0[2]))
            .expect("every table has a station at the release height");
        QuadricepsPull {
            release,
            insertion: self.insertion(),
            weight: self.visible_human_volume(),
        }
    }

    /// The control stations from the origin down to the last femur-fixed one (mm in the
    /// table; see the module documentation), and the insertion's section (width
    /// direction, half-width, half-thickness [mm]).
    fn table(self) -> (&'static [Station], ([f64; 3], f64, f64)) {
        match self {
            Quadriceps::VastusIntermedius => (VASTUS_INTERMEDIUS, ([0.0, 0.0, 1.0], 9.0, 3.5)),
            Quadriceps::VastusLateralis => (VASTUS_LATERALIS, ([1.0, 0.0, 0.0], 7.0, 4.0)),
            Quadriceps::VastusMedialis => (VASTUS_MEDIALIS, ([1.0, 0.0, 0.0], 7.0, 4.0)),
            Quadriceps::RectusFemoris => (RECTUS_FEMORIS, ([0.0, 0.0, 1.0], 8.0, 3.5)),
        }
    }
}

/// Where a muscle's tendinous parts are, as heights y in the femur's frame [m] (the
/// stations run down y from the origin to the insertion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TendonLayout {
    /// The origin's tendon reaches down to this height, where the belly begins (`None`: a
    /// fleshy origin, the belly starts at the origin).
    pub origin_tendon_end: Option<f64>,
    /// The muscle–tendon junction: the belly ends here, the tendon runs on to the patella.
    pub junction: f64,
}

/// What a block of a muscle's mesh is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tissue {
    /// The belly: the Hill muscle.
    Muscle,
    /// Tendon or aponeurosis.
    Tendon,
}

impl Quadriceps {
    /// The muscle's tendons (see the module documentation): the vasti's junctions 40 mm
    /// (VI, VL) and 20 mm (VM, whose oblique fibres reach lowest) above the patella's
    /// base (y ≈ 49 mm at 0°), the rectus femoris's 80 mm above it, and its direct tendon
    /// from the spine the first 42 mm below the origin (y = 482 → 440 mm).
    ///
    /// Each vastus begins with 32–42 mm of tendinous origin (VI 402 → 360 mm, VL 420 →
    /// 380 mm, VM 352 → 320 mm): the proximal aponeuroses of the lateralis and medialis,
    /// and for the intermedius the broad origin on the upper shaft, which the swept solid's
    /// narrow end (VI 10 × 4 mm semi-axes, 1/33 of its largest section) cannot carry as
    /// muscle. With those ends of muscle material the whole pull went through them: on
    /// the coarse passive squat at 90° the first two of twelve layers stretched most
    /// (fiber stretch 1.21–1.28 against 1.15–1.20 in the belly) and held every one of
    /// VI's top-5 % elements (vm95 342 kPa; 106 kPa over the other layers; explicit
    /// solver, 2026-11-25).
    pub fn tendon_layout(self) -> TendonLayout {
        let (origin_tendon_end, junction) = match self {
            Quadriceps::VastusIntermedius => (Some(360.0), 89.0),
            Quadriceps::VastusLateralis => (Some(380.0), 89.0),
            Quadriceps::VastusMedialis => (Some(320.0), 69.0),
            Quadriceps::RectusFemoris => (Some(440.0), 129.0),
        };
        TendonLayout {
            origin_tendon_end: origin_tendon_end.map(|y| y * MM),
            junction: junction * MM,
        }
    }
}

/// Height of the release station [m]: the musculotendon path is femur-fixed down to the
/// station at y = 105 mm (where the muscles leave the femoral shaft for the
/// suprapatellar region) and free from there to the patella.
pub const RELEASE_HEIGHT: f64 = 105.0 * MM;

/// One quadriceps: its solid, its mesh and the data of its musculotendon path.
#[derive(Clone, Debug)]
pub struct Muscle {
    pub muscle: Quadriceps,
    /// Control stations, origin first, the last one on the patella at 0°.
    pub stations: Vec<SweptStation>,
    /// The continuous solid through the stations.
    pub solid: SweptSolid,
    /// Index of the release station (the last femur-fixed point of the path).
    pub release: usize,
    /// Centreline length from the origin to the release station [m].
    pub fixed_length: f64,
    /// Arclengths [m] of the belly's start (0 for a fleshy origin) and end (the
    /// muscle–tendon junction).
    pub belly: (f64, f64),
    /// The hex8 mesh, a block per segment from the origin: [`Quadriceps::name`] for the
    /// belly, `<name>_tendon` below it, `<name>_origin_tendon` above it; sets `origin`,
    /// `insertion`, `lateral`, `outer`, `all` (see `swept_muscle_mesh`) and the node sets
    /// `belly_start` and `belly_end` (the belly's end sections).
    pub mesh: Mesh,
    /// The tissue of each block of `mesh`.
    pub tissues: Vec<Tissue>,
}

impl Muscle {
    /// The muscle with its insertion placed on the patella at `patella` (its pose at 0°),
    /// volume-matched to the Visible Human and meshed at `resolution`.
    pub fn new(muscle: Quadriceps, patella: &PatellaPose, resolution: Resolution) -> Result<Self> {
        let (table, (width, half_width, half_thickness)) = muscle.table();
        let mut stations: Vec<SweptStation> = table
            .iter()
            .map(|&(c, w, a, b)| SweptStation {
                centre: mm(c[0], c[1], c[2]),
                width_direction: Vector3::from(w),
                half_width: a * MM,
                half_thickness: b * MM,
            })
            .collect();
        let insertion = patella.to_world(&muscle.insertion()) + Vector3::new(0.0, MM, 0.0);
        stations.push(SweptStation {
            centre: insertion,
            width_direction: Vector3::from(width),
            half_width: half_width * MM,
            half_thickness: half_thickness * MM,
        });
        let layout = muscle.tendon_layout();
        let centreline = SweptSolid::new(&stations)?;
        let at_height = |y: f64| arclength_at_height(&centreline, y);
        let belly = (
            layout.origin_tendon_end.map_or(0.0, at_height),
            at_height(layout.junction),
        );
        // Scale the semi-axes (not the end sections) until the belly's ∫πab ds is the
        // VHM's (the centreline, and with it the junctions' arclengths, stays).
        let last = stations.len() - 1;
        let target = muscle.visible_human_volume();
        for _ in 0..8 {
            let volume = SweptSolid::new(&stations)?.volume_between(belly.0, belly.1);
            let scale = (target / volume).sqrt();
            for s in &mut stations[1..last] {
                s.half_width *= scale;
                s.half_thickness *= scale;
            }
        }
        let solid = SweptSolid::new(&stations)?;
        let release = table
            .iter()
            .position(|s| (s.0[1] * MM - RELEASE_HEIGHT).abs() < 1e-9)
            .context("no station at the release height")?;
        let fixed_length = solid.station_arclengths()[release];
        let (per_side, radial, belly_layers) = resolution.muscle_divisions();
        // The belly keeps the resolution's layers; the tendons get as many layers per
        // section size they span (the measure the layers are graded by) as the belly. With
        // half as many (coarse: 2 layers of 20–25 mm from the vasti's junctions to the
        // patella) the tendons' nodes, the only points of their contact with the femur,
        // popped in and out of the trochlea as the tendons wrapped it, and Newton's method
        // stalled in deep flexion.
        let density = belly_layers as f64 / solid.section_sizes_between(belly.0, belly.1);
        let tendon_layers = |from: f64, to: f64| {
            ((density * solid.section_sizes_between(from, to)).ceil() as usize).max(1)
        };
        let mut junctions = Vec::new();
        let mut segment_layers = Vec::new();
        if belly.0 > 0.0 {
            junctions.push(belly.0);
            segment_layers.push(tendon_layers(0.0, belly.0));
        }
        junctions.push(belly.1);
        segment_layers.push(belly_layers);
        segment_layers.push(tendon_layers(belly.1, solid.length()));
        let swept = swept_muscle_mesh(&SweptMuscleSpec {
            name: muscle.name().to_string(),
            stations: stations.clone(),
            per_side,
            radial,
            axial: belly_layers,
            junctions,
            segment_layers: Some(segment_layers),
        })
        .with_context(|| format!("meshing the {}", muscle.name()))?;
        let (mesh, tissues) = split_into_segments(swept, muscle, belly.0 > 0.0)?;
        Ok(Self {
            muscle,
            stations,
            solid,
            release,
            fixed_length,
            belly,
            mesh,
            tissues,
        })
    }

    /// The index of the belly's block in [`Muscle::mesh`].
    pub fn belly_block(&self) -> usize {
        self.tissues
            .iter()
            .position(|&t| t == Tissue::Muscle)
            .expect("every muscle has a belly")
    }

    /// The pull of this muscle on the patella (see [`Quadriceps::pull`]).
    pub fn pull(&self) -> QuadricepsPull {
        self.muscle.pull()
    }
}

/// The arclength [m] at which the centreline of `solid` passes the height `y` [m] (its
/// centre's y falls monotonically from the origin to the insertion), by bisection.
fn arclength_at_height(solid: &SweptSolid, y: f64) -> f64 {
    let (mut low, mut high) = (0.0, solid.length());
    for _ in 0..60 {
        let middle = 0.5 * (low + high);
        if solid.section(middle).centre.y > y {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// The swept mesh of `muscle` (one block, with element sets `segment_i`) split into a
/// block per segment: the origin's tendon first if `origin_tendon`, then the belly, then
/// the tendon; with the node sets `belly_start` and `belly_end`.
fn split_into_segments(
    swept: Mesh,
    muscle: Quadriceps,
    origin_tendon: bool,
) -> Result<(Mesh, Vec<Tissue>)> {
    let mut parts = Vec::new();
    if origin_tendon {
        parts.push((format!("{}_origin_tendon", muscle.name()), Tissue::Tendon));
    }
    parts.push((muscle.name().to_string(), Tissue::Muscle));
    parts.push((format!("{}_tendon", muscle.name()), Tissue::Tendon));
    let source = &swept.blocks[0];
    let per_element = source.shape.nodes_per_element();
    let mut blocks = Vec::new();
    // Where each element of the swept block went: (block, element).
    let mut moved = vec![ElementRef::new(0, 0); source.len()];
    for (b, (name, _)) in parts.iter().enumerate() {
        let segment = swept
            .element_set(&format!("segment_{b}"))
            .with_context(|| format!("the {}'s segment {b}", muscle.name()))?;
        let first = segment.first().map_or(0, |e| e.element as usize);
        let count = segment.len();
        let range = first..first + count;
        let mut block = ElementBlock::new(
            name.clone(),
            source.shape,
            source.connectivity[range.start * per_element..range.end * per_element].to_vec(),
        )?;
        block.fiber_direction = source.fiber_direction[range.clone()].to_vec();
        for (k, e) in range.enumerate() {
            moved[e] = ElementRef::new(b as u32, k as u32);
        }
        blocks.push(block);
    }
    let mut mesh = Mesh::new(swept.nodes.clone(), blocks);
    mesh.node_sets = swept.node_sets.clone();
    let junction = |i: usize| {
        swept
            .node_set(&format!("junction_{i}"))
            .map(<[u32]>::to_vec)
            .with_context(|| format!("the {}'s junction {i}", muscle.name()))
    };
    let belly_start = if origin_tendon {
        junction(0)?
    } else {
        mesh.node_set("origin")?.to_vec()
    };
    let belly_end = junction(usize::from(origin_tendon))?;
    mesh.node_sets
        .insert("belly_start".to_string(), belly_start);
    mesh.node_sets.insert("belly_end".to_string(), belly_end);
    let remap = |e: &ElementRef| moved[e.element as usize];
    for (name, set) in &swept.element_sets {
        if !name.starts_with("segment_") {
            mesh.element_sets
                .insert(name.clone(), set.iter().map(remap).collect());
        }
    }
    for (name, faces) in &swept.surfaces {
        mesh.surfaces.insert(
            name.clone(),
            faces
                .iter()
                .map(|f| Face::new(remap(&f.element), f.face))
                .collect(),
        );
    }
    Ok((mesh, parts.into_iter().map(|(_, t)| t).collect()))
}

/// One block of the combined mesh: its muscle and tissue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockRole {
    pub muscle: Quadriceps,
    pub tissue: Tissue,
}

/// The muscles' meshes as one mesh: the bellies first, one block per muscle in the order
/// given (block `b` is `muscles[b]`'s belly), then every tendon block. Every node set and
/// surface of muscle `m` is renamed `<m>_<name>` (`vastus_lateralis_origin`, ...), its
/// element sets likewise, and the element set `<m>` holds all its elements; each
/// surface's faces are sorted. Returns the role of every block.
pub fn combined_mesh(muscles: &[Muscle]) -> (Mesh, Vec<BlockRole>) {
    let mut combined = Mesh::default();
    let mut roles = Vec::new();
    let mut offsets = Vec::new();
    for muscle in muscles {
        offsets.push(combined.nodes.len() as u32);
        for i in 0..muscle.mesh.nodes.len() {
            combined.nodes.push(muscle.mesh.nodes.position(i));
        }
    }
    // Where each muscle's blocks go: bellies first, then the tendons.
    let mut placed: Vec<Vec<u32>> = muscles.iter().map(|m| vec![0; m.tissues.len()]).collect();
    for pass in [Tissue::Muscle, Tissue::Tendon] {
        for (m, muscle) in muscles.iter().enumerate() {
            for (b, &tissue) in muscle.tissues.iter().enumerate() {
                if tissue != pass {
                    continue;
                }
                placed[m][b] = combined.blocks.len() as u32;
                let mut block = muscle.mesh.blocks[b].clone();
                block
                    .connectivity
                    .iter_mut()
                    .for_each(|id| *id += offsets[m]);
                combined.blocks.push(block);
                roles.push(BlockRole {
                    muscle: muscle.muscle,
                    tissue,
                });
            }
        }
    }
    for (m, muscle) in muscles.iter().enumerate() {
        let mesh = &muscle.mesh;
        let name = muscle.muscle.name();
        let moved = |e: &ElementRef| ElementRef::new(placed[m][e.block as usize], e.element);
        let mut all = Vec::new();
        for (b, block) in mesh.blocks.iter().enumerate() {
            all.extend((0..block.len() as u32).map(|e| ElementRef::new(placed[m][b], e)));
        }
        combined.element_sets.insert(name.to_string(), all);
        for (set, ids) in &mesh.node_sets {
            combined.node_sets.insert(
                format!("{name}_{set}"),
                ids.iter().map(|id| id + offsets[m]).collect(),
            );
        }
        for (set, elements) in &mesh.element_sets {
            combined.element_sets.insert(
                format!("{name}_{set}"),
                elements.iter().map(moved).collect(),
            );
        }
        // Each surface's faces sorted (by block, element, face) as a mesh file reads them
        // back, so that a scene of the knee has the knee's own triangles in its order.
        for (surface, faces) in &mesh.surfaces {
            let mut faces: Vec<Face> = faces
                .iter()
                .map(|f| Face::new(moved(&f.element), f.face))
                .collect();
            faces.sort_unstable();
            combined.surfaces.insert(format!("{name}_{surface}"), faces);
        }
    }
    (combined, roles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insertions_lie_on_the_patella_and_pulls_on_the_femur_side() {
        let [a, b, c] = PATELLA_SEMI_AXES;
        for m in Quadriceps::ALL {
            let p = m.insertion();
            let on = (p.x / c).powi(2) + (p.y / b).powi(2) + (p.z / a).powi(2);
            assert!((on - 1.0).abs() < 1e-12, "{m:?}");
            assert!(p.y > 0.7 * b, "{m:?} inserts on the base");
            let pull = m.pull();
            assert!((pull.release.y - RELEASE_HEIGHT).abs() < 1e-12);
            assert!((pull.weight - m.visible_human_volume()).abs() < 1e-15);
        }
    }

    #[test]
    fn the_combined_mesh_keeps_every_muscle_and_its_names() {
        let pose = PatellaPose {
            centre: mm(46.4, 27.0, 0.0),
            flexion: 0.0,
            groove_coordinate: 0.0,
        };
        let muscles: Vec<Muscle> = Quadriceps::ALL
            .iter()
            .map(|&m| Muscle::new(m, &pose, Resolution::Coarse).unwrap())
            .collect();
        let (mesh, roles) = combined_mesh(&muscles);
        mesh.validate().unwrap();
        // The four bellies first, then every tendon block.
        let blocks: usize = muscles.iter().map(|m| m.tissues.len()).sum();
        assert_eq!(mesh.blocks.len(), blocks);
        assert_eq!(roles.len(), blocks);
        assert!(roles[..4].iter().all(|r| r.tissue == Tissue::Muscle));
        assert!(roles[4..].iter().all(|r| r.tissue == Tissue::Tendon));
        let total: f64 = muscles.iter().map(|m| m.mesh.total_volume().unwrap()).sum();
        assert!((mesh.total_volume().unwrap() - total).abs() < 1e-12 * total);
        for (b, muscle) in muscles.iter().enumerate() {
            let name = muscle.muscle.name();
            assert_eq!(mesh.blocks[b].name, name);
            assert_eq!(roles[b].muscle, muscle.muscle);
            // The muscle's element set holds all its segments.
            assert_eq!(
                mesh.element_set(name).unwrap().len(),
                muscle.mesh.element_count()
            );
            // The insertion nodes of the combined mesh are the muscle's, moved by its
            // offset.
            let own = muscle.mesh.node_set("insertion").unwrap();
            let combined = mesh.node_set(&format!("{name}_insertion")).unwrap();
            assert_eq!(own.len(), combined.len());
            for (&i, &j) in own.iter().zip(combined) {
                assert_eq!(
                    muscle.mesh.nodes.position(i as usize),
                    mesh.nodes.position(j as usize)
                );
            }
            // Its surfaces lie on its own blocks.
            for surface in ["origin", "insertion", "outer"] {
                let faces = mesh.surface(&format!("{name}_{surface}")).unwrap();
                assert!(
                    faces
                        .iter()
                        .all(|f| roles[f.element.block as usize].muscle == muscle.muscle)
                );
            }
        }
    }
}
