//! Pictures of a solid coloured by a value per cell, read back pixel by pixel: the
//! projection, what hides what, the colour map and the colour bar.

use std::ops::Range;
use std::path::{Path, PathBuf};

use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_io::plot::mesh_picture::{
    MeshPicture, NamedView, PictureSummary, RIGID_GREY, RigidSurface, TITLE_HEIGHT, ValueLabel,
    View, default_range, shaded, stage_mesh_png, value_colour,
};
use musclefem_io::plot::viridis;
use nalgebra::Vector3;
use plotters::style::RGBColor;

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("musclefem-io-mesh-picture-tests")
        .join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A decoded RGB picture.
struct Png {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Png {
    fn read(path: &Path) -> Png {
        let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut rgb).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        rgb.truncate(info.buffer_size());
        Png {
            width: info.width,
            height: info.height,
            rgb,
        }
    }

    fn at(&self, x: i32, y: i32) -> RGBColor {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        RGBColor(self.rgb[i], self.rgb[i + 1], self.rgb[i + 2])
    }
}

/// The unit cube as two hex8 cells: cell 0 in x ∈ [0, 0.5], cell 1 in x ∈ [0.5, 1].
fn two_cells() -> Mesh {
    box_of_hexes([1.0, 1.0, 1.0], [2, 1, 1]).unwrap()
}

const VALUES: [f64; 2] = [100e3, 400e3];

fn label() -> ValueLabel {
    ValueLabel {
        name: "von Mises stress".into(),
        unit: "kPa".into(),
        factor: 1e-3,
    }
}

fn picture<'a>(
    mesh: &'a Mesh,
    displacement: &'a [Vector3<f64>],
    view: View,
    range: Option<Range<f64>>,
) -> MeshPicture<'a> {
    MeshPicture {
        title: "Two cells".into(),
        note: "a test".into(),
        mesh,
        displacement,
        values: &VALUES,
        blocks: None,
        view,
        label: label(),
        range,
        rigid: Vec::new(),
        size: (800, 600),
        outlines: Some(false),
    }
}

fn draw(path: &Path, picture: &MeshPicture) -> (Png, PictureSummary) {
    let (staged, summary) = stage_mesh_png(path, picture).unwrap();
    staged.commit().unwrap();
    let png = Png::read(path);
    assert_eq!((png.width, png.height), picture.size);
    (png, summary)
}

/// Every pixel of the image area whose centre is inside the square with corners `a` and
/// `b` (picture pixels), shrunk by `inset` pixels.
fn pixels_inside(a: (f64, f64), b: (f64, f64), inset: f64) -> Vec<(i32, i32)> {
    let (x0, x1) = (a.0.min(b.0) + inset, a.0.max(b.0) - inset);
    let (y0, y1) = (a.1.min(b.1) + inset, a.1.max(b.1) - inset);
    let mut inside = Vec::new();
    for y in y0.ceil() as i32..y1.floor() as i32 {
        for x in x0.ceil() as i32..x1.floor() as i32 {
            inside.push((x, y));
        }
    }
    inside
}

