use anyhow::Result;
use musclefem_core::mesh::ElementRef;
use musclefem_studies::knee::Squat;
use musclefem_studies::knee::anatomy::visible_human::{
    MeshResolution, VisibleHumanKnee, mechanism,
};
use nalgebra::Vector3;

fn main() -> Result<()> {
    let knee = VisibleHumanKnee::load(MeshResolution::Coarse)?;
    let squat = Squat::to_ninety_degrees(2.0);
    let motions = squat.motions(&mechanism::closed_chain(&knee)?)?;
    let h = 1e-3;
    for (b, m) in knee.muscles.iter().enumerate() {
        let n = knee.mesh.blocks[b].len() as u32;
        for t in [0.6, 0.8, 1.0] {
            let mut force = Vector3::zeros();
            let mut mass = 0.0;
            for e in 0..n {
                let r = ElementRef::new(b as u32, e);
                let v = knee.mesh.element_volume(r)?;
                let nodes = knee.mesh.element_nodes(r)?;
                let c: Vector3<f64> = nodes
                    .iter()
                    .map(|&i| knee.mesh.nodes.position(i as usize))
                    .sum::<Vector3<f64>>()
                    / nodes.len() as f64;
                let p = |t: f64| motions.femur.position_at(&c, t);
                let a = (p(t + h) - 2.0 * p(t) + p(t - h)) / (h * h);
                force += 1060.0 * v * a;
                mass += 1060.0 * v;
            }
            println!(
                "{m:?} t={t}: mass {mass:.3} kg, m·a (femur-fixed, unscaled) {:.2?} N |{:.2}| ; x102: {:.1} N",
                force,
                force.norm(),
                102.0 * force.norm()
            );
        }
    }
    Ok(())
}
