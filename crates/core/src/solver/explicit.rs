//! Explicit central-difference time integration with lumped mass (the paper's method).
//!
//! With M the lumped (diagonal) mass, f the internal nodal forces and half-step velocities:
//! - v^{n+½} = v^{n−½} + Δt^n M⁻¹ (f_ext^n − f^n), Δt^n = ½ (Δt^{n−½} + Δt^{n+½});
//! - u^{n+1} = u^n + Δt^{n+½} v^{n+½};
//! - prescribed displacement components (and nodes tied to a rigid body with prescribed
//!   motion) take v^{n+½} = (ū(t^{n+1}) − u^n)/Δt^{n+½};
//! - nodal forces enter as f_ext^n, dead loads at t^n.
//!
//! The step is Δt = safety × min over elements of L₀ √(ρ₀/M): total Lagrangian, so the
//! reference characteristic length L₀ (Flanagan–Belytschko bound from the element's mean
//! shape-function gradients, h/√3 for a cube of side h) and density ρ₀ with the current
//! acoustic modulus M, the largest eigenvalue of the acoustic tensor
//! Q_ik = ∂P_iJ/∂F_kL n_J n_L over n = e_x, e_y, e_z at the element's first integration
//! point, refreshed from the material tangent every [`MODULUS_REFRESH_INTERVAL`] steps.
//! Stiffening in between is covered by the safety factor and, should it not suffice,
//! caught by the energy balance.
//!
//! Energies (trapezoidal rule over each step): internal W_int = Σ ½(f^{n−1} + f^n)·Δu,
//! external W_ext = Σ ½(R^{n−1} + R^n + f_ext^{n−1} + f_ext^n)·Δu, with the reaction
//! R = f − f_ext + M a on the prescribed components (zero elsewhere); kinetic
//! K = ½ Σ m |v^n|², v^n = ½ (v^{n−½} + v^{n+½}).
//! The total W_int + W_visc + K − W_ext must stay at its value after the first step within a
//! fraction of the largest energy reached so far, or within 10× the largest energy of the
//! first [`STARTUP_STEPS`] steps. The second allowance covers the start-up error: K at
//! whole steps from averaged half-step velocities differs from the work done by about
//! ⅛ Σ m |a Δt|², which dominates while the energies are small (a load ramped from zero
//! gives almost none for many steps); an instability grows past both quickly. The same
//! error dominates a whole phase in which nothing moves (an activated muscle held at
//! both ends: energies of 10⁻¹⁰ J from round-off-sized motions), so the fraction is taken
//! of at least the energy scale Σ_e ½ M_e V_e ε² with ε = [`ENERGY_SCALE_STRAIN`]: the
//! model's strain energy at a strain of 10⁻⁴ under its initial acoustic moduli, far
//! below any solution worth checking and far below where an instability ends.
//!
//! A [`crate::element::Technology::Tet4NodalAverage`] block couples neighbouring elements through nodal
//! averages, so it is evaluated in passes over the whole block (`nodal_average.rs`) rather
//! than element by element; its mass and stable step are those of the plain tet4.
//!
//! The hourglass forces of the one-point hex8 are part of its internal forces, so their
//! work is in W_int (`BlockKernel::hourglass_energy` gives it per element; the history does
//! not report it separately yet).
//!
//! Mass scaling ([`ExplicitSettings::mass_scaling_time_step`]): at the start, every element
//! whose stable step (× safety) is below the target gets its density raised to
//! ρ_e = ρ₀ (Δt_target / Δt_e)², so that its step reaches the target; the added mass is
//! lumped like the rest and reported as a fraction of the physical mass. Stiffening later
//! in the run can still bring the step below the target (the step always follows the
//! stability limit). Mass scaling adds inertia: check the kinetic energy stays small
//! against the internal energy in a quasi-static run. The kinetic energy does not see the
//! added mass's inertia where a moving body carries the model and turns (at the bottom of
//! a squat the velocity is zero and the acceleration largest):
//! [`ExplicitSettings::mass_scaling_frame`] gives the added mass the carrier's
//! acceleration as a body force ([`super::added_mass_frame`]).
//!
//! Bulk viscosity ([`ExplicitSettings::bulk_viscosity`], off by default): see
//! [`super::bulk_viscosity`]; its dissipated work is the viscous energy W_visc, and the
//! balance becomes W_int + W_visc + K − W_ext = const. The shear viscosity
//! ([`ExplicitSettings::shear_viscosity`], off by default) adds its forces and work to the
//! same terms, and its damping to the stable step's factor.
//!
//! The history also reports the hourglass energy of the one-point hex8 (Σ ½ k |q|², part of
//! W_int, recorded with each row).

