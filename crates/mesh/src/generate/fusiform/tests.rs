use std::collections::HashMap;

use super::*;
use crate::{ElementRef, Face};

const MM: f64 = 1e-3;

fn mesh(shape: SpecimenShape, element: ElementShape, mesh_size: f64) -> Mesh {
    let spec = SpecimenSpec {
        shape,
        element,
        mesh_size,
    };
    fusiform_mesh(&spec).unwrap_or_else(|e| panic!("{spec:?}: {e}"))
}

fn shapes() -> [SpecimenShape; 2] {
    [
        SpecimenShape::paper_fusiform(),
        SpecimenShape::cylinder(PAPER_MID_RADIUS),
    ]
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Smallest scaled Jacobian over the mesh's elements.
fn min_scaled_jacobian(mesh: &Mesh) -> f64 {
    let block = &mesh.blocks[0];
    let mut coords = [Vector3::zeros(); 10];
    let n = block.shape.nodes_per_element();
    block
        .elements()
        .map(|ids| {
            mesh.nodes.gather(ids, &mut coords);
            block.shape.min_scaled_jacobian(&coords[..n])
        })
        .fold(f64::INFINITY, f64::min)
}

/// The hex mesh's volume in closed form: each section is the unit polygon (area A) scaled
/// by r, and between two layers r is linear in z, so a slab holds
/// A Δz (r_k² + r_k r_{k+1} + r_{k+1}²)/3.
fn discrete_volume(spec: &SpecimenSpec) -> f64 {
    let d = spec.divisions().unwrap();
    let area = polygon_area(d.per_side);
    spec.shape
        .layer_heights(d.axial)
        .windows(2)
        .map(|z| {
            let (r0, r1) = (spec.shape.radius(z[0]), spec.shape.radius(z[1]));
            area * (z[1] - z[0]) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
        })
        .sum()
}

/// ∫₀^z f by composite Simpson's rule on `intervals` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, z: f64, intervals: usize) -> f64 {
    let h = z / intervals as f64;
    let weight = |i: usize| match i {
        0 => 1.0,
        i if i == intervals => 1.0,
        i if i % 2 == 1 => 4.0,
        _ => 2.0,
    };
    (0..=intervals)
        .map(|i| weight(i) * f(i as f64 * h))
        .sum::<f64>()
        * h
        / 3.0
}

#[test]
fn analytic_volume_and_profile_match_an_independent_quadrature() {
    let fusiform = SpecimenShape::paper_fusiform();
    assert_eq!(fusiform.radius(0.0), PAPER_END_RADIUS);
    assert!(relative(fusiform.radius(PAPER_LENGTH), PAPER_END_RADIUS) < 1e-14);
    assert!(relative(fusiform.radius(0.5 * PAPER_LENGTH), PAPER_MID_RADIUS) < 1e-15);
    for shape in shapes() {
        // Composite Simpson's rule on 2000 intervals (error ~1e-13 relative).
        let area = |z: f64| PI * shape.radius(z).powi(2);
        let simpson = simpson(area, shape.length(), 2000);
        assert!(relative(shape.volume(), simpson) < 1e-12, "{shape:?}");
    }
    // 7249 mm³ for the paper's specimen.
    assert!(
        (fusiform.volume() - 7.2489e-6).abs() < 1e-10,
        "{}",
        fusiform.volume()
    );
}

/// The divisions and element counts that the documentation of `divisions` gives for the
/// paper's specimen at 4, 2 and 1 mm.
#[test]
fn divisions_and_counts_follow_the_documented_rule() {
    // Fusiform: graded length 8.75 × 50 / √(4.5 × 8.75) = 69.72 mm; cylinder: 50 mm.
    let fusiform = SpecimenShape::paper_fusiform();
    let cylinder = SpecimenShape::cylinder(PAPER_MID_RADIUS);
    assert!((fusiform.graded_length() - 0.069_721_7).abs() < 1e-7);
    for (shape, size, per_side, radial, axial) in [
        (fusiform, 4.0, 4, 1, 18),
        (fusiform, 2.0, 8, 2, 36),
        (fusiform, 1.0, 14, 4, 70),
        (cylinder, 4.0, 4, 1, 14),
        (cylinder, 2.0, 8, 2, 26),
        (cylinder, 1.0, 14, 4, 50),
    ] {
        let spec = SpecimenSpec {
            shape,
            element: ElementShape::Hex8,
            mesh_size: size * MM,
        };
        let d = spec.divisions().unwrap();
        let expected = SpecimenDivisions {
            per_side,
            radial,
            axial,
        };
        assert_eq!(d, expected, "{size} mm");
        if size > 1.0 && shape == fusiform {
            for element in ElementShape::ALL {
                let mesh = fusiform_mesh(&SpecimenSpec { element, ..spec }).unwrap();
                assert_eq!(mesh.element_count(), d.element_count(element));
                if element != ElementShape::Tet10 {
                    let nodes = d.nodes_per_section() * (axial + 1);
                    assert_eq!(mesh.node_count(), nodes, "{element}");
                }
            }
        }
    }
    let d = SpecimenSpec::paper(ElementShape::Hex8, 2.0 * MM)
        .divisions()
        .unwrap();
    assert_eq!(d.element_count(ElementShape::Hex8), 128 * 36);
    assert_eq!(d.element_count(ElementShape::Tet10), 6 * 128 * 36);
}

