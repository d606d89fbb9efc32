use std::f64::consts::PI;

use super::*;

const MM: f64 = 1e-3;

fn station(centre: [f64; 3], width: [f64; 3], a: f64, b: f64) -> SweptStation {
    SweptStation {
        centre: Vector3::from(centre) * MM,
        width_direction: Vector3::from(width),
        half_width: a * MM,
        half_thickness: b * MM,
    }
}

/// A straight elliptic frustum along z: a and b linear from (a0, b0) to (a1, b1).
fn frustum() -> Vec<SweptStation> {
    (0..5)
        .map(|i| {
            let f = i as f64 / 4.0;
            station(
                [0.0, 0.0, 200.0 * f],
                [1.0, 0.0, 0.0],
                30.0 + (10.0 - 30.0) * f,
                12.0 + (6.0 - 12.0) * f,
            )
        })
        .collect()
}

/// A bent, twisting, fusiform muscle: thigh-like in size.
fn bent() -> Vec<SweptStation> {
    vec![
        station([0.0, 300.0, 40.0], [0.0, 0.0, 1.0], 12.0, 5.0),
        station([20.0, 220.0, 30.0], [0.2, 0.0, 1.0], 40.0, 18.0),
        station([35.0, 140.0, 15.0], [0.5, 0.0, 1.0], 35.0, 15.0),
        station([45.0, 80.0, 5.0], [1.0, 0.0, 1.0], 20.0, 9.0),
        station([42.0, 50.0, 0.0], [1.0, 0.0, 0.3], 8.0, 3.5),
    ]
}

fn spec(
    stations: Vec<SweptStation>,
    per_side: usize,
    radial: usize,
    axial: usize,
) -> SweptMuscleSpec {
    SweptMuscleSpec {
        name: "muscle".to_string(),
        stations,
        per_side,
        radial,
        axial,
        junctions: Vec::new(),
        segment_layers: None,
    }
}

