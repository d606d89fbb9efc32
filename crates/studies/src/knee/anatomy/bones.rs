//! The rigid bones of the default right knee as closed triangle surfaces: femur, tibia
//! and patella, each in its own reference pose (the global frame at 0° of flexion, see
//! [`super::dimensions`]).
//!
//! The femur and tibia are implicit solids ([`femur_distance`], [`tibia_distance`]:
//! distance-like functions, negative inside, built from the primitives of
//! [`super::implicit`] with smooth unions) triangulated by marching tetrahedra; the
//! patella is a triangulated ellipsoid ([`patella_surface`]). Dimensions (millimetres in
//! the code, adult male):
//!
//! - **Femur** (490 mm from the head's top to the condyles): a round shaft of radius
//!   14 mm (28 mm across, a typical adult male mid-shaft) from 90 mm above the flexion
//!   axis to the neck, its axis leaning 40 mm laterally between y = 25 and 400 mm (the
//!   ≈ 6° between the anatomical and the mechanical axis), its anterior surface on
//!   x = 35.5 mm distally; a metaphysis flaring from the shaft's section at y = 95 mm
//!   to 44 × 76 mm at y = 5 mm, keeping the shaft's anterior line; two condyles
//!   (lateral z ∈ [10, 40] mm, medial [−42, −10] mm) whose profile is the 21 mm circle
//!   about the flexion axis, with epicondyles on that axis 90 mm apart tip to tip (the
//!   transepicondylar width of adult men, ≈ 85–90 mm); the trochlea, a body of revolution about
//!   the groove axis whose floor is the groove circle and whose facets rise by 0.85
//!   times the patella's own receding (so the patella rides on the floor only), cut
//!   off 4 mm above the tibial plateau; an intercondylar notch 20 mm wide; a neck
//!   (radius 15 mm) to a head of radius 24 mm at the hip centre, and greater and
//!   lesser trochanters.
//! - **Tibia** (390 mm from the plateau to the distal end): the plateau, an elliptic
//!   slab 78 mm wide and 50 mm deep (adult male plateaus are about 75–80 × 48–52 mm)
//!   from the joint line 23 mm below the flexion axis down 22 mm, tapering to a shaft
//!   of 26 × 24 mm by 110 mm below the axis; the tibial tuberosity, an ellipsoidal
//!   prominence 9 mm in front of the plateau around the tendon's insertion; a distal
//!   flare and a rounded distal end.
//! - **Patella**: the ellipsoid of semi-axes 25 × 22 × 10.85 mm (25.0 cm³, the VHM
//!   patella's volume).
//!
//! The fibula, the femoral anteversion and the articular cartilage are left out.

use anyhow::Result;
use nalgebra::Vector3;

use super::dimensions::{
    ANTERIOR_FEMUR, CONDYLE_RADIUS, GROOVE_CENTRE, GROOVE_RADIUS, HIP_CENTRE, JOINT_LINE, MM,
    PATELLA_SEMI_AXES, TUBEROSITY,
};
use super::implicit::{
    Grid, capsule, ellipse, marching_tetrahedra, relax_on_surface, rounded_disc, smooth_max,
    smooth_min, smooth_subtract, sphere,
};
use super::surface::TriangleSurface;

/// The three rigid bones, each in its reference pose.
#[derive(Clone, Debug)]
pub struct Bones {
    pub femur: TriangleSurface,
    pub tibia: TriangleSurface,
    /// In the patella's own frame: centred on its centroid, axes along the global ones
    /// (placed by the patella's pose, see [`super::kinematics::PatellaPose`]).
    pub patella: TriangleSurface,
}

