//! `[[rigid_bodies]]` and `[[interactions]]` of a scene: rigid triangle surfaces with a
//! prescribed motion, and contact or cohesion of a part's surface against a rigid body or
//! another part's surface (built by `musclefem-contact`). The scene's `[[strands]]`
//! (`strands.rs`) join them as [`InteractionModel::Strands`].

use nalgebra::Vector3;
use toml::Spanned;

use musclefem_contact::{
    CohesiveInterface, CohesiveSettings, ContactTarget, PenaltyContact, RigidSurface,
    TangentialMode, TendonStrands,
};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{Interaction, Part, RigidMotion};

use super::error::{Locator, SceneError, suggestion};
use super::format::{InteractionEntry, RigidBodyEntry};
use super::interaction_surfaces::{
    PartSurface, default_node_penalties, faces_in_band, part_surfaces,
};

/// Subdivisions of a generated rigid surface by default.
const DEFAULT_DIVISIONS: usize = 16;

/// One interaction of a scene, ready to hand to a solver.
#[derive(Debug, Clone)]
pub enum InteractionModel {
    /// Penalty contact (boxed: it carries its broadphase).
    Contact(Box<PenaltyContact>),
    /// Cohesive traction–separation with damage.
    Cohesive(Box<CohesiveInterface>),
    /// Tendon strands between pairs of nodes (a scene's `[[strands]]`).
    Strands(Box<TendonStrands>),
}

impl InteractionModel {
    /// A fresh copy for a solver (each run starts from the undamaged state).
    pub fn boxed(&self) -> Box<dyn Interaction> {
        match self {
            InteractionModel::Contact(c) => c.clone(),
            InteractionModel::Cohesive(c) => c.clone(),
            InteractionModel::Strands(s) => s.clone(),
        }
    }

    /// One line on the interaction: its name, kind, surfaces and law.
    pub fn describe(&self) -> String {
        match self {
            InteractionModel::Contact(c) => format!(
                "'{}': penalty contact of '{}' ({} nodes) on '{}', ε = {:.3e} N/m³{}",
                c.name(),
                c.secondary().name,
                c.secondary().nodes.len(),
                c.target().name(),
                c.penalty(),
                if c.smooth_normals() {
                    ", along smooth normals"
                } else {
                    ""
                }
            ),
            InteractionModel::Cohesive(c) => {
                let (secondary, main) = c.surfaces();
                format!(
                    "'{}': cohesive bond of '{secondary}' on '{main}', {} bonds over {:.3e} m²",
                    c.name(),
                    c.bond_count(),
                    c.bonded_reference_area()
                )
            }
            InteractionModel::Strands(s) => {
                let strands = s.strands();
                let stiffness: f64 = strands.iter().map(|s| s.strain_stiffness).sum();
                let (shortest, longest) = strands.iter().fold((f64::INFINITY, 0.0), |(a, b), s| {
                    (a.min(s.slack_length), f64::max(b, s.slack_length))
                });
                format!(
                    "'{}': {} tendon strands, E A = {stiffness:.3e} N in all, slack lengths \
                     {shortest:.3e}–{longest:.3e} m",
                    s.name(),
                    strands.len()
                )
            }
        }
    }

    /// The interaction's name.
    pub fn name(&self) -> &str {
        match self {
            InteractionModel::Contact(c) => c.name(),
            InteractionModel::Cohesive(c) => c.name(),
            InteractionModel::Strands(s) => s.name(),
        }
    }
}

