//! From a parsed scene to what the solvers take: one mesh holding every part's blocks
//! (node sets renamed `PART.SET`), the parts with their materials, the loads and the
//! solver settings. Every reference (material, part, node set, amplitude, component) is
//! checked here, and an error names the line of the reference.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::{Unit, Vector3};
use toml::Spanned;

use musclefem_core::element::{ElementKind, Technology};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{
    Loads, NodalForce, Part, PrescribedDisplacement, RigidMotion, RigidRotation, RigidTie,
};
use musclefem_materials::{ActivationHistory, Amplitude, Material, MaterialLibrary};

use super::activation::{activation_history, driven_material};
use super::amplitudes::Amplitudes;
use super::error::{Locator, SceneError, suggestion};
use super::followers::{Followers, PrescribedMotion, followed_alone};
use super::format::{PartEntry, SceneFile};
use super::interactions::{InteractionModel, build_interactions, rigid_body};
use super::locking::small_strain_shear_modulus;
use super::part_mesh::{SharedFile, append_part, part_mesh};
use super::step::step_settings;
use super::strands::tendon_strands;
use super::trust::PluginPolicy;

/// The Hill muscle's activation parameters, which a part's recorded activation replaces.
const ACTIVATION_PARAMETERS: [&str; 5] = ["n1", "n2", "t0", "t1", "S"];

/// Element technologies by scene name ([`ElementKind::NAMES`]).
pub const ELEMENT_NAMES: [&str; ElementKind::NAMES.len()] = ElementKind::NAMES;

/// The analysis of the step: the solver's own [`musclefem_core::solver::Analysis`].
pub use musclefem_core::solver::Analysis;

/// Everything a run needs.
#[derive(Debug, Clone)]
pub struct Model {
    pub description: String,
    pub mesh: Mesh,
    pub parts: Vec<Part>,
    /// Part names, in the order of `parts` (part i is block i of the mesh).
    pub part_names: Vec<String>,
    /// The name of each part's material, in the order of `parts`.
    pub material_names: Vec<String>,
    pub loads: Loads,
    /// A name for each prescribed displacement of `loads`, e.g. "cube.x1.x".
    pub displacement_names: Vec<String>,
    pub analysis: Analysis,
    /// Why `solver = "auto"` chose the analysis's solver (`None`: the scene named it).
    pub solver_rationale: Option<String>,
    /// Time between output rows (explicit history) [s].
    pub output_interval: f64,
    /// Time between frames [s] (`[output] frame_interval`, default `output_interval`).
    pub frame_interval: f64,
    pub write_frames: bool,
    /// `[output] von_mises_percentile`: each part's percentile P ∈ (0, 100) of its
    /// elements' von Mises stress as history columns.
    pub von_mises_percentile: Option<f64>,
    /// Contact and cohesion between surfaces, in the order of the scene file.
    pub interactions: Vec<InteractionModel>,
    /// The rigid bodies, in the order of the scene file (the frames show them; the
    /// interactions hold their own copies).
    pub rigid_bodies: Vec<musclefem_contact::RigidSurface>,
    /// Materials whose plugin `check` did not load (a neo-Hookean stood in for them), as
    /// "material (plugin file)".
    pub unchecked_plugins: Vec<String>,
    /// Per part: its recorded activation (`None`: the material's own).
    pub activation_histories: Vec<Option<Arc<ActivationHistory>>>,
    /// Lines on each part's mesh file (in the order of `parts`): its reader's warnings
    /// (skipped keywords, ...) and where the fibers come from when the file gives them.
    pub part_notes: Vec<Vec<String>>,
}