impl Bones {
    /// The bones triangulated on grids of spacing `spacing` [m] around the knee
    /// (y ∈ [−80, 110] mm) and three times that along the shafts (the patella with about
    /// `spacing` between vertices).
    pub fn new(spacing: f64) -> Result<Self> {
        let knee = [-80.0 * MM, 110.0 * MM];
        let femur = marching_tetrahedra(
            femur_distance,
            &Grid::graded_along_y(
                Vector3::new(-45.0, -32.0, -60.0) * MM,
                Vector3::new(60.0, 480.0, 80.0) * MM,
                spacing,
                knee,
                SHAFT_COARSENING,
            ),
        )?;
        let tibia = marching_tetrahedra(
            tibia_distance,
            &Grid::graded_along_y(
                Vector3::new(-35.0, -425.0, -50.0) * MM,
                Vector3::new(55.0, -15.0, 50.0) * MM,
                spacing,
                knee,
                SHAFT_COARSENING,
            ),
        )?;
        let (mut femur, mut tibia) = (femur, tibia);
        relax_on_surface(&mut femur, femur_distance, RELAXATION_ROUNDS);
        relax_on_surface(&mut tibia, tibia_distance, RELAXATION_ROUNDS);
        let around = (2.0 * std::f64::consts::PI * PATELLA_SEMI_AXES[0] / spacing).ceil() as usize;
        Ok(Self {
            femur,
            tibia,
            patella: patella_surface(around.max(12)),
        })
    }
}

/// Rounds of [`relax_on_surface`] on the femur and tibia: the muscles slide on the femur
/// along its vertex normals, which slivers would scatter.
const RELAXATION_ROUNDS: usize = 6;

/// How much coarser the bones' grids are along the shafts than at the knee.
const SHAFT_COARSENING: f64 = 3.0;

/// Rise of the trochlear facets above the groove floor at lateral offset `z` [mm]:
/// 0.85 c (1 − √(1 − (z/a)²)) for |z| < 0.95 a, a and c the patella's semi-axes
/// (0.85 of how far the patella's posterior surface recedes from its ridge there), then
/// rising at 0.3 mm/mm towards the condyles' rims.
fn facet_rise(z: f64) -> f64 {
    let (a, c) = (PATELLA_SEMI_AXES[0] / MM, PATELLA_SEMI_AXES[2] / MM);
    let r = (z.abs() / a).min(0.95);
    let mut rise = 0.85 * c * (1.0 - (1.0 - r * r).sqrt());
    if z.abs() > 0.95 * a {
        rise += 0.3 * (z.abs() - 0.95 * a);
    }
    rise
}

/// Centre (x, z) [mm] of the femoral shaft at height `y` [mm]: on the anterior line
/// x = 35.5 − 14 mm at y = 25 mm, leaning 5.6 mm back and 40 mm laterally by y = 400 mm.
fn shaft_centre(y: f64) -> (f64, f64) {
    let t = (y - 25.0) / 375.0;
    (ANTERIOR_FEMUR / MM - 14.0 - 5.6 * t, 40.0 * t)
}

/// Distance-like function of the femur [m] (negative inside) at `p` [m].
pub fn femur_distance(p: &Vector3<f64>) -> f64 {
    let q = p / MM;
    let (x, y, z) = (q.x, q.y, q.z);
    // Shaft and metaphysis, one elliptic section swept along y ∈ [5, 410]: the round
    // shaft above y = 95 mm; below, the metaphysis flaring (smoothly: the smoothstep's
    // slope vanishes at 95 mm) to AP semi-axis 22 mm and ML 38 mm at y = 5 mm, its
    // anterior kept on the anterior line, its centre sliding from the shaft's to z = 0.
    // (Two solids joined by a smooth minimum there left a 1.5 mm ring where the vasti
    // slide.)
    let (cx, cz) = shaft_centre(y);
    let t = ((95.0 - y) / 85.0).clamp(0.0, 1.0);
    let s = t * t * (3.0 - 2.0 * t);
    let (ap, ml) = (14.0 + 8.0 * s, 14.0 + 24.0 * s);
    let mut d = ellipse(x - (cx + 14.0 - ap), z - cz * (1.0 - s), ap, ml)
        .max(5.0 - y)
        .max(y - 410.0);
    // Condyles: discs of the condyle radius about the flexion axis.
    let r = CONDYLE_RADIUS / MM;
    let condyles = rounded_disc(&q, [0.0, 0.0], r, [10.0, 40.0], 5.0).min(rounded_disc(
        &q,
        [0.0, 0.0],
        r,
        [-42.0, -10.0],
        5.0,
    ));
    d = smooth_min(d, condyles, 5.0);
    // Trochlea: within groove radius + facet rise of the groove axis, in front of x = 2
    // and above y = −19 mm (4 mm clear of the tibial plateau in extension).
    let (gx, gy) = (GROOVE_CENTRE[0] / MM, GROOVE_CENTRE[1] / MM);
    let trochlea = ((x - gx).hypot(y - gy) - (GROOVE_RADIUS / MM + facet_rise(z)))
        .max(2.0 - x)
        .max(-19.0 - y);
    // Its lateral and medial ends rounded (radius ~4 mm): the vasti's tendons slide over
    // them in deep flexion.
    let trochlea = smooth_max(trochlea, (z - 2.0).abs() - 38.0, 4.0);
    d = smooth_min(d, trochlea, 1.0);
    // Epicondyles, on the flexion axis: 90 mm from tip to tip.
    let epicondyles = sphere(&q, &Vector3::new(0.0, 0.0, 37.0), 8.0).min(sphere(
        &q,
        &Vector3::new(0.0, 0.0, -38.0),
        8.0,
    ));
    d = smooth_min(d, epicondyles, 4.0);
    // Intercondylar notch.
    let notch = smooth_max(smooth_max(z.abs() - 10.0, x - 5.0, 2.0), y + 2.0, 2.0);
    d = smooth_subtract(d, notch, 3.0);
    // Neck, head and trochanters.
    let head = HIP_CENTRE / MM;
    d = smooth_min(
        d,
        capsule(&q, &Vector3::new(16.0, 405.0, 38.0), &head, 15.0),
        8.0,
    );
    d = smooth_min(d, sphere(&q, &head, 24.0), 4.0);
    d = smooth_min(d, sphere(&q, &Vector3::new(10.0, 425.0, 52.0), 17.0), 8.0);
    d = smooth_min(d, sphere(&q, &Vector3::new(2.0, 370.0, 22.0), 9.0), 5.0);
    d * MM
}

