//! The force each quadriceps' mass needs to follow the femur in the Visible Human knee's
//! squat, m a summed over its elements (each carried as a point of the femur, at its
//! centroid), physical and with the explicit squat's mass scaling (the added mass about
//! 101 × the physical one): what the explicit run's interfaces and ties carry on top of
//! the muscles' pull unless the added mass rides on the femur's frame
//! (`[step.explicit] mass_scaling_frame`, `crates/core/src/solver/added_mass_frame.rs`).
//!
//! ```text
//! cargo run --release -p musclefem-studies --example knee_inertia
//! ```

use anyhow::Result;
use nalgebra::Vector3;

use musclefem_core::mesh::ElementRef;
use musclefem_studies::knee::Squat;
use musclefem_studies::knee::anatomy::visible_human::{
    MeshResolution, VisibleHumanKnee, mechanism,
};
use musclefem_studies::knee::simulation::model::MUSCLE_DENSITY;

/// The explicit squat's mass over the physical mass (its run.log's added mass + 1).
const SCALED_MASS_RATIO: f64 = 102.0;

/// Time step of the second difference of the femur's motion [s].
const DIFFERENCE_STEP: f64 = 1e-3;

fn main() -> Result<()> {
    let knee = VisibleHumanKnee::load(MeshResolution::Coarse)?;
    let squat = Squat::to_ninety_degrees(2.0);
    let femur = squat.motions(&mechanism::closed_chain(&knee)?)?.femur;
    let h = DIFFERENCE_STEP;
    println!("muscle  mass [kg]  t [s]  knee [°]  |m a| [N]  |m a| × {SCALED_MASS_RATIO} [N]");
    for (block, muscle) in knee.muscles.iter().enumerate() {
        for time in [0.6, 0.8, 1.0] {
            let (mut mass, mut force) = (0.0, Vector3::zeros());
            for element in 0..knee.mesh.blocks[block].len() as u32 {
                let element = ElementRef::new(block as u32, element);
                let nodes = knee.mesh.element_nodes(element)?;
                let centroid = nodes
                    .iter()
                    .map(|&n| knee.mesh.nodes.position(n as usize))
                    .sum::<Vector3<f64>>()
                    / nodes.len() as f64;
                let at = |t: f64| femur.position_at(&centroid, t);
                let acceleration = (at(time + h) - 2.0 * at(time) + at(time - h)) / (h * h);
                let element_mass = MUSCLE_DENSITY * knee.mesh.element_volume(element)?;
                mass += element_mass;
                force += element_mass * acceleration;
            }
            println!(
                "{:6}  {mass:9.3}  {time:5.1}  {:8.1}  {:9.2}  {:14.1}",
                muscle.abbreviation(),
                squat.flexion_at(time).to_degrees(),
                force.norm(),
                SCALED_MASS_RATIO * force.norm()
            );
        }
    }
    Ok(())
}
