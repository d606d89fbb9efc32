//! A curved tube of hexahedra: the annular sector of a torus of rectangular section, the
//! domain on which the fiber solver's flow is known in closed form (it follows the
//! circles about the axis).

use std::f64::consts::FRAC_PI_2;

use nalgebra::Vector3;

use super::box_of_hexes;
use crate::{Mesh, MeshError};

/// The annular sector r ∈ [`radii`[0], `radii`[1]] [m], θ ∈ [0, π/2], z ∈ [0, `height`]
/// [m] (a quarter of a torus of rectangular section) in hex8, `divisions` = (radial,
/// angular, axial). Its surfaces `y0` and `y1` are the cut faces θ = 0 and θ = π/2, `x0`
/// and `x1` the inner and outer walls, `z0` and `z1` the flat ones.
pub fn curved_tube(radii: [f64; 2], height: f64, divisions: [usize; 3]) -> Result<Mesh, MeshError> {
    let mut mesh = box_of_hexes([1.0, 1.0, 1.0], divisions)?;
    for i in 0..mesh.nodes.len() {
        let p = mesh.nodes.position(i);
        let r = radii[0] + (radii[1] - radii[0]) * p.x;
        let theta = FRAC_PI_2 * p.y;
        mesh.nodes.set_position(
            i,
            Vector3::new(r * theta.cos(), r * theta.sin(), height * p.z),
        );
    }
    Ok(mesh)
}

/// The flow direction in the curved tube at `x`: e_θ, tangent to the circle about the z
/// axis through x, pointing from θ = 0 to θ = π/2.
pub fn circumferential(x: Vector3<f64>) -> Vector3<f64> {
    let theta = x.y.atan2(x.x);
    Vector3::new(-theta.sin(), theta.cos(), 0.0)
}