/// Build the model of `scene` (parsed from the file `locator` names). Plugins are loaded
/// into `library` relative to the scene's directory when the locator's trust allows it.
pub fn build_model(
    scene: &SceneFile,
    locator: &Locator,
    library: &mut MaterialLibrary,
) -> Result<Model, SceneError> {
    let at = |span: std::ops::Range<usize>, message: String| locator.error(span, message);

    // Materials.
    let mut materials: BTreeMap<String, Arc<dyn Material>> = BTreeMap::new();
    let mut unchecked_plugins = Vec::new();
    let mut stand_ins: Vec<&str> = Vec::new();
    for entry in &scene.materials {
        if let Some(plugin) = &entry.plugin {
            let path = locator.resolve(plugin.span(), plugin.get_ref())?;
            match locator.trust().plugins {
                PluginPolicy::Refuse => {
                    return Err(at(
                        plugin.span(),
                        format!(
                            "plugin '{}': loading a shared library runs its code; pass \
                             --allow-plugins if you trust it (`check` reads the rest of \
                             the scene without loading it)",
                            path.display()
                        ),
                    ));
                }
                PluginPolicy::Load => {
                    library.load_plugin(&path).map_err(|e| {
                        at(plugin.span(), format!("plugin '{}': {e}", path.display()))
                    })?;
                }
                PluginPolicy::SkipForCheck => {
                    unchecked_plugins.push(format!(
                        "{} ({})",
                        entry.name.get_ref(),
                        plugin.get_ref()
                    ));
                    let stand_in = library
                        .create("neo-hookean", &BTreeMap::new())
                        .map_err(|e| at(plugin.span(), format!("neo-Hookean stand-in: {e}")))?;
                    materials.insert(entry.name.get_ref().clone(), stand_in);
                    stand_ins.push(entry.name.get_ref());
                    continue;
                }
            }
        }
        let model = entry.model.get_ref();
        let names = library.names();
        if !names.iter().any(|n| n == model) {
            return Err(at(
                entry.model.span(),
                format!(
                    "unknown material model '{model}'{}; known: {}",
                    suggestion(model, names.iter().map(String::as_str)),
                    names.join(", ")
                ),
            ));
        }
        let (parameters, span) = match &entry.parameters {
            Some(p) => (p.get_ref().clone(), p.span()),
            None => (BTreeMap::new(), entry.model.span()),
        };
        let material = library
            .create(model, &parameters)
            .map_err(|e| at(span, format!("material '{model}': {e}")))?;
        if materials
            .insert(entry.name.get_ref().clone(), material)
            .is_some()
        {
            return Err(at(
                entry.name.span(),
                format!("material '{}' is defined twice", entry.name.get_ref()),
            ));
        }
    }

    // Parts: one block each, meshes appended into one.
    let mut mesh = Mesh::new(Default::default(), Vec::new());
    let mut parts = Vec::new();
    let mut part_names: Vec<String> = Vec::new();
    let mut part_notes: Vec<Vec<String>> = Vec::new();
    let mut material_names: Vec<String> = Vec::new();
    let mut shared_offsets = std::collections::HashMap::new();
    // Per part with `shared_nodes`: where its file's nodes start, and their labels.
    let mut shared_files: Vec<Option<(u32, SharedFile)>> = Vec::new();
    for entry in &scene.parts {
        let name = entry.name.get_ref();
        if part_names.contains(name) {
            return Err(at(
                entry.name.span(),
                format!("part '{name}' is defined twice"),
            ));
        }
        let material = materials.get(entry.material.get_ref()).ok_or_else(|| {
            at(
                entry.material.span(),
                format!(
                    "part '{name}': unknown material '{}'{}",
                    entry.material.get_ref(),
                    suggestion(
                        entry.material.get_ref(),
                        materials.keys().map(String::as_str)
                    )
                ),
            )
        })?;
        let technology = technology(entry, material.as_ref(), locator)?;
        let density = *entry.density.get_ref();
        if !(density.is_finite() && density > 0.0) {
            return Err(at(
                entry.density.span(),
                format!("density {density} kg/m3 must be positive"),
            ));
        }
        let (part_mesh, notes, shared) = part_mesh(entry, technology.shape(), locator)?;
        let offset = append_part(
            &mut mesh,
            part_mesh,
            name,
            shared.as_ref(),
            &mut shared_offsets,
        );
        shared_files.push(shared.map(|file| (offset, file)));
        part_notes.push(notes);
        parts.push(Part {
            block: parts.len(),
            technology,
            material: material.clone(),
            density,
        });
        part_names.push(name.clone());
        material_names.push(entry.material.get_ref().clone());
    }

    if parts.is_empty() {
        return Err(locator.whole("the scene has no parts"));
    }

    // Amplitudes.
    let amplitudes = Amplitudes::new(scene, locator)?;
    let mut activation_histories = vec![None; parts.len()];
    for (index, entry) in scene.parts.iter().enumerate() {
        let Some(activation) = &entry.activation else {
            continue;
        };
        let part = entry.name.get_ref();
        let history = Arc::new(activation_history(activation, part, &amplitudes, locator)?);
        activation_histories[index] = Some(history.clone());
        if stand_ins.contains(&entry.material.get_ref().as_str()) {
            // `check` without the plugin: the stand-in has no activation to drive.
            continue;
        }
        if let Some(set) = scene
            .materials
            .iter()
            .find(|m| m.name.get_ref() == entry.material.get_ref())
            .and_then(|m| m.parameters.as_ref())
            && let Some(key) = ACTIVATION_PARAMETERS
                .iter()
                .find(|k| set.get_ref().contains_key(**k))
        {
            return Err(at(
                set.span(),
                format!(
                    "material '{}' sets its activation parameter '{key}', but part '{part}'                      takes its activation from {}: remove one of the two",
                    entry.material.get_ref(),
                    history.source
                ),
            ));
        }
        parts[index].material =
            driven_material(&parts[index].material, history, part, activation, locator)?;
    }
    let scaled = |name: &Option<Spanned<String>>, value: f64| -> Result<Amplitude, SceneError> {
        let knots = match name {
            None => vec![(0.0, value)],
            Some(name) => amplitudes
                .knots(name, locator)?
                .into_iter()
                .map(|(t, v)| (t, value * v))
                .collect(),
        };
        Amplitude::new(knots).map_err(|e| locator.whole(e.to_string()))
    };
    let node_set =
        |part: &Spanned<String>, set: &Spanned<String>| -> Result<Vec<u32>, SceneError> {
            if !part_names.contains(part.get_ref()) {
                return Err(at(
                    part.span(),
                    format!(
                        "unknown part '{}'{}",
                        part.get_ref(),
                        suggestion(part.get_ref(), part_names.iter().map(String::as_str))
                    ),
                ));
            }
            let full = format!("{}.{}", part.get_ref(), set.get_ref());
            mesh.node_sets.get(&full).cloned().ok_or_else(|| {
                let prefix = format!("{}.", part.get_ref());
                let known: Vec<&str> = mesh
                    .node_sets
                    .keys()
                    .filter_map(|k| k.strip_prefix(&prefix))
                    .collect();
                at(
                    set.span(),
                    format!(
                        "part '{}' has no node set '{}'{}; it has: {}",
                        part.get_ref(),
                        set.get_ref(),
                        suggestion(set.get_ref(), known.iter().copied()),
                        known.join(", ")
                    ),
                )
            })
        };

    // Loads.
    let mut loads = Loads::default();
    let mut displacement_names = Vec::new();
    for entry in &scene.displacements {
        let nodes = node_set(&entry.part, &entry.nodes)?;
        if entry.components.get_ref().is_empty() {
            return Err(at(
                entry.components.span(),
                "no components given".to_string(),
            ));
        }
        let components = entry.components.get_ref();
        if let Some(k) = (1..components.len()).find(|&k| components[..k].contains(&components[k])) {
            return Err(at(
                entry.components.span(),
                format!("component \"{}\" is given twice", components[k]),
            ));
        }
        for component in components {
            let dof = component_index(component)
                .ok_or_else(|| at(entry.components.span(), bad_component(component)))?;
            loads.displacements.push(PrescribedDisplacement {
                nodes: nodes.clone(),
                dof,
                amplitude: scaled(&entry.amplitude, entry.value)?,
            });
            displacement_names.push(format!(
                "{}.{}.{component}",
                entry.part.get_ref(),
                entry.nodes.get_ref()
            ));
        }
    }
    for entry in &scene.forces {
        let nodes = node_set(&entry.part, &entry.nodes)?;
        let dof = component_index(entry.component.get_ref()).ok_or_else(|| {
            at(
                entry.component.span(),
                bad_component(entry.component.get_ref()),
            )
        })?;
        loads.forces.push(NodalForce {
            nodes,
            dof,
            amplitude: scaled(&entry.amplitude, entry.value)?,
        });
    }
    let tie_names: Vec<String> = scene
        .rigid_ties
        .iter()
        .map(|t| t.name.get_ref().clone())
        .collect();
    let motion_tables: Vec<_> = scene.rigid_ties.iter().map(|t| t.motion.as_ref()).collect();
    let (mut followers, tie_followers) = Followers::of_ties(&motion_tables, &tie_names, locator)?;
    for (entry, follower) in scene.rigid_ties.iter().zip(tie_followers) {
        let nodes = node_set(&entry.part, &entry.nodes)?;
        let prescribed = (
            &entry.translation,
            &entry.translation_amplitude,
            &entry.rotation,
        );
        loads.rigid_ties.push(RigidTie {
            name: entry.name.get_ref().clone(),
            nodes,
            motion: match (follower, &entry.motion) {
                (Some(follower), Some(table)) => {
                    followed_alone(table, prescribed, locator)?;
                    RigidMotion::followed(follower)
                }
                _ => rigid_motion(prescribed, &scaled, locator)?,
            },
        });
    }

    // Rigid bodies and interactions.
    let mut rigid_bodies = Vec::with_capacity(scene.rigid_bodies.len());
    for entry in &scene.rigid_bodies {
        let prescribed = (
            &entry.translation,
            &entry.translation_amplitude,
            &entry.rotation,
        );
        let motion = match &entry.motion {
            Some(table) => {
                followed_alone(table, prescribed, locator)?;
                RigidMotion::followed(followers.of_body(table, &tie_names, locator)?)
            }
            None => rigid_motion(prescribed, &scaled, locator)?,
        };
        rigid_bodies.push(rigid_body(entry, motion, locator)?);
    }
    let mut interactions = build_interactions(
        &scene.interactions,
        &rigid_bodies,
        &mesh,
        &parts,
        &part_names,
        locator,
    )?;
    for entry in &scene.strands {
        let strands = tendon_strands(entry, &part_names, &shared_files, &mesh, locator)?;
        if interactions
            .iter()
            .any(|i| i.name() == entry.name.get_ref())
        {
            return Err(at(
                entry.name.span(),
                format!(
                    "'{}' names an interaction already: strands and interactions need \
                     different names",
                    entry.name.get_ref()
                ),
            ));
        }
        interactions.push(InteractionModel::Strands(Box::new(strands)));
    }

    // Step.
    let step = step_settings(
        scene,
        &mesh,
        &parts,
        !interactions.is_empty(),
        &rigid_bodies,
        locator,
    )?;
    Ok(Model {
        description: scene.description.clone(),
        mesh,
        parts,
        part_names,
        material_names,
        loads,
        displacement_names,
        analysis: step.analysis,
        solver_rationale: step.solver_rationale,
        output_interval: step.output_interval,
        frame_interval: step.frame_interval,
        write_frames: scene.output.frames.unwrap_or(true),
        von_mises_percentile: match &scene.output.von_mises_percentile {
            Some(p) if !(*p.get_ref() > 0.0 && *p.get_ref() < 100.0) => {
                return Err(locator.error(
                    p.span(),
                    format!(
                        "von_mises_percentile = {} must be in (0, 100) (95: the paper's peak \
                         stress)",
                        p.get_ref()
                    ),
                ));
            }
            Some(p) => Some(*p.get_ref()),
            None => None,
        },
        interactions,
        rigid_bodies,
        unchecked_plugins,
        activation_histories,
        part_notes,
    })
}