use nalgebra::Vector3;

use super::added_mass_frame::AddedMassFrame;
use super::bulk_viscosity::{BulkViscosity, Viscosities, damped_step_factor};
use super::checkpoint::{Checkpoint, CheckpointReader, CheckpointWriter};
use super::element_fields::PartFields;
use super::explicit_parts::{
    PartRun, hourglass_energy, internal_forces, scale_masses, smallest_impedance_length,
    smallest_stable_step, viscous_forces,
};
pub use super::explicit_settings::{ExplicitSettings, MAX_EXPLICIT_STEPS, MIN_MASS_SCALED_STEPS};
use super::explicit_settings::{check_settings, check_step_budget};
use super::interaction::{Interaction, InteractionReport, all_nodal_fields, interaction_forces};
use super::nodal::{advance_positions, deterministic_sum, update_velocities};
use super::observer::{NoObserver, Observer, Record, Snapshot};
use super::rigid_motion::{observe_followers, restore_follower_states, save_follower_states};
use super::{Loads, Part, RigidReaction, SolverError};
use crate::mesh::Mesh;

/// One recorded instant of an explicit run.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryRow {
    /// Time [s].
    pub time: f64,
    /// Step taken to reach it [s].
    pub time_step: f64,
    /// Reaction force of each prescribed displacement, in its direction, summed over its
    /// nodes [N].
    pub reactions: Vec<f64>,
    /// Resultant reaction force and moment of each rigid tie.
    pub rigid_reactions: Vec<RigidReaction>,
    /// Internal (strain) energy W_int [J].
    pub internal_energy: f64,
    /// Of the internal energy, the hourglass energy of one-point hex8 elements [J].
    pub hourglass_energy: f64,
    /// Work dissipated by bulk viscosity W_visc [J].
    pub viscous_energy: f64,
    /// Kinetic energy K [J].
    pub kinetic_energy: f64,
    /// External work W_ext [J].
    pub external_work: f64,
    /// Work of the interaction forces W_c = Σ ½(f_c^{n−1} + f_c^n)·Δu [J] (see
    /// [`super::interaction`]).
    pub interaction_work: f64,
    /// Totals of each interaction, in the order given.
    pub interactions: Vec<InteractionReport>,
}

/// What an explicit run returns.
#[derive(Debug, Clone)]
pub struct ExplicitResult {
    pub history: Vec<HistoryRow>,
    /// Nodal displacements at the end [m].
    pub displacement: Vec<Vector3<f64>>,
    /// Time steps taken.
    pub steps: usize,
    /// Mass added by mass scaling over the physical mass (0 without mass scaling).
    pub added_mass_fraction: f64,
}

/// Steps over which the energy balance measures its start-up allowance.
pub const STARTUP_STEPS: usize = 20;

/// The strain of the energy balance's floor (module documentation): energies below the
/// model's strain energy at this strain under its initial acoustic moduli are noise.
pub const ENERGY_SCALE_STRAIN: f64 = 1e-4;

/// Steps between refreshes of the elements' acoustic moduli (stable step).
pub const MODULUS_REFRESH_INTERVAL: usize = 10;

/// Run the explicit solver on `mesh` with `parts` under `loads`.
pub fn run_explicit(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    settings: &ExplicitSettings,
) -> Result<ExplicitResult, SolverError> {
    run_explicit_observed(mesh, parts, loads, settings, &mut NoObserver)
}

/// [`run_explicit`], showing `observer` every history row and every step.
pub fn run_explicit_observed(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    settings: &ExplicitSettings,
    observer: &mut dyn Observer,
) -> Result<ExplicitResult, SolverError> {
    run_explicit_with(mesh, parts, loads, &mut [], settings, observer)
}