fn mesh(spec: &SweptMuscleSpec) -> Mesh {
    swept_muscle_mesh(spec).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_solid_volume_is_the_frustum_volume() {
    let solid = SweptSolid::new(&frustum()).unwrap();
    // ∫ π a b dz with a, b linear: π L [a0 b0 + (a0 Δb + b0 Δa)/2 + Δa Δb / 3].
    let (l, a0, b0, da, db) = (0.2, 0.030, 0.012, -0.020, -0.006);
    let exact = PI * l * (a0 * b0 + 0.5 * (a0 * db + b0 * da) + da * db / 3.0);
    assert!(
        (solid.volume() - exact).abs() < 1e-12 * exact,
        "{} {exact}",
        solid.volume()
    );
    assert!((solid.length() - l).abs() < 1e-12);
    let at_stations = solid.station_arclengths();
    assert_eq!(at_stations.len(), 5);
    for (i, s) in at_stations.iter().enumerate() {
        assert!((s - 0.05 * i as f64).abs() < 1e-12, "{at_stations:?}");
    }
    let mid = solid.section(0.1);
    assert!((mid.half_width - 0.020).abs() < 1e-12 && (mid.half_thickness - 0.009).abs() < 1e-12);
    assert!((mid.centre - Vector3::new(0.0, 0.0, 0.1)).norm() < 1e-12);
}

#[test]
fn mesh_volume_converges_to_the_integral_of_pi_a_b() {
    let errors = |stations: Vec<SweptStation>| -> Vec<f64> {
        let exact = SweptSolid::new(&stations).unwrap().volume();
        [(4, 1, 8), (6, 2, 16), (8, 3, 32)]
            .iter()
            .map(|&(n, m, axial)| {
                let volume = mesh(&spec(stations.clone(), n, m, axial))
                    .total_volume()
                    .unwrap();
                (volume - exact).abs() / exact
            })
            .collect()
    };
    // Area-preserving sections: a straight frustum (similar polygons, linear in z) is
    // meshed exactly at every resolution ...
    let straight = errors(frustum());
    assert!(straight.iter().all(|&e| e < 1e-12), "{straight:?}");
    // ... and a bent one errs only by the straight edges along the curve: second order,
    // the error falls about fourfold each time the layers double (4.5 %, 1.0 %, 0.27 %).
    let bent = errors(bent());
    assert!(bent[2] < 3e-3, "{bent:?}");
    assert!(
        bent[0] > 3.0 * bent[1] && bent[1] > 3.0 * bent[2],
        "{bent:?}"
    );
}

#[test]
fn elements_are_valid_and_fibers_follow_the_centreline() {
    let solid = SweptSolid::new(&bent()).unwrap();
    for (n, m, axial) in [(2, 1, 6), (4, 1, 12), (6, 2, 30)] {
        let mesh = mesh(&spec(bent(), n, m, axial));
        mesh.validate().unwrap();
        assert_eq!(
            mesh.element_count(),
            spec(bent(), n, m, axial).element_count()
        );
        let block = &mesh.blocks[0];
        let cells = block.len() / axial;
        let stations = solid.graded_stations(axial);
        for (e, fiber) in block.fiber_direction.iter().enumerate() {
            assert!((fiber.norm() - 1.0).abs() < 1e-12);
            let k = e / cells;
            let tangent = solid.section(0.5 * (stations[k] + stations[k + 1])).tangent;
            assert!(
                fiber.dot(&tangent) > 0.99,
                "element {e}: {fiber:?} {tangent:?}"
            );
        }
    }
}

#[test]
fn outer_nodes_lie_on_the_area_preserving_ellipse_and_names_are_where_stated() {
    let (n, m, axial) = (4, 2, 10);
    let stations = bent();
    let mesh = mesh(&spec(stations.clone(), n, m, axial));
    let solid = SweptSolid::new(&stations).unwrap();
    let scale = (PI / polygon_area(n)).sqrt();
    let per_layer = UnitSection::new(n, m).node_count();
    let layers = solid.graded_stations(axial);
    // The last 4n nodes of every layer are its outer ring.
    for (k, &s) in layers.iter().enumerate() {
        let section = solid.section(s);
        for p in (k + 1) * per_layer - 4 * n..(k + 1) * per_layer {
            let d = mesh.nodes.position(p) - section.centre;
            assert!(
                d.dot(&section.tangent).abs() < 1e-12,
                "node {p} off its section's plane"
            );
            let u = d.dot(&section.width_axis) / (scale * section.half_width);
            let v = d.dot(&section.thickness_axis) / (scale * section.half_thickness);
            assert!((u * u + v * v - 1.0).abs() < 1e-10, "node {p}: {u} {v}");
        }
    }
    let origin = mesh.node_set("origin").unwrap();
    assert_eq!(origin.len(), per_layer);
    assert!(origin.iter().all(|&id| (id as usize) < per_layer));
    let insertion = mesh.node_set("insertion").unwrap();
    assert!(insertion.iter().all(|&id| id as usize >= axial * per_layer));
    let cells = n * n + 4 * n * m;
    assert_eq!(mesh.surface("origin").unwrap().len(), cells);
    assert_eq!(mesh.surface("insertion").unwrap().len(), cells);
    assert_eq!(mesh.surface("lateral").unwrap().len(), 4 * n * axial);
    assert_eq!(
        mesh.surface("outer").unwrap().len(),
        2 * cells + 4 * n * axial
    );
    // The origin's faces point backwards along the centreline, the insertion's forwards.
    let first = solid.section(0.0).tangent;
    for &face in mesh.surface("origin").unwrap() {
        assert!(mesh.face_area_vector(face).unwrap().normalize().dot(&first) < -0.99);
    }
    let last = solid.section(solid.length()).tangent;
    for &face in mesh.surface("insertion").unwrap() {
        assert!(mesh.face_area_vector(face).unwrap().normalize().dot(&last) > 0.99);
    }
}

#[test]
fn layers_are_graded_by_the_local_size() {
    let solid = SweptSolid::new(&frustum()).unwrap();
    let stations = solid.graded_stations(20);
    assert_eq!(stations.len(), 21);
    assert!(stations[0].abs() < 1e-15 && (stations[20] - 0.2).abs() < 1e-12);
    // Δs / √(ab) is the same for every layer (to the midpoint rule's accuracy).
    let ratios: Vec<f64> = stations
        .windows(2)
        .map(|w| {
            let sec = solid.section(0.5 * (w[0] + w[1]));
            (w[1] - w[0]) / (sec.half_width * sec.half_thickness).sqrt()
        })
        .collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    assert!(
        ratios.iter().all(|r| (r - mean).abs() < 1e-3 * mean),
        "{ratios:?}"
    );
    // The thin end gets the short layers.
    assert!(stations[20] - stations[19] < 0.6 * (stations[1] - stations[0]));
}

#[test]
fn signed_distance_is_negative_inside_and_exact_at_the_boundary() {
    let solid = SweptSolid::new(&bent()).unwrap();
    for s in [0.05, 0.12, 0.2] {
        let sec = solid.section(s);
        for angle in [0.0, 0.7, 2.0, 4.0] {
            let (u, v) = (
                sec.half_width * f64::cos(angle),
                sec.half_thickness * f64::sin(angle),
            );
            let on = sec.point(u, v);
            assert!(
                solid.signed_distance(&on).abs() < 1e-6,
                "{}",
                solid.signed_distance(&on)
            );
            let inside = sec.point(0.8 * u, 0.8 * v);
            let outside = sec.point(1.2 * u, 1.2 * v);
            assert!(solid.signed_distance(&inside) < 0.0);
            assert!(solid.signed_distance(&outside) > 0.0);
        }
        // Along the width axis the distance is exact: 3 mm out is +3 mm.
        let out = sec.point(sec.half_width + 0.003, 0.0);
        assert!((solid.signed_distance(&out) - 0.003).abs() < 3e-4);
    }
    // Past the insertion cap.
    let end = solid.section(solid.length());
    let beyond = end.centre + 0.01 * end.tangent;
    assert!((solid.signed_distance(&beyond) - 0.01).abs() < 1e-6);
}

#[test]
fn unusable_specs_are_rejected() {
    let two = vec![station([0.0; 3], [1.0, 0.0, 0.0], 5.0, 3.0)];
    assert!(SweptSolid::new(&two).is_err());
    let mut flat = frustum();
    flat[2].half_thickness = 0.0;
    assert!(SweptSolid::new(&flat).is_err());
    let mut along = frustum();
    along[1].width_direction = Vector3::z();
    assert!(SweptSolid::new(&along).is_err());
    let mut repeated = frustum();
    repeated[2].centre = repeated[1].centre;
    assert!(SweptSolid::new(&repeated).is_err());
    assert!(swept_muscle_mesh(&spec(frustum(), 3, 1, 4)).is_err());
    assert!(swept_muscle_mesh(&spec(frustum(), 4, 0, 4)).is_err());
    // A hairpin: the section (80 mm across in the bending plane) is far wider than the
    // bend (10 mm radius).
    let hairpin: Vec<_> = [[0.0, 100.0], [0.0, 0.0], [20.0, 0.0], [20.0, 100.0]]
        .iter()
        .map(|&[x, y]| station([x, y, 0.0], [0.0, 0.0, 1.0], 10.0, 40.0))
        .collect();
    let error = SweptSolid::new(&hairpin).unwrap_err();
    assert!(error.to_string().contains("bends too sharply"), "{error}");
    // The same bend with a section 4 mm across in the bending plane is fine.
    let thin: Vec<_> = hairpin
        .iter()
        .map(|s| SweptStation {
            half_thickness: 2.0 * MM,
            ..*s
        })
        .collect();
    assert!(SweptSolid::new(&thin).is_ok());
}

#[test]
fn junctions_fall_on_layers_and_split_the_elements_into_segments() {
    let solid = SweptSolid::new(&bent()).unwrap();
    let length = solid.length();
    let junctions = vec![0.12 * length, 0.8 * length];
    let mut spec = spec(bent(), 4, 1, 20);
    spec.junctions = junctions.clone();
    let mesh = mesh(&spec);
    let cells = 32;
    // Every junction is a layer of nodes on the section at its arclength.
    for (i, &s) in junctions.iter().enumerate() {
        let nodes = mesh.node_set(&format!("junction_{i}")).unwrap();
        assert_eq!(nodes.len(), mesh.node_count() / 21);
        let section = solid.section(s);
        for &n in nodes {
            let offset = mesh.nodes.position(n as usize) - section.centre;
            assert!(offset.dot(&section.tangent).abs() < 1e-12, "{offset:?}");
        }
    }
    // The segments partition the elements, origin first, in proportion to the sizes they
    // span (at least one layer each).
    let counts: Vec<usize> = (0..3)
        .map(|i| mesh.element_set(&format!("segment_{i}")).unwrap().len() / cells)
        .collect();
    assert_eq!(counts.iter().sum::<usize>(), 20);
    let total = solid.section_sizes_between(0.0, length);
    let ends = [0.0, junctions[0], junctions[1], length];
    for i in 0..3 {
        let share = solid.section_sizes_between(ends[i], ends[i + 1]) / total;
        assert!(
            (counts[i] as f64 - 1.0 - share * 17.0).abs() <= 1.0,
            "segment {i}: {} layers for a share {share}",
            counts[i]
        );
    }
    // The volume between junctions adds up to the whole.
    let parts: f64 = (0..3)
        .map(|i| solid.volume_between(ends[i], ends[i + 1]))
        .sum();
    assert!((parts - solid.volume()).abs() < 1e-9 * solid.volume());
    // Layers given per segment.
    let mut given = spec.clone();
    given.segment_layers = Some(vec![2, 9, 3]);
    let counted = swept_muscle_mesh(&given).unwrap();
    let counts: Vec<usize> = (0..3)
        .map(|i| counted.element_set(&format!("segment_{i}")).unwrap().len() / cells)
        .collect();
    assert_eq!(counts, vec![2, 9, 3]);
    given.segment_layers = Some(vec![2, 9]);
    assert!(swept_muscle_mesh(&given).is_err());
    // A junction out of range is refused.
    let mut bad = spec.clone();
    bad.junctions = vec![0.5 * length, 0.2 * length];
    assert!(swept_muscle_mesh(&bad).is_err());
}

/// Station arclengths and section counts hold at the very end of the curve: the last
/// knot's parameter can round past the arclength table's last entry, which once indexed
/// beyond it. Many perturbed copies of the bent muscle, every station measured.
#[test]
fn measures_reach_the_end_of_the_curve_for_perturbed_stations() {
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for _ in 0..300 {
        let stations: Vec<SweptStation> = bent()
            .into_iter()
            .map(|mut s| {
                s.centre += Vector3::new(next(), next(), next()) * (4.0 * MM);
                s
            })
            .collect();
        let Ok(solid) = SweptSolid::new(&stations) else {
            continue;
        };
        let arclengths = solid.station_arclengths();
        assert_eq!(arclengths.len(), stations.len());
        assert!((arclengths[arclengths.len() - 1] - solid.length()).abs() < 1e-9);
        assert!(solid.section_sizes_between(0.0, solid.length()) > 0.0);
    }
}