/// Seen from the front (+x), the front cell's face x = 1 covers the whole cube: every
/// pixel inside it has the front cell's colour, lit face-on, and the back cell's colour
/// (lit from any side) appears nowhere in the image.
#[test]
fn the_front_cell_hides_the_back_cell() {
    let dir = test_dir("front");
    let mesh = two_cells();
    let u = vec![Vector3::zeros(); mesh.node_count()];
    let view = View::named(NamedView::Anterior);
    let range = 0.0..500e3;
    let (png, summary) = draw(
        &dir.join("front.png"),
        &picture(&mesh, &u, view, Some(range.clone())),
    );
    let front = shaded(value_colour(400e3, &range), &Vector3::x(), &view);
    assert_eq!(value_colour(400e3, &range), viridis(0.8));
    let p = |x: Vector3<f64>| {
        let p = summary.projection.pixel(&x);
        (p.x, p.y)
    };
    let centre = p(Vector3::new(1.0, 0.5, 0.5));
    assert_eq!(png.at(centre.0 as i32, centre.1 as i32), front);
    let corner = (
        p(Vector3::new(1.0, 0.0, 0.0)),
        p(Vector3::new(1.0, 1.0, 1.0)),
    );
    let inside = pixels_inside(corner.0, corner.1, 1.5);
    assert!(inside.len() > 100_000, "{} pixels", inside.len());
    assert!(inside.iter().all(|&(x, y)| png.at(x, y) == front));

    let back: Vec<RGBColor> = [Vector3::x(), Vector3::y(), Vector3::z()]
        .iter()
        .map(|n| shaded(value_colour(100e3, &range), n, &view))
        .collect();
    let (left, top, width, height) = summary.projection.image;
    for y in top..top + height {
        for x in left..left + width {
            let colour = png.at(x as i32, y as i32);
            assert!(!back.contains(&colour), "back colour at ({x}, {y})");
        }
    }
    // The cube fills the image area's height but for the margins (28 px on top, 76 px
    // at the bottom for the axes and the scale bar).
    let side = f64::from(height) - 28.0 - 76.0;
    assert!((centre.1 - (f64::from(TITLE_HEIGHT) + 28.0 + 0.5 * side)).abs() < 1e-9);
    assert!(((corner.1.1 - corner.0.1).abs() - side).abs() < 1e-9);
    assert_eq!((summary.above, summary.below, summary.cells), (0, 0, 2));
    // Ten quadrilaterals on the boundary (the face between the cells is inside), each two
    // triangles.
    assert_eq!(summary.facets, 20);
}

/// Seen from the side (+z, anterior to the right), both cells show side by side, cell 1
/// (larger x) on the right; a value above the range takes the top colour.
#[test]
fn side_view_puts_each_cell_where_it_is_and_clamps_to_the_range() {
    let dir = test_dir("side");
    let mesh = two_cells();
    let u = vec![Vector3::zeros(); mesh.node_count()];
    let view = View::named(NamedView::Lateral);
    let range = 0.0..300e3;
    let (png, summary) = draw(
        &dir.join("side.png"),
        &picture(&mesh, &u, view, Some(range.clone())),
    );
    let at = |x: Vector3<f64>| {
        let p = summary.projection.pixel(&x);
        png.at(p.x as i32, p.y as i32)
    };
    let left = at(Vector3::new(0.25, 0.5, 1.0));
    let right = at(Vector3::new(0.75, 0.5, 1.0));
    assert_eq!(left, shaded(viridis(1.0 / 3.0), &Vector3::z(), &view));
    assert_eq!(right, shaded(viridis(1.0), &Vector3::z(), &view));
    assert!(
        summary.projection.pixel(&Vector3::new(0.75, 0.5, 1.0)).x
            > summary.projection.pixel(&Vector3::new(0.25, 0.5, 1.0)).x
    );
    assert_eq!(summary.above, 1);
}

/// The default range runs from 0 to the 99th percentile of the values (397 kPa of 100
/// and 400), so the larger value is above it; the colour bar's top row has the map's end
/// colour and its bottom row its start colour.
#[test]
fn the_default_range_and_the_colour_bar_ends() {
    let dir = test_dir("bar");
    let mesh = two_cells();
    let u = vec![Vector3::zeros(); mesh.node_count()];
    let (png, summary) = draw(
        &dir.join("bar.png"),
        &picture(&mesh, &u, View::named(NamedView::Lateral), None),
    );
    assert!((summary.range.start - 0.0).abs() < 1e-9);
    assert!(
        (summary.range.end - 397e3).abs() < 1e-6,
        "{:?}",
        summary.range
    );
    assert_eq!((summary.above, summary.below), (1, 0));
    let ((x0, x1), (top, bottom)) = (summary.colour_bar.columns, summary.colour_bar.rows);
    assert!(x0 >= summary.projection.image.2 as i32 && bottom - top > 300);
    let middle = (x0 + x1) / 2;
    assert_eq!(png.at(middle, top), viridis(1.0));
    assert_eq!(png.at(middle, bottom - 1), viridis(0.0));
    assert_eq!(png.at(middle, top - 3), RGBColor(255, 255, 255));
}