/// value × the named amplitude (or a constant without a name).
type ScaledAmplitude<'a> =
    dyn Fn(&Option<Spanned<String>>, f64) -> Result<Amplitude, SceneError> + 'a;

/// The motion of a rigid tie or body: `translation` [m] times its amplitude, and a
/// rotation about an axis.
fn rigid_motion(
    (translation, translation_amplitude, rotation): PrescribedMotion<'_>,
    scaled: &ScaledAmplitude<'_>,
    locator: &Locator,
) -> Result<RigidMotion, SceneError> {
    let mut amplitudes = [None, None, None];
    for (k, value) in translation.iter().enumerate() {
        if *value != 0.0 || translation_amplitude.is_some() {
            amplitudes[k] = Some(scaled(translation_amplitude, *value)?);
        }
    }
    let rotation = match rotation {
        None => None,
        Some(r) => {
            let axis = Vector3::from(*r.axis.get_ref());
            if !(axis.norm() > 0.0 && axis.iter().all(|x| x.is_finite())) {
                return Err(locator.error(r.axis.span(), "the rotation axis must be non-zero"));
            }
            Some(RigidRotation {
                center: Vector3::from(r.center),
                axis: Unit::new_normalize(axis),
                angle: scaled(&r.amplitude, r.angle_degrees.to_radians())?,
            })
        }
    };
    Ok(RigidMotion {
        translation: amplitudes,
        rotation,
        follower: None,
    })
}