/// The rigid surface of `entry`, moving with `motion`.
pub(super) fn rigid_body(
    entry: &RigidBodyEntry,
    motion: RigidMotion,
    locator: &Locator,
) -> Result<RigidSurface, SceneError> {
    let name = entry.name.get_ref();
    let surface = entry.surface.get_ref();
    let span = entry.surface.span();
    let at =
        |message: String| locator.error(span.clone(), format!("rigid body '{name}': {message}"));
    let need = |value: Option<f64>, key: &str| {
        value.ok_or_else(|| at(format!("this shape needs `{key}`")))
    };
    let need3 = |value: Option<[f64; 3]>, key: &str| {
        value
            .map(Vector3::from)
            .ok_or_else(|| at(format!("this shape needs `{key}`")))
    };
    let divisions = surface.divisions.unwrap_or(DEFAULT_DIVISIONS);
    let built = match (&surface.file, &surface.shape) {
        (Some(file), None) => {
            let scale = match surface.units.as_ref().map(|u| (u.get_ref().as_str(), u)) {
                None | Some(("m", _)) => 1.0,
                Some(("mm", _)) => 1e-3,
                Some((other, units)) => {
                    return Err(locator.error(
                        units.span(),
                        format!(
                            "rigid body '{name}': units = \"{other}\": the surface file's \
                             length unit is \"m\" or \"mm\""
                        ),
                    ));
                }
            };
            let path = locator.resolve(file.span(), file.get_ref())?;
            let lower = file.get_ref().to_ascii_lowercase();
            if lower.ends_with(".stl") {
                RigidSurface::from_stl(&path)
            } else if lower.ends_with(".obj") {
                RigidSurface::from_obj(&path)
            } else {
                return Err(locator.error(
                    file.span(),
                    format!(
                        "rigid body '{name}': '{}' is neither .stl nor .obj",
                        file.get_ref()
                    ),
                ));
            }
            .map(|mut surface| {
                surface.name = name.clone();
                surface.vertices.iter_mut().for_each(|x| *x *= scale);
                surface
            })
        }
        (None, Some(_)) if surface.units.is_some() => {
            let units = surface.units.as_ref().map_or(0..0, Spanned::span);
            return Err(locator.error(
                units,
                format!(
                    "rigid body '{name}': `units` is the unit of a surface file's \
                     coordinates; a generated shape's sizes and positions are in m"
                ),
            ));
        }
        (None, Some(shape)) => match shape.get_ref().as_str() {
            "plane" => RigidSurface::plane(
                name,
                need3(surface.point, "point")?,
                need3(surface.normal, "normal")?,
                need(surface.half_size, "half_size")?,
                divisions,
            ),
            "sphere" => RigidSurface::sphere(
                name,
                need3(surface.center, "center")?,
                need(surface.radius, "radius")?,
                (divisions as f64).log2().ceil().max(1.0) as u32,
            ),
            "cylinder" => RigidSurface::cylinder(
                name,
                need3(surface.center, "center")?,
                need3(surface.axis, "axis")?,
                need(surface.radius, "radius")?,
                2.0 * need(surface.half_length, "half_length")?,
                [4 * divisions, divisions],
            ),
            other => {
                return Err(locator.error(
                    shape.span(),
                    format!(
                        "rigid body '{name}': unknown shape '{other}'{}; use plane, sphere or \
                         cylinder",
                        suggestion(other, ["plane", "sphere", "cylinder"])
                    ),
                ));
            }
        },
        _ => return Err(at("give either `shape` or `file`".to_string())),
    };
    built
        .map(|s| s.with_motion(motion))
        .map_err(|e| at(e.to_string()))
}