/// The layers are equal steps of Z(z) = ∫₀^z dζ/r(ζ) (checked against Simpson's rule),
/// symmetric about L/2, so Δz ∝ r to second order.
#[test]
fn layers_are_spaced_in_proportion_to_the_radius() {
    for shape in shapes() {
        let layers = 36;
        let z = shape.layer_heights(layers);
        let length = shape.length();
        assert_eq!(
            (z[0], z[layers / 2], z[layers]),
            (0.0, 0.5 * length, length)
        );
        let inverse_radius = |x: f64| 1.0 / shape.radius(x);
        let total = simpson(inverse_radius, length, 4000);
        for (k, &zk) in z.iter().enumerate() {
            assert!((zk + z[layers - k] - length).abs() < 1e-15 * length);
            let steps = simpson(inverse_radius, zk, 4000) / total * layers as f64;
            assert!(
                (steps - k as f64).abs() < 1e-9,
                "{shape:?} layer {k}: {steps}"
            );
        }
        assert!(relative(total * shape.max_radius(), shape.graded_length()) < 1e-12);
        let ratios: Vec<f64> = z
            .windows(2)
            .map(|w| (w[1] - w[0]) / shape.radius(0.5 * (w[0] + w[1])))
            .collect();
        let (min, max) = ratios
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
        assert!(max / min < 1.01, "{shape:?}: {min} {max}");
    }
}

/// Every element is valid, and no corner is close to flat. Measured smallest scaled
/// Jacobian at 4, 2, 1 mm: hex8 0.83, 0.85, 0.84 (fusiform: the O-grid section alone
/// gives 0.86, the taper of the side tilts the axial edges) and 0.84, 0.86, 0.86
/// (cylinder); tets 0.25, 0.25, 0.29 (fusiform) and 0.32, 0.31, 0.34 (cylinder).
#[test]
fn meshes_validate_with_well_shaped_elements() {
    for shape in shapes() {
        for size in [4.0, 2.0, 1.0] {
            let hexes = mesh(shape, ElementShape::Hex8, size * MM);
            hexes.validate().unwrap();
            let quality = min_scaled_jacobian(&hexes);
            assert!(quality > 0.75, "{shape:?} {size} mm: hex8 {quality}");
        }
        for element in [ElementShape::Tet4, ElementShape::Tet10] {
            for size in [4.0, 2.0, 1.0] {
                let tets = mesh(shape, element, size * MM);
                tets.validate().unwrap();
                let quality = min_scaled_jacobian(&tets);
                assert!(quality > 0.2, "{shape:?} {size} mm: {element} {quality}");
            }
        }
    }
}

/// The hex mesh holds exactly the volume of its polygonal, piecewise-conical solid, and
/// that converges to ∫ π r² dz at second order: both the inscribed 4n-gon (relative error
/// π²/(24 n²)) and the chords of r(z) (∝ Δz²) are second-order. Measured (paper's
/// fusiform, h = πR/8, πR/16, πR/32 with n = 4, 8, 16): 2.77e-2, 7.03e-3, 1.77e-3, orders
/// 1.98 and 1.99; 0.73 % at h = 2 mm.
#[test]
fn hex_volume_converges_at_second_order() {
    let shape = SpecimenShape::paper_fusiform();
    let exact = shape.volume();
    let mut errors = Vec::new();
    for n in [4.0, 8.0, 16.0] {
        let size = PI * PAPER_MID_RADIUS / (2.0 * n);
        let spec = SpecimenSpec {
            shape,
            element: ElementShape::Hex8,
            mesh_size: size,
        };
        assert_eq!(spec.divisions().unwrap().per_side, n as usize);
        let volume = fusiform_mesh(&spec).unwrap().total_volume().unwrap();
        assert!(relative(volume, discrete_volume(&spec)) < 1e-12, "{n}");
        errors.push(relative(volume, exact));
    }
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
    eprintln!("volume errors {shown:?}, orders {orders:.3?}");
    for order in orders {
        assert!((1.9..2.1).contains(&order), "{order}");
    }
    let volume = mesh(shape, ElementShape::Hex8, 2.0 * MM)
        .total_volume()
        .unwrap();
    assert!(
        relative(volume, exact) < 0.008,
        "{}",
        relative(volume, exact)
    );
}

