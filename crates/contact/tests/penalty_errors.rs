//! Errors that a user meets when setting up a contact: they name what is wrong.

use nalgebra::Vector3;

use musclefem_contact::{
    ContactError, DeformableSurface, PenaltyContact, RigidSurface, default_penalty,
};
use musclefem_core::mesh::generate::box_of_hexes;

#[test]
fn an_unknown_surface_name_lists_the_known_ones() {
    let mesh = box_of_hexes([1.0; 3], [1; 3]).unwrap();
    let error = DeformableSurface::from_mesh_surface(&mesh, "skin").unwrap_err();
    let text = error.to_string();
    assert!(matches!(error, ContactError::Mesh { .. }));
    assert!(
        text.contains("'skin'") && text.contains("z1") && text.contains("outer"),
        "{text}"
    );
    let error = DeformableSurface::outer_surface(&mesh, &["muscle"]).unwrap_err();
    assert!(
        error.to_string().contains("muscle") && error.to_string().contains("hexes"),
        "{error}"
    );
}

#[test]
fn an_empty_surface_is_refused_by_name() {
    let mesh = box_of_hexes([1.0; 3], [1; 3]).unwrap();
    let error = DeformableSurface::from_faces(&mesh, "fascia", &[]).unwrap_err();
    assert!(matches!(error, ContactError::EmptySurface(ref name) if name == "fascia"));
    assert_eq!(
        error.to_string(),
        "surface 'fascia' is empty: it has no face, so nothing can touch it"
    );
    let error = RigidSurface::new("femur", vec![Vector3::zeros()], vec![]).unwrap_err();
    assert!(error.to_string().contains("'femur' is empty"), "{error}");
}

#[test]
fn penalties_and_distances_must_be_positive() {
    let mesh = box_of_hexes([1.0; 3], [1; 3]).unwrap();
    let bottom = DeformableSurface::from_mesh_surface(&mesh, "z0").unwrap();
    let plane = RigidSurface::plane("floor", Vector3::zeros(), Vector3::z(), 2.0, 1).unwrap();
    let error = PenaltyContact::new("c", bottom.clone(), plane.clone(), -1.0).unwrap_err();
    assert!(
        error.to_string().contains("contact 'c': penalty stiffness"),
        "{error}"
    );
    let error = PenaltyContact::new("c", bottom.clone(), plane.clone(), 1e6)
        .unwrap()
        .with_search_distance(f64::NAN)
        .unwrap_err();
    assert!(error.to_string().contains("search distance"), "{error}");
    let error = default_penalty(0.0, 1e-3).unwrap_err();
    assert!(error.to_string().contains("Young's modulus"), "{error}");
    assert_eq!(default_penalty(3e4, 1e-3).unwrap(), 3e8);
}