/// The interactions of the scene, with their surfaces taken from `mesh` (part surfaces
/// are named "PART.SURFACE"; a list of them is one surface) and `rigid_bodies`.
pub(super) fn build_interactions(
    entries: &[InteractionEntry],
    rigid_bodies: &[RigidSurface],
    mesh: &Mesh,
    parts: &[Part],
    part_names: &[String],
    locator: &Locator,
) -> Result<Vec<InteractionModel>, SceneError> {
    let mut built: Vec<InteractionModel> = Vec::with_capacity(entries.len());
    for entry in entries {
        let name = entry.name.get_ref();
        if built.iter().any(|b| b.name() == name) {
            return Err(locator.error(
                entry.name.span(),
                format!("interaction '{name}' is defined twice"),
            ));
        }
        let at = |span: std::ops::Range<usize>, message: String| {
            locator.error(span, format!("interaction '{name}': {message}"))
        };
        let secondary = part_surfaces(&entry.secondary, mesh, part_names, locator)?;
        let main = main_surface(entry, rigid_bodies, mesh, part_names, locator)?;
        let model = match entry.kind.get_ref().as_str() {
            "contact" => {
                refuse(entry, &COHESIVE_KEYS, "contact", locator)?;
                let PartSurface {
                    parts: surface_parts,
                    surface,
                } = secondary;
                // One penalty for every node, or the lowest and each node's own.
                let (penalty, node_penalties) = match &entry.penalty_stiffness {
                    Some(p) => (*p.get_ref(), None),
                    None => {
                        let each = default_node_penalties(
                            entry,
                            &surface,
                            &surface_parts,
                            parts,
                            mesh,
                            locator,
                        )?;
                        let lowest = each.iter().copied().fold(f64::INFINITY, f64::min);
                        let uniform = each.iter().all(|&p| p == lowest);
                        (lowest, (!uniform).then_some(each))
                    }
                };
                if let Some(friction) = &entry.friction
                    && *friction.get_ref() != 0.0
                {
                    return Err(at(
                        friction.span(),
                        "friction is not built yet: contact is frictionless".to_string(),
                    ));
                }
                let smooth = entry.smooth_normals.as_ref().is_some_and(|s| *s.get_ref());
                let contact = PenaltyContact::new(name, surface, main, penalty)
                    .and_then(|c| match node_penalties {
                        Some(each) => c.with_node_penalties(each),
                        None => Ok(c),
                    })
                    .map_err(|e| at(entry.kind.span(), e.to_string()))?;
                let contact = if smooth {
                    contact.with_smooth_normals()
                } else {
                    contact
                };
                InteractionModel::Contact(Box::new(contact))
            }
            "cohesive" => {
                refuse(entry, &CONTACT_KEYS, "cohesive", locator)?;
                let settings = cohesive_settings(entry, locator)?;
                let bonding = match &entry.bond_band {
                    Some(band) => faces_in_band(entry, &secondary.surface, band, mesh, locator)?,
                    None => secondary.surface,
                };
                let interface = CohesiveInterface::new(name, &bonding, main, mesh, &settings)
                    .map_err(|e| at(entry.kind.span(), e.to_string()))?;
                if let Some(minimum) = &entry.minimum_bonds {
                    check_minimum_bonds(&interface, minimum, locator)?;
                }
                InteractionModel::Cohesive(Box::new(interface))
            }
            other => {
                return Err(at(
                    entry.kind.span(),
                    format!(
                        "unknown kind '{other}'{}; use contact or cohesive",
                        suggestion(other, ["contact", "cohesive"])
                    ),
                ));
            }
        };
        built.push(model);
    }
    Ok(built)
}

/// The main surface of `entry`: a rigid body by its name, or part surfaces.
fn main_surface(
    entry: &InteractionEntry,
    rigid_bodies: &[RigidSurface],
    mesh: &Mesh,
    part_names: &[String],
    locator: &Locator,
) -> Result<ContactTarget, SceneError> {
    let listed = entry.main.get_ref().names();
    if let [one] = listed.as_slice() {
        if let Some(body) = rigid_bodies.iter().find(|b| b.name == *one) {
            return Ok(ContactTarget::Rigid(body.clone()));
        }
        if !one.contains('.') {
            let known: Vec<&str> = rigid_bodies.iter().map(|b| b.name.as_str()).collect();
            return Err(locator.error(
                entry.main.span(),
                format!(
                    "interaction '{}': main '{one}' is neither a rigid body{} nor a part \
                     surface \"PART.SURFACE\"",
                    entry.name.get_ref(),
                    suggestion(one, known.iter().copied())
                ),
            ));
        }
    }
    let main = part_surfaces(&entry.main, mesh, part_names, locator)?;
    Ok(ContactTarget::Deformable(main.surface))
}

/// Errors unless `interface` has at least `minimum` bonds.
fn check_minimum_bonds(
    interface: &CohesiveInterface,
    minimum: &Spanned<usize>,
    locator: &Locator,
) -> Result<(), SceneError> {
    let name = interface.name();
    if *minimum.get_ref() == 0 {
        return Err(locator.error(
            minimum.span(),
            format!("interaction '{name}': minimum_bonds must be at least 1"),
        ));
    }
    if interface.bond_count() < *minimum.get_ref() {
        return Err(locator.error(
            minimum.span(),
            format!(
                "interaction '{name}': {} secondary nodes bonded, fewer than minimum_bonds = \
                 {}; leave the interaction out, or widen bond_tolerance or bond_band",
                interface.bond_count(),
                minimum.get_ref()
            ),
        ));
    }
    Ok(())
}

