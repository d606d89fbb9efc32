//! Smooth against closest-point contact: the same outcome on a flat surface (rim
//! included), and the continuity of the force when a pressed node slides over a convex
//! fold, a concave fold and a concave cone vertex.

use super::*;

/// Every force, the report, the nodal fields and the stiffness blocks of `contact` at
/// `positions` and `time`.
type Outcome = (
    Vec<Vector3<f64>>,
    InteractionReport,
    Vec<NodalField>,
    HashMap<(u32, u32), Matrix3<f64>>,
);

fn outcome(contact: &mut PenaltyContact, time: f64, positions: &[Vector3<f64>]) -> Outcome {
    contact.search(time, positions).unwrap();
    let mut force = vec![Vector3::zeros(); positions.len()];
    contact.forces(time, positions, true, &mut force).unwrap();
    let mut blocks: HashMap<(u32, u32), Matrix3<f64>> = HashMap::new();
    contact.stiffness(&mut |a, b, block| *blocks.entry((a, b)).or_default() += block);
    (
        force,
        contact.report(),
        contact.nodal_fields(positions.len()),
        blocks,
    )
}

/// The closest-point and the smooth outcomes agree to `tolerance` relative to the largest
/// force and block, the stiffness in the columns of nodes below `columns` (all: a rigid
/// main); returns the number of active nodes and the largest difference of the other
/// blocks relative to the largest block.
fn assert_same(closest: &Outcome, smooth: &Outcome, tolerance: f64, columns: u32) -> (usize, f64) {
    let scale = closest.0.iter().map(|f| f.amax()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    for (a, b) in closest.0.iter().zip(&smooth.0) {
        assert!((a - b).amax() <= tolerance * scale, "{a} vs {b}");
    }
    let (a, b) = (&closest.1, &smooth.1);
    assert_eq!(a.active_points, b.active_points);
    assert_eq!(a.active_area, b.active_area);
    assert!((a.force - b.force).amax() <= tolerance * scale);
    assert!((a.stored_energy - b.stored_energy).abs() <= tolerance * a.stored_energy);
    // The gap of a node beside the rim is its distance to the rim at the closest point,
    // to the plane of the rim triangle along the normals: compared where in contact.
    let pressure = &closest.2[0].values;
    for (fa, fb) in closest.2.iter().zip(&smooth.2) {
        assert_eq!(fa.name, fb.name);
        let largest = fa.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (n, (va, vb)) in fa.values.iter().zip(&fb.values).enumerate() {
            if fa.name == "contact_gap" && pressure[n] == 0.0 {
                continue;
            }
            assert!(
                (va - vb).abs() <= tolerance * largest,
                "{}: {va} vs {vb}",
                fa.name
            );
        }
    }
    let stiff = closest.3.values().map(|k| k.amax()).fold(0.0, f64::max);
    let keys: std::collections::BTreeSet<_> = closest.3.keys().chain(smooth.3.keys()).collect();
    let mut others = 0.0f64;
    for key in keys {
        let zero = Matrix3::zeros();
        let (ka, kb) = (
            closest.3.get(key).unwrap_or(&zero),
            smooth.3.get(key).unwrap_or(&zero),
        );
        let difference = (ka - kb).amax() / stiff;
        if key.1 < columns {
            assert!(difference <= tolerance, "{key:?}: {ka} vs {kb}");
        } else {
            others = others.max(difference);
        }
    }
    (a.active_points, others)
}

/// A secondary grid of 6 × 6 squares of 0.3 m over [−0.9, 0.9]² pressed into the plane
/// z = 0 by 1–3 cm (a different depth and a small shift at every node, none exactly over
/// an edge of the main surface, where the closest point's stiffness is an edge's), its
/// right column
/// moved past the main surface's rim at x = 1 by `past` times each node's depth.
fn pressed_grid(past: f64) -> Vec<Vector3<f64>> {
    let mut points = Vec::new();
    for j in 0..7 {
        for i in 0..7 {
            let s = f64::from(7 * j + i);
            let depth = 0.01 + 0.02 * (0.618 * s).fract();
            let shift = 0.02
                * Vector3::new(
                    (0.31 * s + 0.13).fract() - 0.5,
                    (0.7123 * s + 0.41).fract() - 0.5,
                    0.0,
                );
            let mut p =
                Vector3::new(0.3 * f64::from(i) - 0.9, 0.3 * f64::from(j) - 0.9, -depth) + shift;
            if i == 6 {
                p.x = 1.0 + past * depth;
            }
            points.push(p);
        }
    }
    points
}

/// The closest-point and the smooth outcomes of the grid pressed with its right column
/// `past` the rim (see [`pressed_grid`]), on a rigid plane over [−1, 1]² (4 × 4 squares)
/// turned and moved by its motion, and on a deformable flat grid over [−1, 1]² (5 × 5
/// squares) in the same mesh as the secondary grid.
fn flat_outcomes(past: f64) -> [(Outcome, Outcome); 2] {
    let points = pressed_grid(past);
    let count = points.len() as u32;
    let motion = RigidMotion {
        translation: [Some(Amplitude::ramp(1.0, 0.05).unwrap()), None, None],
        rotation: Some(RigidRotation {
            center: Vector3::new(0.1, -0.2, 0.0),
            axis: Unit::new_normalize(Vector3::new(0.3, 1.0, 0.2)),
            angle: Amplitude::ramp(1.0, 0.5).unwrap(),
        }),
        follower: None,
    };
    let plane = RigidSurface::plane("plane", Vector3::zeros(), Vector3::z(), 1.0, 4)
        .unwrap()
        .with_motion(motion.clone());
    let time = 0.7;
    let iso = motion.isometry_at(time);
    let placed: Vec<Vector3<f64>> = points
        .iter()
        .map(|p| iso.transform_point(&Point3::from(*p)).coords)
        .collect();
    let both = |mesh: &Mesh, main: ContactTarget, time: f64, at: &[Vector3<f64>]| {
        let skin = DeformableSurface::from_triangles(mesh, "skin", grid_triangles(6, 6)).unwrap();
        let closest = PenaltyContact::new("flat", skin, main, PENALTY).unwrap();
        let smooth = closest.clone().with_smooth_normals();
        assert!(closest.symmetric_stiffness() && !smooth.symmetric_stiffness());
        assert!(!closest.smooth_normals() && smooth.smooth_normals());
        (
            outcome(&mut closest.clone(), time, at),
            outcome(&mut smooth.clone(), time, at),
        )
    };
    let rigid = both(&mesh(&placed), plane.into(), time, &placed);
    let mut all = points.clone();
    for j in 0..6 {
        for i in 0..6 {
            all.push(Vector3::new(
                0.4 * f64::from(i) - 1.0,
                0.4 * f64::from(j) - 1.0,
                0.0,
            ));
        }
    }
    let mesh = mesh(&all);
    let triangles = grid_triangles(5, 5)
        .iter()
        .map(|t| t.map(|v| v + count))
        .collect();
    let main = DeformableSurface::from_triangles(&mesh, "grid", triangles).unwrap();
    let deformable = both(&mesh, main.into(), 0.0, &all);
    [rigid, deformable]
}

/// On a flat surface the normal field is the face normal and the projection along it is
/// the orthogonal one: the smooth contact is the closest-point contact (forces, report,
/// fields to 1e-12) on a rigid plane turned and moved by its motion and on a deformable
/// flat grid. So is the stiffness on the rigid plane, and in the secondary nodes' columns
/// on the grid; in the grid nodes' columns the smooth tangent, holding the vertex normals
/// fixed, leaves out the turn of the faces that the closest point's includes (a term of
/// the order of the penetration over the element size). Past the rim both contacts fade
/// the force with the overhang the same way: a node that overhangs by 15 times its depth
/// (15–45 cm, past the fade of a quarter of the 0.4–0.5 m triangles) is beside the surface
/// in both, and one that leans by 0.5 % is over it; that one the closest-point contact
/// pushes from the rim's edge, the smooth one along the normal, a force differing by its
/// lean.
#[test]
fn on_a_flat_surface_the_smooth_contact_is_the_closest_point_contact() {
    let [rigid, deformable] = flat_outcomes(15.0);
    let (active, _) = assert_same(&rigid.0, &rigid.1, 1e-12, u32::MAX);
    eprintln!("flat rigid main: {active} of 49 nodes active, the same in both modes");
    assert_eq!(active, 42, "the right column beside the rim");
    let (active, others) = assert_same(&deformable.0, &deformable.1, 1e-12, 49);
    eprintln!(
        "flat deformable main: {active} of 49 nodes active, the same in both modes; the \
         main nodes' columns of the stiffness differ by {others:.1e} of its largest entry \
         (penetrations 1–3 cm, 2.5–7.5 % of the 0.4 m triangles)"
    );
    assert_eq!(active, 42, "the right column beside the rim");
    assert!(others > 1e-4 && others < 0.1, "{others:e}");
    for (closest, smooth) in &flat_outcomes(0.005) {
        assert_eq!(closest.1.active_points, 49);
        assert_eq!(smooth.1.active_points, 49);
        let mut worst = 0.0f64;
        for (a, b) in closest.0.iter().zip(&smooth.0).take(49) {
            worst = worst.max((a - b).norm() / a.norm());
        }
        eprintln!("over the rim by 0.5 % of the depth: forces differ by up to {worst:.2e}");
        assert!(worst < 0.006, "{worst}");
    }
}

/// The force on node 0 of the secondary triangle moved along `path` over the rigid
/// `main` (a search before every evaluation, as the solvers do), with smooth normals or
/// at the closest point.
fn along_path(main: &RigidSurface, smooth: bool, path: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let mesh = mesh(&triangle_at(path[0]));
    let mut contact = pressed(&mesh, main.clone(), smooth);
    path.iter()
        .map(|&x| {
            let positions = triangle_at(x);
            contact.search(0.0, &positions).unwrap();
            let mut force = vec![Vector3::zeros(); 3];
            contact.forces(0.0, &positions, false, &mut force).unwrap();
            force[0]
        })
        .collect()
}

/// `samples` + 1 points from x = −0.4983 m to 0.5017 m at `y` (samples 5 mm or 2.5 mm
/// apart miss x = 0 by 1.7 mm or 0.8 mm), `depth` [m] below the rigid `main` surface at
/// rest: straight below each point (a path with kinks under the edges), or, `straight`,
/// on the line `depth` below the surface's point at x = 0.
fn pressed_path(
    main: &RigidSurface,
    (y, depth, straight): (f64, f64, bool),
    samples: usize,
) -> Vec<Vector3<f64>> {
    let ends = [Vector3::new(-0.4983, y, 0.0), Vector3::new(0.5017, y, 0.0)];
    let middle = below(main, 0.0, y).z - depth;
    line(ends[0], ends[1], samples)
        .iter()
        .map(|p| match straight {
            true => Vector3::new(p.x, p.y, middle),
            false => below(main, p.x, p.y) - depth * Vector3::z(),
        })
        .collect()
}

/// Between consecutive samples along a pressed path ([`pressed_path`]) 5 mm and 2.5 mm
/// apart, the largest change of the force [N], the largest turn of its direction [rad]
/// and the largest change of the force over ε A_s times the distance moved (a Lipschitz
/// quotient [1]): `[[change, turn, quotient] at 5 mm, [change, turn, quotient] at
/// 2.5 mm]`, with smooth normals or at the closest point. With smooth normals the node is
/// in contact everywhere and the force is continuous: change and turn within 10 times
/// their medians and shrinking with the step, the quotient below 1.5.
fn largest_changes(
    what: &str,
    main: &RigidSurface,
    path: (f64, f64, bool),
    smooth: bool,
) -> [[f64; 3]; 2] {
    let mut largest = [[0.0; 3]; 2];
    let mode = if smooth { "smooth" } else { "closest point" };
    let area = DeformableSurface::from_triangles(
        &mesh(&triangle_at(Vector3::zeros())),
        "skin",
        vec![[0, 1, 2]],
    )
    .unwrap()
    .node_area[0];
    for (s, samples) in [200, 400].into_iter().enumerate() {
        let points = pressed_path(main, path, samples);
        let forces = along_path(main, smooth, &points);
        if smooth {
            assert!(forces.iter().all(|f| f.norm() > 0.0));
        }
        let quotient = forces
            .windows(2)
            .zip(points.windows(2))
            .map(|(f, x)| (f[1] - f[0]).norm() / (PENALTY * area * (x[1] - x[0]).norm()))
            .fold(0.0, f64::max);
        let (change, change_median) = jumps(&forces);
        let (turn, turn_median) = turns(&forces);
        eprintln!(
            "{what}, pressed {} m, {mode}, step {} mm: largest force change {change:.3e} N \
             (median {change_median:.3e}), turn {turn:.3e} rad (median {turn_median:.3e}), \
             |Δf|/(ε A |Δx|) {quotient:.3}",
            path.1,
            1000.0 / samples as f64,
        );
        if smooth {
            assert!(
                change < 10.0 * change_median,
                "{change:e} vs {change_median:e}"
            );
            assert!(turn < 10.0 * turn_median, "{turn:e} vs {turn_median:e}");
            assert!(quotient < 1.5, "{quotient}");
        }
        largest[s] = [change, turn, quotient];
    }
    if smooth {
        for q in 0..2 {
            assert!(largest[1][q] < 0.6 * largest[0][q], "{largest:?}");
        }
    }
    largest
}

/// A node pressed 2 cm into a convex ridge (a 30° fold) and slid across it: the closest
/// point jumps from one face to the other at the crest, and its force turns by the fold
/// angle between two samples however small the step (its Lipschitz quotient doubles as
/// the step halves); the smooth force turns by less than 0.01 rad per step, less with a
/// smaller step.
#[test]
fn the_force_is_continuous_over_a_convex_fold() {
    let fold = 30f64.to_radians();
    let ridge = folded(-(0.5 * fold).tan());
    let what = "convex fold (30°)";
    let path = (0.3, 0.02, false);
    let smooth = largest_changes(what, &ridge, path, true);
    assert!(smooth[1][1] < 0.01, "{}", smooth[1][1]);
    let closest = largest_changes(what, &ridge, path, false);
    for [_, turn, _] in closest {
        assert!((turn - fold).abs() < 1e-3, "{turn}");
    }
    assert!(closest[1][2] > 1.9 * closest[0][2], "{closest:?}");
}

/// Pressed into a concave fold or vertex on `main` along paths at `y` (`straight` or
/// following the surface, [`pressed_path`]): the smooth force is continuous. The closest
/// point under a concave edge or vertex stays on it while the node is within about
/// |g| tan(θ/2) of it (θ the fold) and its force sweeps through the fold angle over that
/// band: pressed 2 cm, over about 1 cm, in several steps of 5 mm or 2.5 mm but at least
/// 50 times faster than the smooth force turns (over the 1 m triangles around the edge);
/// pressed 0.5 mm, by more than `sweep` [rad] within one step.
fn concave(what: &str, main: &RigidSurface, (y, straight): (f64, bool), sweep: f64) {
    let smooth = largest_changes(what, main, (y, 0.02, straight), true);
    assert!(smooth[1][1] < 0.01, "{}", smooth[1][1]);
    let deep = largest_changes(what, main, (y, 0.02, straight), false);
    for (closest, smooth) in deep.iter().zip(&smooth) {
        assert!(closest[1] > 50.0 * smooth[1], "{closest:?} vs {smooth:?}");
    }
    for [_, turn, _] in largest_changes(what, main, (y, 0.0005, straight), false) {
        assert!(turn > sweep, "{turn}");
    }
}

/// A node pressed into a concave valley (a 30° fold) and slid across it, following the
/// surface.
#[test]
fn the_force_is_continuous_over_a_concave_fold() {
    let fold = 30f64.to_radians();
    concave(
        "concave fold (30°)",
        &folded((0.5 * fold).tan()),
        (0.3, false),
        0.9 * fold,
    );
}

/// A node pressed into an inverted cone (its faces rising 15°) and slid on a straight line
/// 5 cm beside the apex, over four of its six faces (deeper away from the apex). Following
/// the faceted surface instead, the path's kink under a radial edge and the foot's
/// crossing of it are a fraction of a millimetre apart (the vertex normals are not
/// symmetric about the edge) and the force changes by 0.1 % over that distance, which
/// steps of millimetres do not resolve.
#[test]
fn the_force_is_continuous_around_a_concave_cone_vertex() {
    let cone = bowl(15f64.to_radians().tan());
    concave("concave cone vertex (15°)", &cone, (0.05, true), 0.2);
}

/// A node pressed 1 cm into a rigid plane of 0.5 m triangles and moved across its rim:
/// in both modes the force is the penalty force over the face times the rim weight
/// w = 1 − (3t² − 2t³), t = s / (0.25 h), of its overhang s (h = √(2 A) = 0.5 m): from
/// the full force at the rim to none 12.5 cm past it, with no jump on the way (before,
/// it dropped from ε A |g| to zero within 0.1 mm of the rim). (The closest-point force
/// also turns, by the lean of x − x_m, quickly near the rim: its size is compared.)
#[test]
fn past_the_rim_the_force_fades_with_the_overhang() {
    let plane = RigidSurface::plane("plane", Vector3::zeros(), Vector3::z(), 1.0, 4).unwrap();
    let depth = 0.01;
    let path: Vec<Vector3<f64>> = (0..=400)
        .map(|k| Vector3::new(0.95 + 0.0005 * f64::from(k), 0.1, -depth))
        .collect();
    for smooth in [false, true] {
        let forces = along_path(&plane, smooth, &path);
        let full = forces[0].norm();
        assert!(full > 0.0);
        // The weight each force shows: its size over the full force (and the lean).
        let mut weights = Vec::new();
        for (x, f) in path.iter().zip(&forces) {
            let overhang = (x.x - 1.0).max(0.0);
            let t = (overhang / (0.25 * 0.5)).min(1.0);
            let expected = 1.0 - t * t * (3.0 - 2.0 * t);
            // The closest-point force leans by the overhang: |x − x_m| = √(s² + g²).
            let lean = match smooth {
                true => 1.0,
                false => (overhang.powi(2) + depth * depth).sqrt() / depth,
            };
            let weight = f.norm() / (full * lean);
            assert!(
                (weight - expected).abs() <= 1e-9,
                "smooth {smooth}, x {}: weight {weight} vs {expected}",
                x.x
            );
            weights.push(weight);
        }
        let largest_step = weights
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "smooth {smooth}: largest change of the weight between 0.5 mm steps over the rim \
             {largest_step:.3e}"
        );
        // The steepest slope of w is 1.5 / (0.125 m): 0.006 per 0.5 mm step.
        assert!(largest_step < 0.007, "{largest_step}");
        assert_eq!(forces.last().unwrap().norm(), 0.0);
    }
}