/// [`run_explicit_observed`] with `interactions` (contact, cohesion) adding their forces:
/// searched, evaluated and committed once per step.
pub fn run_explicit_with(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    interactions: &mut [Box<dyn Interaction>],
    settings: &ExplicitSettings,
    observer: &mut dyn Observer,
) -> Result<ExplicitResult, SolverError> {
    explicit_run(mesh, parts, loads, interactions, settings, observer, None)
}

/// [`run_explicit_with`], started from `from` (a checkpoint of the same problem) when
/// given: the result's history then holds the rows after the checkpoint only.
pub(super) fn explicit_run(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    interactions: &mut [Box<dyn Interaction>],
    settings: &ExplicitSettings,
    observer: &mut dyn Observer,
    from: Option<&Checkpoint>,
) -> Result<ExplicitResult, SolverError> {
    check_settings(settings)?;
    let node_count = mesh.nodes.len();
    let mut runs = Vec::with_capacity(parts.len());
    let mut mass = vec![0.0; node_count];
    for part in parts {
        runs.push(PartRun::new(
            mesh,
            part,
            &mut mass,
            settings.has_viscosity(),
        )?);
    }
    loads.validate(node_count)?;
    // A node without mass (in no element, e.g. one end of tendon strands carried by a
    // rigid tie) is allowed when all its components are prescribed: its motion is given.
    let constrained = loads.constrained_components(node_count);
    let unheld = |n: usize| constrained[3 * n..3 * n + 3].contains(&false);
    if let Some(n) = (0..node_count).find(|&n| mass[n] <= 0.0 && unheld(n)) {
        return Err(SolverError::InvalidPart {
            block: parts.first().map_or(0, |p| p.block),
            reason: format!(
                "node {n} belongs to no element of any part and is not held in every \
                 component: it has no mass"
            ),
        });
    }

    let reference: Vec<Vector3<f64>> = (0..node_count).map(|i| mesh.nodes.position(i)).collect();
    let mut displacement = vec![Vector3::zeros(); node_count];
    let mut positions = reference.clone();
    let mut velocity = vec![Vector3::zeros(); node_count];
    let mut old_velocity = vec![Vector3::zeros(); node_count];
    let mut force = vec![Vector3::zeros(); node_count];
    let mut previous_force = vec![Vector3::zeros(); node_count];
    let mut viscous_force = vec![Vector3::zeros(); node_count];
    let mut previous_viscous_force = vec![Vector3::zeros(); node_count];
    let mut interaction_force = vec![Vector3::zeros(); node_count];
    let mut previous_interaction_force = vec![Vector3::zeros(); node_count];
    let viscosities = Viscosities {
        bulk: settings.bulk_viscosity,
        shear: settings.shear_viscosity.unwrap_or(0.0),
    };
    let mut previous_displacement = vec![Vector3::zeros(); node_count];
    // Constrained degrees of freedom 3 node + component, their targets ū, the nodal
    // reactions R (zero on free components) and the external forces.
    let held: Vec<usize> = (constrained.iter())
        .enumerate()
        .filter_map(|(d, &h)| h.then_some(d))
        .collect();
    let mut target = vec![0.0; 3 * node_count];
    let mut reaction = vec![Vector3::zeros(); node_count];
    let mut previous_reaction = vec![Vector3::zeros(); node_count];
    let mut external = vec![Vector3::zeros(); node_count];
    let mut previous_external = vec![Vector3::zeros(); node_count];
    loads.external_forces(0.0, &mut external);

    let mut time = 0.0;
    let (mut stable_step, mut critical) = internal_forces(
        mesh, &mut runs, &positions, time, 0.0, true, None, &mut force,
    )?;
    let mut step_factor = settings.safety_factor
        * settings
            .bulk_viscosity
            .as_ref()
            .map_or(1.0, BulkViscosity::stable_step_factor);
    interaction_forces(interactions, time, &positions, &mut interaction_force)?;
    let energy_scale: f64 = runs
        .iter()
        .map(|run| run.strain_energy_scale(mesh, ENERGY_SCALE_STRAIN))
        .sum();
    let physical_mass: f64 = mass.iter().sum();
    let mut added_mass = 0.0;
    let mut carrier = None;
    if let Some(target) = settings.mass_scaling_time_step {
        let physical = mass.clone();
        added_mass = scale_masses(mesh, &mut runs, &mut mass, target / step_factor);
        (stable_step, critical) = smallest_stable_step(&runs);
        carrier = (settings.mass_scaling_frame.as_deref())
            .map(|frame| AddedMassFrame::new(frame, &physical, &mass));
    }
    if let Some(carrier) = &carrier {
        carrier.add_forces(0.0, &positions, &mut external);
    }
    if viscosities.shear > 0.0 {
        // The damping ratio of the highest mode: b₁ from the bulk viscosity and, at its
        // largest, (4/3) η/(ρ c L₀) from the shear viscosity (the densities as scaled, the
        // moduli as first computed).
        let damping_ratio = settings.bulk_viscosity.as_ref().map_or(0.0, |b| b.linear)
            + 4.0 / 3.0 * viscosities.shear / smallest_impedance_length(&runs);
        step_factor = settings.safety_factor * damped_step_factor(damping_ratio);
    }
    check_step_budget(
        settings.end_time,
        settings
            .fixed_time_step
            .unwrap_or(stable_step * step_factor),
    )?;
    let mut half_step = 0.0;
    let (mut internal_energy, mut external_work, mut viscous_energy) = (0.0, 0.0, 0.0);
    let mut interaction_work = 0.0;
    let mut initial_balance = None;
    let mut startup_energy = None;
    let mut largest_energy: f64 = 0.0;
    let mut history = Vec::new();
    let mut next_record = 0.0;
    let mut steps = 0;
    // Set after a recorded row whose observer asked for a checkpoint: taken at the top of
    // the next pass, where the state is that of a step boundary.
    let mut checkpoint_wanted = false;
    if let Some(checkpoint) = from {
        let mut input = CheckpointReader::new(&checkpoint.state);
        time = input.f64()?;
        half_step = input.f64()?;
        for value in [
            &mut internal_energy,
            &mut external_work,
            &mut viscous_energy,
            &mut interaction_work,
            &mut largest_energy,
            &mut next_record,
        ] {
            *value = input.f64()?;
        }
        initial_balance = input.optional_f64()?;
        startup_energy = input.optional_f64()?;
        steps = input.index()?;
        for (what, values) in [
            ("displacements", &mut displacement),
            ("displacements", &mut previous_displacement),
            ("positions", &mut positions),
            ("velocities", &mut velocity),
            ("velocities", &mut old_velocity),
            ("internal forces", &mut force),
            ("internal forces", &mut previous_force),
            ("viscous forces", &mut viscous_force),
            ("viscous forces", &mut previous_viscous_force),
            ("interaction forces", &mut interaction_force),
            ("interaction forces", &mut previous_interaction_force),
            ("reactions", &mut reaction),
            ("reactions", &mut previous_reaction),
            ("external forces", &mut external),
            ("external forces", &mut previous_external),
        ] {
            input.matrices_into(what, values)?;
        }
        for run in &mut runs {
            run.restore_state(&mut input)?;
        }
        for interaction in interactions.iter_mut() {
            interaction.restore_state(&mut input)?;
        }
        restore_follower_states(&loads.rigid_ties, &mut input)?;
        input.finish()?;
        (stable_step, critical) = smallest_stable_step(&runs);
    }

    loop {
        if std::mem::take(&mut checkpoint_wanted) {
            let checkpoint = (|| {
                let mut out = CheckpointWriter::new();
                out.f64(time);
                out.f64(half_step);
                for value in [
                    internal_energy,
                    external_work,
                    viscous_energy,
                    interaction_work,
                    largest_energy,
                    next_record,
                ] {
                    out.f64(value);
                }
                out.optional_f64(initial_balance);
                out.optional_f64(startup_energy);
                out.u64(steps as u64);
                for values in [
                    &displacement,
                    &previous_displacement,
                    &positions,
                    &velocity,
                    &old_velocity,
                    &force,
                    &previous_force,
                    &viscous_force,
                    &previous_viscous_force,
                    &interaction_force,
                    &previous_interaction_force,
                    &reaction,
                    &previous_reaction,
                    &external,
                    &previous_external,
                ] {
                    out.matrices(values);
                }
                runs.iter().for_each(|run| run.save_state(&mut out));
                for interaction in interactions.iter_mut() {
                    interaction.save_state(&mut out)?;
                }
                save_follower_states(&loads.rigid_ties, &mut out);
                Ok(Checkpoint {
                    solver: "explicit".to_string(),
                    time,
                    state: out.into_bytes(),
                })
            })();
            if observer.checkpoint(checkpoint).is_break() {
                return Err(SolverError::Interrupted { time });
            }
        }
        // At the end time one more velocity update closes the books at t^N: the free
        // components get v^{N+½} from the forces, the prescribed ones keep their rate.
        let closing = time >= settings.end_time * (1.0 - 1e-12);
        let stable = stable_step;
        let mut dt = stable * step_factor;
        if closing {
            dt = half_step;
        } else if let Some(fixed) = settings.fixed_time_step {
            if fixed > stable && settings.refuse_unstable_step {
                return Err(SolverError::UnstableTimeStep {
                    requested: fixed,
                    stable,
                    block: critical.0.to_string(),
                    element: critical.1,
                });
            }
            dt = fixed;
        }
        if !closing {
            dt = dt.min(settings.end_time - time);
        }
        let average_step = 0.5 * (half_step + dt);

        // Velocities at n + ½: free components from the forces, prescribed from ū.
        update_velocities(
            &mut velocity,
            &mut old_velocity,
            [&force, &viscous_force, &interaction_force, &external],
            &mass,
            average_step,
        );
        loads.prescribed_displacements(time + dt, &reference, &mut target);
        for &d in &held {
            let (n, k) = (d / 3, d % 3);
            velocity[n][k] = if closing {
                old_velocity[n][k]
            } else {
                (target[d] - displacement[n][k]) / dt
            };
        }
        // Reactions at n: R = f + f_visc + f_c − f_ext + m a on the prescribed components.
        for &d in &held {
            let (n, k) = (d / 3, d % 3);
            let acceleration = if average_step > 0.0 {
                (velocity[n][k] - old_velocity[n][k]) / average_step
            } else {
                0.0
            };
            reaction[n][k] = force[n][k] + viscous_force[n][k] + interaction_force[n][k]
                - external[n][k]
                + mass[n] * acceleration;
        }
        // Energies at n.
        internal_energy += deterministic_sum(node_count, |i| {
            0.5 * (previous_force[i] + force[i]).dot(&(displacement[i] - previous_displacement[i]))
        });
        if settings.has_viscosity() {
            viscous_energy += deterministic_sum(node_count, |i| {
                0.5 * (previous_viscous_force[i] + viscous_force[i])
                    .dot(&(displacement[i] - previous_displacement[i]))
            });
        }
        if !interactions.is_empty() {
            interaction_work += deterministic_sum(node_count, |i| {
                0.5 * (previous_interaction_force[i] + interaction_force[i])
                    .dot(&(displacement[i] - previous_displacement[i]))
            });
        }
        external_work += deterministic_sum(node_count, |i| {
            0.5 * (previous_reaction[i] + reaction[i] + previous_external[i] + external[i])
                .dot(&(displacement[i] - previous_displacement[i]))
        });
        let kinetic_energy = deterministic_sum(node_count, |i| {
            0.5 * mass[i] * (0.5 * (old_velocity[i] + velocity[i])).norm_squared()
        });
        let total =
            internal_energy + viscous_energy + interaction_work + kinetic_energy - external_work;
        let drift = total - *initial_balance.get_or_insert(total);
        largest_energy = largest_energy
            .max(internal_energy.abs())
            .max(interaction_work.abs())
            .max(kinetic_energy)
            .max(external_work.abs());
        // The start-up error is measured over the first steps (a load ramped from zero
        // gives no energy at t = 0, and tiny energies for a while).
        if steps <= STARTUP_STEPS {
            startup_energy = Some(largest_energy);
        }
        let startup = startup_energy.unwrap_or(largest_energy);
        let allowed = settings.energy_tolerance * largest_energy.max(energy_scale);
        if drift.abs() > allowed.max(10.0 * startup) {
            return Err(SolverError::EnergyBalance {
                time,
                error: drift,
                relative: 100.0 * drift.abs() / largest_energy,
                limit: 100.0 * settings.energy_tolerance,
            });
        }
        if time >= next_record || closing {
            history.push(HistoryRow {
                time,
                time_step: half_step,
                reactions: loads.displacement_reactions(&reaction),
                rigid_reactions: loads.rigid_reactions(time, &positions, &reaction),
                internal_energy,
                hourglass_energy: hourglass_energy(mesh, &runs, &positions),
                viscous_energy,
                kinetic_energy,
                external_work,
                interaction_work,
                interactions: interactions.iter().map(|i| i.report()).collect(),
            });
            if let Some(row) = history.last() {
                observe_followers(&loads.rigid_ties, time, &row.rigid_reactions);
            }
            next_record += settings.history_interval;
            let fields = || all_fields(mesh, &runs, time);
            let nodal = || all_nodal_fields(interactions, node_count);
            let snapshot = Snapshot::new(time, &displacement, &fields).with_nodal_fields(&nodal);
            if let (Some(row), false) = (history.last(), closing) {
                if observer
                    .record(&Record::Explicit(row), &snapshot)
                    .is_break()
                {
                    return Err(SolverError::Interrupted { time });
                }
                checkpoint_wanted = observer.wants_checkpoint();
            }
        }
        // A non-finite velocity makes K non-finite: look for it only then.
        if !kinetic_energy.is_finite()
            && let Some(node) = velocity
                .iter()
                .position(|v| !v.iter().all(|x| x.is_finite()))
        {
            return Err(SolverError::Diverged { time, node });
        }
        if closing {
            if let Some(row) = history.last() {
                // The run is over: a request to stop changes nothing.
                let fields = || all_fields(mesh, &runs, time);
                let nodal = || all_nodal_fields(interactions, node_count);
                let snapshot =
                    Snapshot::new(time, &displacement, &fields).with_nodal_fields(&nodal);
                let _ = observer.record(&Record::Explicit(row), &snapshot);
            }
            break;
        }

        // Positions at n + 1 and forces there. Each array swapped here is overwritten
        // where it is not zero before it is read again.
        std::mem::swap(&mut previous_force, &mut force);
        std::mem::swap(&mut previous_viscous_force, &mut viscous_force);
        std::mem::swap(&mut previous_interaction_force, &mut interaction_force);
        std::mem::swap(&mut previous_reaction, &mut reaction);
        std::mem::swap(&mut previous_external, &mut external);
        advance_positions(
            &mut displacement,
            &mut previous_displacement,
            &mut positions,
            &reference,
            &velocity,
            dt,
        );
        time += dt;
        half_step = dt;
        steps += 1;
        if observer.progress(time, steps).is_break() {
            return Err(SolverError::Interrupted { time });
        }
        if loads.has_forces() || carrier.is_some() {
            loads.external_forces(time, &mut external);
        }
        if let Some(carrier) = &carrier {
            carrier.add_forces(time, &positions, &mut external);
        }
        let refresh = steps % MODULUS_REFRESH_INTERVAL == 0;
        let viscous = settings
            .has_viscosity()
            .then_some((&viscosities, velocity.as_slice()));
        (stable_step, critical) = internal_forces(
            mesh, &mut runs, &positions, time, dt, refresh, viscous, &mut force,
        )?;
        if viscous.is_some() {
            viscous_forces(mesh, &mut runs, &mut viscous_force);
        }
        interaction_forces(interactions, time, &positions, &mut interaction_force)?;
        runs.iter_mut().for_each(PartRun::commit);
        interactions.iter_mut().for_each(|i| i.commit());
    }
    Ok(ExplicitResult {
        history,
        displacement,
        steps,
        added_mass_fraction: added_mass / physical_mass,
    })
}

/// The output fields of every part at the last accepted step, ending at `time`.
fn all_fields(mesh: &Mesh, runs: &[PartRun], time: f64) -> Result<Vec<PartFields>, SolverError> {
    runs.iter().map(|run| run.fields(mesh, time)).collect()
}