/// Distance-like function of the tibia [m] (negative inside) at `p` [m], in the tibia's
/// reference pose.
pub fn tibia_distance(p: &Vector3<f64>) -> f64 {
    let q = p / MM;
    let (x, y, z) = (q.x, q.y, q.z);
    let top = JOINT_LINE / MM;
    // Plateau: elliptic slab 50 × 78 mm, 22 mm thick, centred 3 mm in front of the axis.
    let mut d = ellipse(x - 3.0, z, 25.0, 39.0)
        .max(y - top)
        .max(top - 22.0 - y);
    // Metaphysis and shaft: ellipses from 44 × 66 mm at the plateau's underside to
    // 26 × 24 mm at y = −110 mm, then straight to −380 mm, flaring to 36 × 44 mm at the
    // distal end (−400 mm).
    let (ap, ml, cx) = if y > -110.0 {
        let t = ((y + 110.0) / (top - 22.0 + 110.0)).clamp(0.0, 1.0);
        (13.0 + 9.0 * t, 12.0 + 21.0 * t, 1.0 + 2.0 * t)
    } else {
        let t = ((-380.0 - y) / 20.0).clamp(0.0, 1.0);
        (13.0 + 5.0 * t, 12.0 + 10.0 * t, 1.0)
    };
    let shaft = ellipse(x - cx, z, ap, ml)
        .max(y - (top - 10.0))
        .max(-398.0 - y);
    d = smooth_min(d, shaft, 8.0);
    d = smooth_min(d, sphere(&q, &Vector3::new(1.0, -396.0, 0.0), 16.0), 6.0);
    // Tuberosity: an ellipsoid around the patellar tendon's insertion.
    let t = TUBEROSITY / MM;
    let centre = Vector3::new(t.x - 5.6, t.y - 11.9, 0.0);
    let tuberosity = ellipse(
        ((x - centre.x) / 7.0).hypot(z / 12.0) * 7.0,
        y - centre.y,
        7.0,
        18.0,
    );
    d = smooth_min(d, tuberosity, 6.0);
    d * MM
}

