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
use musclefem_core::solver::bulk_viscosity::BulkViscosity;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::{ImplicitSettings, Newmark};
use musclefem_core::solver::{
    Loads, NodalForce, Part, PrescribedDisplacement, RigidMotion, RigidRotation, RigidTie,
};
use musclefem_materials::{ActivationHistory, Amplitude, Material, MaterialLibrary};

use super::activation::{activation_history, driven_material};
use super::error::{Locator, SceneError, suggestion};
use super::format::{AmplitudeEntry, PartEntry, RotationEntry, SceneFile};
use super::interactions::{InteractionModel, build_interactions, rigid_body};
use super::locking::small_strain_shear_modulus;
use super::part_mesh::{append_part, part_mesh};
use super::solver_choice::{AutoSolver, choose_solver};
use super::trust::PluginPolicy;

/// The Hill muscle's activation parameters, which a part's recorded activation replaces.
const ACTIVATION_PARAMETERS: [&str; 5] = ["n1", "n2", "t0", "t1", "S"];

/// Element technologies by scene name ([`ElementKind::NAMES`]).
pub const ELEMENT_NAMES: [&str; 6] = ElementKind::NAMES;

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
    let mut material_names: Vec<String> = Vec::new();
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
        let part_mesh = part_mesh(entry, technology.shape(), locator)?;
        append_part(&mut mesh, part_mesh, name);
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
    let mut amplitudes: BTreeMap<String, &AmplitudeEntry> = BTreeMap::new();
    for entry in &scene.amplitudes {
        let name = entry.name.get_ref();
        let points = entry.points.get_ref();
        if let Some(k) = points.iter().position(|p| p.len() != 2) {
            return Err(at(
                entry.points.span(),
                format!(
                    "amplitude '{name}': knot {} has {} values; a knot is [time, value]",
                    k + 1,
                    points[k].len()
                ),
            ));
        }
        Amplitude::new(points.iter().map(|p| (p[0], p[1])).collect())
            .map_err(|e| at(entry.points.span(), format!("amplitude '{name}': {}", e.0)))?;
        if amplitudes.insert(name.clone(), entry).is_some() {
            return Err(at(
                entry.name.span(),
                format!("amplitude '{name}' is defined twice"),
            ));
        }
    }
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
            Some(name) => {
                let entry = amplitudes.get(name.get_ref()).ok_or_else(|| {
                    at(
                        name.span(),
                        format!(
                            "unknown amplitude '{}'{}",
                            name.get_ref(),
                            suggestion(name.get_ref(), amplitudes.keys().map(String::as_str))
                        ),
                    )
                })?;
                entry
                    .points
                    .get_ref()
                    .iter()
                    .map(|p| (p[0], value * p[1]))
                    .collect()
            }
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
    for entry in &scene.rigid_ties {
        let nodes = node_set(&entry.part, &entry.nodes)?;
        loads.rigid_ties.push(RigidTie {
            name: entry.name.get_ref().clone(),
            nodes,
            motion: rigid_motion(
                &entry.translation,
                &entry.translation_amplitude,
                &entry.rotation,
                &scaled,
                locator,
            )?,
        });
    }

    // Rigid bodies and interactions.
    let mut rigid_bodies = Vec::with_capacity(scene.rigid_bodies.len());
    for entry in &scene.rigid_bodies {
        let motion = rigid_motion(
            &entry.translation,
            &entry.translation_amplitude,
            &entry.rotation,
            &scaled,
            locator,
        )?;
        rigid_bodies.push(rigid_body(entry, motion, locator)?);
    }
    let interactions = build_interactions(
        &scene.interactions,
        &rigid_bodies,
        &mesh,
        &parts,
        &part_names,
        locator,
    )?;

    // Step.
    let step = &scene.step;
    let duration = *step.duration.get_ref();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(at(
            step.duration.span(),
            format!("duration {duration} s must be positive"),
        ));
    }
    let output_interval = match &step.output_interval {
        Some(v) if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) => {
            return Err(at(
                v.span(),
                format!("output_interval {} s must be positive", v.get_ref()),
            ));
        }
        Some(v) => *v.get_ref(),
        None => duration / 100.0,
    };
    let frame_interval = match &scene.output.frame_interval {
        Some(v) if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) => {
            return Err(at(
                v.span(),
                format!("frame_interval {} s must be positive", v.get_ref()),
            ));
        }
        Some(v) => *v.get_ref(),
        None => output_interval,
    };
    let solver_span = step
        .solver
        .as_ref()
        .map_or(step.duration.span(), |s| s.span());
    let (solver, solver_rationale) = match step.solver.as_ref().map(|s| s.get_ref().as_str()) {
        None | Some("auto") => {
            let (solver, why) = choose_solver(&mesh, &parts, duration, !interactions.is_empty());
            (solver, Some(why))
        }
        Some("explicit") => (AutoSolver::Explicit, None),
        Some("implicit") => (AutoSolver::Implicit { dynamic: false }, None),
        Some(other) => {
            return Err(at(
                solver_span,
                format!(
                    "unknown solver '{other}'{}; use auto, explicit or implicit",
                    suggestion(other, ["auto", "explicit", "implicit"])
                ),
            ));
        }
    };
    // Every setting the file gives is checked, whichever solver runs (`run --solver` may
    // switch it): `check` refuses what `run` would.
    let in_range = |value: &Option<Spanned<f64>>,
                    key: &str,
                    what: &str,
                    accepts: fn(f64) -> bool|
     -> Result<(), SceneError> {
        match value {
            Some(v) if !accepts(*v.get_ref()) => Err(at(
                v.span(),
                format!("{key} = {} must be {what}", v.get_ref()),
            )),
            _ => Ok(()),
        }
    };
    let explicit = &step.explicit;
    in_range(
        &explicit.safety_factor,
        "safety_factor",
        "in (0, 1] (a fraction of the stable time step)",
        |x| x > 0.0 && x <= 1.0,
    )?;
    in_range(
        &explicit.mass_scaling_time_step,
        "mass_scaling_time_step",
        "a positive time [s]",
        |x| x.is_finite() && x > 0.0,
    )?;
    in_range(
        &explicit.energy_tolerance,
        "energy_tolerance",
        "a positive fraction of the largest energy",
        |x| x.is_finite() && x > 0.0,
    )?;
    in_range(
        &step.implicit.residual_tolerance,
        "residual_tolerance",
        "in (0, 1) (relative to the first residual)",
        |x| x > 0.0 && x < 1.0,
    )?;
    let analysis = match solver {
        AutoSolver::Explicit => {
            let mut settings = ExplicitSettings::new(duration);
            settings.history_interval = output_interval;
            let e = &step.explicit;
            if let Some(v) = &e.safety_factor {
                settings.safety_factor = *v.get_ref();
            }
            settings.mass_scaling_time_step =
                e.mass_scaling_time_step.as_ref().map(|v| *v.get_ref());
            if let Some(v) = &e.energy_tolerance {
                settings.energy_tolerance = *v.get_ref();
            }
            settings.bulk_viscosity = e.bulk_viscosity.then(BulkViscosity::default);
            Analysis::Explicit(settings)
        }
        AutoSolver::Implicit { dynamic } => {
            let i = &step.implicit;
            let increments = i.increments.as_ref().map_or(10, |v| *v.get_ref());
            if increments == 0 {
                let span = i.increments.as_ref().map_or(solver_span, |v| v.span());
                return Err(at(span, "increments must be at least 1".to_string()));
            }
            let mut settings = ImplicitSettings::new(duration, increments);
            if i.step_cutting.unwrap_or(true) {
                settings = settings.with_cutting();
            }
            if let Some(v) = &i.residual_tolerance {
                settings.residual_tolerance = *v.get_ref();
            }
            if i.dynamic || dynamic {
                settings.dynamics = Some(Newmark::default());
            }
            Analysis::Implicit(settings)
        }
    };
    Ok(Model {
        description: scene.description.clone(),
        mesh,
        parts,
        part_names,
        material_names,
        loads,
        displacement_names,
        analysis,
        solver_rationale,
        output_interval,
        frame_interval,
        write_frames: scene.output.frames.unwrap_or(true),
        interactions,
        rigid_bodies,
        unchecked_plugins,
        activation_histories,
    })
}

/// value × the named amplitude (or a constant without a name).
type ScaledAmplitude<'a> =
    dyn Fn(&Option<Spanned<String>>, f64) -> Result<Amplitude, SceneError> + 'a;

/// The motion of a rigid tie or body: `translation` [m] times its amplitude, and a
/// rotation about an axis.
fn rigid_motion(
    translation: &[f64; 3],
    translation_amplitude: &Option<Spanned<String>>,
    rotation: &Option<RotationEntry>,
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