/// A rigid plate in front of half of the front face is drawn over it in grey; the
/// picture shows the displaced solid, fitted wherever it is.
#[test]
fn rigid_surfaces_and_displacements() {
    let dir = test_dir("rigid");
    let mesh = two_cells();
    let u = vec![Vector3::zeros(); mesh.node_count()];
    let view = View::named(NamedView::Anterior);
    let range = 0.0..500e3;
    // A plate at x = 1.2 over z ∈ [0.5, 1.5]: in the anterior view +z is to the left.
    let plate = [
        Vector3::new(1.2, -0.5, 0.5),
        Vector3::new(1.2, 1.5, 0.5),
        Vector3::new(1.2, 1.5, 1.5),
        Vector3::new(1.2, -0.5, 1.5),
    ];
    let triangles = [[0, 1, 2], [0, 2, 3]];
    let mut with_plate = picture(&mesh, &u, view, Some(range.clone()));
    with_plate.rigid = vec![RigidSurface {
        vertices: &plate,
        triangles: &triangles,
    }];
    let (png, summary) = draw(&dir.join("plate.png"), &with_plate);
    let at = |x: Vector3<f64>| {
        let p = summary.projection.pixel(&x);
        png.at(p.x as i32, p.y as i32)
    };
    assert_eq!(
        at(Vector3::new(1.0, 0.5, 0.75)),
        shaded(RIGID_GREY, &Vector3::x(), &view)
    );
    assert_eq!(
        at(Vector3::new(1.0, 0.5, 0.25)),
        shaded(viridis(0.8), &Vector3::x(), &view)
    );
    assert_eq!(summary.rigid_facets, 2);

    let pushed: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|_| Vector3::new(0.0, 0.0, -2.0))
        .collect();
    let (_, moved) = draw(
        &dir.join("pushed.png"),
        &picture(&mesh, &pushed, view, Some(range)),
    );
    // Moved by u = (0, 0, −2) m, the front face's centre is drawn at the same pixel.
    let before = summary.projection.pixel(&Vector3::new(1.0, 0.5, 0.5));
    let after = moved.projection.pixel(&Vector3::new(1.0, 0.5, -1.5));
    assert!((before - after).norm() < 1e-9);
}

/// The default range: 0 to the 99th percentile (interpolated between order statistics),
/// from the 1st percentile when a value is negative; an empty range widens.
#[test]
fn default_ranges() {
    let close = |a: Range<f64>, b: Range<f64>| {
        assert!(
            (a.start - b.start).abs() < 1e-12 && (a.end - b.end).abs() < 1e-12,
            "{a:?} ≠ {b:?}"
        );
    };
    let hundred: Vec<f64> = (1..=100).map(f64::from).collect();
    close(default_range(&hundred), 0.0..99.01);
    close(default_range(&[-10.0, 0.0, 10.0, f64::NAN]), -9.8..9.8);
    close(default_range(&[5.0, 5.0]), 0.0..5.0);
    close(default_range(&[0.0, 0.0]), -0.5..0.5);
    close(default_range(&[-4.0]), -6.0..-2.0);
    close(default_range(&[f64::NAN]), 0.0..1.0);
}

#[test]
fn bad_pictures_are_refused_naming_the_file() {
    let dir = test_dir("bad");
    let mesh = two_cells();
    let u = vec![Vector3::zeros(); mesh.node_count()];
    let good = picture(&mesh, &u, View::named(NamedView::Lateral), None);
    let cases: Vec<(&str, MeshPicture, &str)> = vec![
        (
            "short.png",
            MeshPicture {
                values: &VALUES[..1],
                ..good.clone()
            },
            "1 values for 2 cells",
        ),
        (
            "block.png",
            MeshPicture {
                blocks: Some(&[3usize][..]),
                ..good.clone()
            },
            "no block 3",
        ),
        (
            "range.png",
            MeshPicture {
                range: Some(5.0..5.0),
                ..good.clone()
            },
            "not increasing",
        ),
        (
            "tiny.png",
            MeshPicture {
                size: (100, 100),
                ..good.clone()
            },
            "100x100",
        ),
        ("picture.jpg", good.clone(), ".png"),
    ];
    for (name, bad, expected) in cases {
        let error = stage_mesh_png(&dir.join(name), &bad)
            .unwrap_err()
            .to_string();
        assert!(error.contains(name) && error.contains(expected), "{error}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}