/// Keys that only a contact takes.
const CONTACT_KEYS: [&str; 3] = ["penalty_stiffness", "friction", "smooth_normals"];
/// Keys that only a cohesive interface takes.
const COHESIVE_KEYS: [&str; 8] = [
    "normal_stiffness",
    "shear_stiffness",
    "initiation_separation",
    "failure_separation",
    "tangential",
    "bond_tolerance",
    "bond_band",
    "minimum_bonds",
];

/// Errors if `entry` sets one of `keys`, which a `kind` interaction does not take.
fn refuse(
    entry: &InteractionEntry,
    keys: &[&str],
    kind: &str,
    locator: &Locator,
) -> Result<(), SceneError> {
    let given: [(&str, Option<std::ops::Range<usize>>); 11] = [
        (
            "penalty_stiffness",
            entry.penalty_stiffness.as_ref().map(Spanned::span),
        ),
        ("friction", entry.friction.as_ref().map(Spanned::span)),
        (
            "smooth_normals",
            entry.smooth_normals.as_ref().map(Spanned::span),
        ),
        (
            "normal_stiffness",
            entry.normal_stiffness.as_ref().map(Spanned::span),
        ),
        (
            "shear_stiffness",
            entry.shear_stiffness.as_ref().map(Spanned::span),
        ),
        (
            "initiation_separation",
            entry.initiation_separation.as_ref().map(Spanned::span),
        ),
        (
            "failure_separation",
            entry.failure_separation.as_ref().map(Spanned::span),
        ),
        ("tangential", entry.tangential.as_ref().map(Spanned::span)),
        (
            "bond_tolerance",
            entry.bond_tolerance.as_ref().map(Spanned::span),
        ),
        ("bond_band", entry.bond_band.as_ref().map(Spanned::span)),
        (
            "minimum_bonds",
            entry.minimum_bonds.as_ref().map(Spanned::span),
        ),
    ];
    for (key, span) in given {
        if let (true, Some(span)) = (keys.contains(&key), span) {
            return Err(locator.error(
                span,
                format!(
                    "interaction '{}': `{key}` does not apply to kind = \"{kind}\"",
                    entry.name.get_ref()
                ),
            ));
        }
    }
    Ok(())
}

/// The cohesive settings of `entry`: the paper's defaults with the keys it gives.
fn cohesive_settings(
    entry: &InteractionEntry,
    locator: &Locator,
) -> Result<CohesiveSettings, SceneError> {
    let mut settings = CohesiveSettings::default();
    let value =
        |v: &Option<Spanned<f64>>, default: f64| v.as_ref().map_or(default, |v| *v.get_ref());
    settings.normal_stiffness = value(&entry.normal_stiffness, settings.normal_stiffness);
    settings.shear_stiffness = value(&entry.shear_stiffness, settings.shear_stiffness);
    settings.tangential_stiffness = settings.shear_stiffness;
    settings.initiation_separation =
        value(&entry.initiation_separation, settings.initiation_separation);
    settings.failure_separation = value(
        &entry.failure_separation,
        2.0 * settings.initiation_separation,
    );
    settings.bond_tolerance = value(&entry.bond_tolerance, settings.bond_tolerance);
    if let Some(mode) = &entry.tangential {
        settings.tangential = match mode.get_ref().as_str() {
            "elastic" => TangentialMode::Elastic,
            "free-slide" => TangentialMode::FreeSlide,
            "smooth-slide" => TangentialMode::SmoothSlide,
            other => {
                return Err(locator.error(
                    mode.span(),
                    format!(
                        "interaction '{}': unknown tangential mode '{other}'{}; use elastic, \
                         free-slide or smooth-slide",
                        entry.name.get_ref(),
                        suggestion(other, ["elastic", "free-slide", "smooth-slide"])
                    ),
                ));
            }
        };
    }
    settings
        .validate(entry.name.get_ref())
        .map_err(|e| locator.error(entry.kind.span(), e.to_string()))?;
    Ok(settings)
}