/// The tets split the hexes: the same volume to round-off (every hex face is planar), each
/// interior triangle shared by exactly two tets, and two boundary triangles per boundary
/// quad of the hex mesh.
#[test]
fn tets_fill_the_hexes_conformingly() {
    for shape in shapes() {
        let size = 3.0 * MM;
        let hexes = mesh(shape, ElementShape::Hex8, size);
        let hex_volume = hexes.total_volume().unwrap();
        let hex_boundary = hexes.surface("outer").unwrap().len();
        for element in [ElementShape::Tet4, ElementShape::Tet10] {
            let tets = mesh(shape, element, size);
            let volume = tets.total_volume().unwrap();
            assert!(relative(volume, hex_volume) < 1e-12, "{element}: {volume}");
            let mut count: HashMap<[u32; 3], usize> = HashMap::new();
            for tet in tets.blocks[0].elements() {
                for skip in 0..4 {
                    let mut key = [0; 3];
                    let others = (0..4).filter(|&i| i != skip).map(|i| tet[i]);
                    for (k, id) in key.iter_mut().zip(others) {
                        *k = id;
                    }
                    key.sort_unstable();
                    *count.entry(key).or_insert(0) += 1;
                }
            }
            assert!(count.values().all(|&c| c == 1 || c == 2), "{element}");
            let boundary = count.values().filter(|&&c| c == 1).count();
            assert_eq!(boundary, 2 * hex_boundary, "{element}");
            assert_eq!(tets.surface("outer").unwrap().len(), boundary);
        }
        // tet10: one node per distinct tet edge, at its midpoint.
        let tet4 = mesh(shape, ElementShape::Tet4, size);
        let tet10 = mesh(shape, ElementShape::Tet10, size);
        let mut edges = std::collections::HashSet::new();
        for tet in tet4.blocks[0].elements() {
            for &[a, b] in ElementShape::Tet4.edges() {
                let (a, b) = (tet[a as usize], tet[b as usize]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        assert_eq!(tet10.node_count(), tet4.node_count() + edges.len());
    }
}

/// Node sets, surfaces, block and fibers are where the documentation puts them.
#[test]
fn names_lie_where_documented() {
    let size = 3.0 * MM;
    for shape in shapes() {
        let (length, r_end) = (shape.length(), shape.radius(0.0));
        for element in ElementShape::ALL {
            let spec = SpecimenSpec {
                shape,
                element,
                mesh_size: size,
            };
            let d = spec.divisions().unwrap();
            let mesh = fusiform_mesh(&spec).unwrap();
            let at = |id: u32| mesh.nodes.position(id as usize);
            let label = format!("{shape:?} {element}");
            let block = &mesh.blocks[0];
            assert_eq!(block.name, "muscle");
            assert!(block.fiber_direction.iter().all(|f| *f == Vector3::z()));
            assert_eq!(mesh.element_set("all").unwrap().len(), block.len());

            let origin = mesh.node_set("origin").unwrap();
            let insertion = mesh.node_set("insertion").unwrap();
            let on_plane = |z: f64| (0..mesh.node_count() as u32).filter(move |&i| at(i).z == z);
            assert_eq!(origin, on_plane(0.0).collect::<Vec<_>>(), "{label}");
            assert_eq!(insertion, on_plane(length).collect::<Vec<_>>(), "{label}");
            let mid = mesh.node_set("mid_belly").unwrap();
            assert_eq!(mid.len(), origin.len(), "{label}");
            assert!(mid.iter().all(|&i| at(i).z == 0.5 * length), "{label}");
            // Lateral corner nodes are on the surface of revolution; tet10 mid-edge nodes
            // (ids after the corners) on chords, off it by less than 2 %.
            let corners = d.nodes_per_section() * (d.axial + 1);
            for &i in mesh.node_set("lateral").unwrap() {
                let p = at(i);
                let (r, exact) = (p.xy().norm(), shape.radius(p.z));
                if (i as usize) < corners {
                    assert!(relative(r, exact) < 1e-14, "{label}: {p}");
                } else {
                    assert!(relative(r, exact) < 0.02, "{label}: {p}");
                }
            }
            let single = |name: &str| {
                let set = mesh.node_set(name).unwrap();
                assert_eq!(set.len(), 1, "{name}");
                at(set[0])
            };
            assert!(single("axis_origin").norm() < 1e-15);
            assert!((single("axis_insertion") - Vector3::new(0.0, 0.0, length)).norm() < 1e-15);
            assert!((single("origin_rim_x") - Vector3::new(r_end, 0.0, 0.0)).norm() < 1e-15);

            // The surfaces partition the boundary, which is closed; the end caps face
            // out along ∓z with the area of the polygonal end section.
            let polygon = polygon_area(d.per_side);
            let sum = |name: &str| -> Vector3<f64> {
                let faces = mesh.surface(name).unwrap();
                faces
                    .iter()
                    .map(|&f| mesh.face_area_vector(f).unwrap())
                    .sum()
            };
            let counts: Vec<usize> = ["origin", "insertion", "lateral"]
                .iter()
                .map(|name| mesh.surface(name).unwrap().len())
                .collect();
            assert_eq!(
                counts.iter().sum::<usize>(),
                mesh.surface("outer").unwrap().len()
            );
            assert!(
                sum("outer").norm() < 1e-12 * polygon * r_end * r_end,
                "{label}"
            );
            let end = Vector3::new(0.0, 0.0, polygon * r_end * r_end);
            assert!((sum("origin") + end).norm() < 1e-14 * end.z, "{label}");
            assert!((sum("insertion") - end).norm() < 1e-14 * end.z, "{label}");
            mesh.validate().unwrap();
        }
    }
}

/// The analytic mid-belly area is π r_mid²; the mesh's is that of its mid section, which
/// the hexes' faces on z = L/2 add up to.
#[test]
fn mid_belly_areas() {
    let spec = SpecimenSpec::paper(ElementShape::Hex8, 2.0 * MM);
    let analytic = spec.shape.mid_belly_area();
    assert!(relative(analytic, PI * 0.00875 * 0.00875) < 1e-15);
    let mesh = fusiform_mesh(&spec).unwrap();
    let d = spec.divisions().unwrap();
    // The hexes of layer axial/2 have their face S1 (ζ = −1) on the mid plane.
    let first = d.cells_per_section() * d.axial / 2;
    let faces =
        (first..first + d.cells_per_section()).map(|e| Face::new(ElementRef::new(0, e as u32), 0));
    let from_faces: f64 = faces
        .map(|f| mesh.face_area_vector(f).unwrap().norm())
        .sum();
    let discrete = spec.mesh_mid_belly_area().unwrap();
    assert!(
        relative(from_faces, discrete) < 1e-13,
        "{from_faces} vs {discrete}"
    );
    // Below the analytic area by about π²/(24 n²) = 0.64 % for n = 8.
    let deficit = 1.0 - discrete / analytic;
    assert!(
        (deficit - PI * PI / (24.0 * 64.0)).abs() < 1e-4,
        "{deficit}"
    );
}

#[test]
fn unusable_specs_are_rejected() {
    let paper = SpecimenShape::paper_fusiform();
    let cases = [
        (paper, 0.0, "finite and positive"),
        (paper, -MM, "finite and positive"),
        (paper, f64::NAN, "finite and positive"),
        (
            paper,
            5.0 * MM,
            "larger than the specimen's smallest radius",
        ),
        (
            SpecimenShape::cylinder(2.0 * MM),
            3.0 * MM,
            "smallest radius",
        ),
        (SpecimenShape::cylinder(-2.0 * MM), 1.0 * MM, "radius"),
        (
            SpecimenShape::Fusiform {
                length: 0.0,
                end_radius: 1.0,
                mid_radius: 2.0,
            },
            0.1,
            "length",
        ),
        (paper, 1e-7, "2^32"),
    ];
    for (shape, mesh_size, message) in cases {
        let spec = SpecimenSpec {
            shape,
            element: ElementShape::Tet10,
            mesh_size,
        };
        let e = fusiform_mesh(&spec).unwrap_err();
        assert!(
            matches!(
                e,
                MeshError::InvalidArgument {
                    generator: "fusiform_mesh",
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains(message), "{e}");
    }
}