/// The element technology a part names. The one-point hex8's hourglass modulus follows
/// the material's small-strain shear modulus ([`small_strain_shear_modulus`]).
fn technology(
    entry: &PartEntry,
    material: &dyn Material,
    locator: &Locator,
) -> Result<Technology, SceneError> {
    let name = entry.element.get_ref().as_str();
    let Some(kind) = ElementKind::from_name(name) else {
        return Err(locator.error(
            entry.element.span(),
            format!(
                "unknown element '{name}'{}; known: {}",
                suggestion(name, ELEMENT_NAMES),
                ELEMENT_NAMES.join(", ")
            ),
        ));
    };
    element_technology(kind, material)
        .map_err(|reason| locator.error(entry.material.span(), reason))
}

/// The technology of `kind` for parts of `material`: the one-point hex8's hourglass
/// modulus scales with the material's small-strain shear modulus
/// ([`small_strain_shear_modulus`], evaluated only for it).
pub fn element_technology(
    kind: ElementKind,
    material: &dyn Material,
) -> Result<Technology, &'static str> {
    let shear_modulus = match kind {
        ElementKind::Hex8OnePoint => small_strain_shear_modulus(material),
        _ => None,
    };
    kind.technology(shear_modulus)
}

fn component_index(component: &str) -> Option<usize> {
    match component {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

fn bad_component(component: &str) -> String {
    format!("unknown component '{component}': use \"x\", \"y\" or \"z\"")
}