/// The patella's ellipsoid ([`PATELLA_SEMI_AXES`]) triangulated with `around` ≥ 3
/// vertices per parallel and `around / 2` parallels between the poles of its long
/// (proximodistal, y) axis, centred on the origin. Closed, outward-oriented.
pub fn patella_surface(around: usize) -> TriangleSurface {
    let around = around.max(3);
    let rings = (around / 2).max(2);
    let [a, b, c] = PATELLA_SEMI_AXES;
    let mut vertices = vec![Vector3::new(0.0, -b, 0.0)];
    for i in 1..rings {
        let polar = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..around {
            let azimuth = 2.0 * std::f64::consts::PI * j as f64 / around as f64;
            vertices.push(Vector3::new(
                c * polar.sin() * azimuth.cos(),
                -b * polar.cos(),
                a * polar.sin() * azimuth.sin(),
            ));
        }
    }
    vertices.push(Vector3::new(0.0, b, 0.0));
    let top = (vertices.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * around + j % around) as u32;
    let mut triangles = Vec::new();
    for j in 0..around {
        triangles.push([0, ring(1, j), ring(1, j + 1)]);
        triangles.push([top, ring(rings - 1, j + 1), ring(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..around {
            triangles.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            triangles.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
        }
    }
    TriangleSurface {
        vertices,
        triangles,
    }
}

/// The unit outward normals ∇f/|∇f| of the implicit solid `f` at the vertices of its
/// `surface` (central differences of 1 µm): the shape's own normals, smoother than its
/// facets' (see `musclefem_contact::RigidSurface::with_vertex_normals`).
pub fn implicit_normals(
    surface: &TriangleSurface,
    f: impl Fn(&Vector3<f64>) -> f64,
) -> Vec<Vector3<f64>> {
    let h = 1e-6;
    surface
        .vertices
        .iter()
        .map(|x| {
            Vector3::from_fn(|k, _| {
                let mut e = Vector3::zeros();
                e[k] = h;
                (f(&(x + e)) - f(&(x - e))) / (2.0 * h)
            })
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::y)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_patella_is_a_closed_ellipsoid_of_25_cm3() {
        let patella = patella_surface(96);
        patella.check_closed().unwrap();
        let [a, b, c] = PATELLA_SEMI_AXES;
        let exact = 4.0 / 3.0 * std::f64::consts::PI * a * b * c;
        assert!((exact - 25.0e-6).abs() < 0.01e-6, "{exact}");
        assert!(
            (patella.volume() - exact).abs() < 0.005 * exact,
            "{}",
            patella.volume()
        );
        assert!(patella.contains(&Vector3::zeros()));
    }

    #[test]
    fn the_femur_holds_its_landmarks() {
        // Inside: the shaft's middle, the condyles' centres, the head.
        for p in [
            mm(20.0, 200.0, 18.0),
            mm(0.0, 0.0, 25.0),
            mm(0.0, 0.0, -26.0),
            HIP_CENTRE,
        ] {
            assert!(femur_distance(&p) < 0.0, "{p:?}");
        }
        // The groove floor and the anterior femur lie on the surface, the notch is empty.
        let [gx, gy] = GROOVE_CENTRE;
        for angle in [-80f64, -45.0, 0.0] {
            let a = angle.to_radians();
            let floor = Vector3::new(
                gx + GROOVE_RADIUS * a.cos(),
                gy + GROOVE_RADIUS * a.sin(),
                0.0,
            );
            assert!(
                femur_distance(&floor).abs() < 0.5 * MM,
                "{angle}: {}",
                femur_distance(&floor)
            );
        }
        assert!(femur_distance(&Vector3::new(ANTERIOR_FEMUR, 40.0 * MM, 0.0)).abs() < 0.5 * MM);
        assert!(femur_distance(&mm(-15.0, -10.0, 0.0)) > 0.0);
        // The posterior condyles are on their circle.
        let posterior = Vector3::new(-CONDYLE_RADIUS, 0.0, 25.0 * MM);
        assert!(femur_distance(&posterior).abs() < 0.5 * MM);
    }

    #[test]
    fn the_tibia_holds_its_landmarks() {
        assert!(tibia_distance(&Vector3::new(0.0, JOINT_LINE - 10.0 * MM, 0.0)) < 0.0);
        assert!(tibia_distance(&Vector3::new(0.0, JOINT_LINE + 1.0 * MM, 0.0)) > 0.0);
        assert!(tibia_distance(&mm(0.0, -250.0, 0.0)) < 0.0);
        assert!(
            tibia_distance(&TUBEROSITY).abs() < 1.5 * MM,
            "{}",
            tibia_distance(&TUBEROSITY)
        );
    }

    fn mm(x: f64, y: f64, z: f64) -> Vector3<f64> {
        super::super::dimensions::mm(x, y, z)
    }
}
