//! The knee's landmarks on the Visible Human Female (`landmarks.csv`, fitted by
//! `scripts/visible_human_landmarks.py`; the data folder's README gives every rule) and
//! the knee frame they define.
//!
//! **Knee frame** (the frame of [`super::super::dimensions`]): origin midway between the
//! centres of the posterior condyles' spheres, z lateral through them (the geometric
//! centre axis, the flexion axis), y proximal along the mechanical axis (origin to the
//! femoral head's centre) made normal to z, x = y × z anterior. The data's frame is x to
//! the subject's right (lateral), y anterior, z superior, in millimetres.

use anyhow::{Context, Result, bail};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

use super::data_dir;

/// One millimetre [m].
const MM: f64 = 1e-3;

/// A fitted point of the anatomy and, for the fitted spheres and circles, its radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landmark {
    /// Position in the data's frame [m].
    pub point: Vector3<f64>,
    /// Radius of the fitted sphere or circle [m], if it is one.
    pub radius: Option<f64>,
}

/// Every landmark of `landmarks.csv` (names as in the file).
#[derive(Clone, Debug, PartialEq)]
pub struct Landmarks {
    /// Sphere through the medial posterior condyle's cartilage.
    pub medial_condyle: Landmark,
    /// Sphere through the lateral posterior condyle's cartilage.
    pub lateral_condyle: Landmark,
    /// Sphere through the femoral head's cartilage: the hip centre.
    pub femoral_head: Landmark,
    /// Circle through the trochlear groove's floor, in the knee's sagittal plane.
    pub trochlear_groove: Landmark,
    /// Circle through the patella's articular ridge, in the knee's sagittal plane.
    pub patellar_ridge: Landmark,
    /// The patella's most distal point, where the patellar tendon arises.
    pub patella_apex: Landmark,
    /// The patella's most proximal point.
    pub patella_base: Landmark,
    /// The tibia's most anterior point 25–70 mm below the flexion axis, where the
    /// patellar tendon inserts.
    pub tibial_tuberosity: Landmark,
    /// Centroid of the distal tibial cartilage: the pin of the closed-chain squat.
    pub ankle: Landmark,
}

impl Landmarks {
    /// The committed `landmarks.csv`.
    pub fn load() -> Result<Landmarks> {
        let path = data_dir().join("landmarks.csv");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        Self::parse(&text).with_context(|| format!("in {}", path.display()))
    }

    /// Landmarks from the text of a `landmarks.csv` (header
    /// `landmark,x_mm,y_mm,z_mm,radius_mm`).
    pub fn parse(text: &str) -> Result<Landmarks> {
        let mut lines = text.lines().enumerate();
        match lines.next() {
            Some((_, "landmark,x_mm,y_mm,z_mm,radius_mm")) => {}
            other => bail!(
                "line 1: expected the header 'landmark,x_mm,y_mm,z_mm,radius_mm', found {:?}",
                other.map(|(_, l)| l)
            ),
        }
        let mut found: Vec<(String, Landmark)> = Vec::new();
        for (index, line) in lines {
            let fields: Vec<&str> = line.split(',').collect();
            if fields.len() != 5 {
                bail!(
                    "line {}: expected 5 fields, found {}",
                    index + 1,
                    fields.len()
                );
            }
            let number = |k: usize| -> Result<f64> {
                fields[k]
                    .parse::<f64>()
                    .with_context(|| format!("line {}: '{}' is not a number", index + 1, fields[k]))
            };
            let point = Vector3::new(number(1)?, number(2)?, number(3)?) * MM;
            let radius = if fields[4].is_empty() {
                None
            } else {
                Some(number(4)? * MM)
            };
            found.push((fields[0].to_string(), Landmark { point, radius }));
        }
        let take = |name: &str| -> Result<Landmark> {
            found
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, l)| *l)
                .with_context(|| format!("no landmark '{name}'"))
        };
        let with_radius = |name: &str| -> Result<Landmark> {
            let landmark = take(name)?;
            if landmark.radius.is_none() {
                bail!("landmark '{name}' has no radius");
            }
            Ok(landmark)
        };
        Ok(Landmarks {
            medial_condyle: with_radius("medial_condyle")?,
            lateral_condyle: with_radius("lateral_condyle")?,
            femoral_head: with_radius("femoral_head")?,
            trochlear_groove: with_radius("trochlear_groove")?,
            patellar_ridge: with_radius("patellar_ridge")?,
            patella_apex: take("patella_apex")?,
            patella_base: take("patella_base")?,
            tibial_tuberosity: take("tibial_tuberosity")?,
            ankle: take("ankle")?,
        })
    }

    /// The map from the data's frame [m] to the knee frame [m] (module documentation).
    pub fn knee_frame(&self) -> Isometry3<f64> {
        let (medial, lateral) = (self.medial_condyle.point, self.lateral_condyle.point);
        let origin = 0.5 * (medial + lateral);
        let z = (lateral - medial).normalize();
        let mechanical = self.femoral_head.point - origin;
        let y = (mechanical - mechanical.dot(&z) * z).normalize();
        let x = y.cross(&z);
        // Rows x, y, z: the rotation taking data vectors to knee-frame components.
        let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_rows(&[
            x.transpose(),
            y.transpose(),
            z.transpose(),
        ]));
        let rotation = UnitQuaternion::from_rotation_matrix(&rotation);
        Isometry3::from_parts(Translation3::from(-(rotation * origin)), rotation)
    }

    /// A landmark's point in the knee frame [m].
    pub fn in_knee_frame(&self, landmark: &Landmark) -> Vector3<f64> {
        self.knee_frame()
            .transform_point(&landmark.point.into())
            .coords
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_knee_frame_puts_the_condyles_on_z_and_the_hip_on_y() {
        let landmarks = Landmarks::load().unwrap();
        let medial = landmarks.in_knee_frame(&landmarks.medial_condyle);
        let lateral = landmarks.in_knee_frame(&landmarks.lateral_condyle);
        let hip = landmarks.in_knee_frame(&landmarks.femoral_head);
        assert!((medial + lateral).norm() < 1e-12);
        assert!(medial.x.abs() < 1e-12 && medial.y.abs() < 1e-12 && medial.z < 0.0);
        assert!(hip.x.abs() < 1e-12 && hip.y > 0.3);
    }

    #[test]
    fn the_patella_sits_in_the_groove_in_extension() {
        // The fitted ridge and groove circles are tangent (the cartilages touch) to within
        // a millimetre, and the patella lies in front of the groove.
        let landmarks = Landmarks::load().unwrap();
        let groove = landmarks.in_knee_frame(&landmarks.trochlear_groove);
        let ridge = landmarks.in_knee_frame(&landmarks.patellar_ridge);
        let apart = (ridge - groove).xy().norm();
        let touching =
            landmarks.trochlear_groove.radius.unwrap() + landmarks.patellar_ridge.radius.unwrap();
        assert!((apart - touching).abs() < 1e-3, "{apart} vs {touching}");
        assert!(ridge.x > groove.x);
    }

    #[test]
    fn a_landmark_file_without_a_radius_where_one_is_needed_is_refused() {
        let text = "landmark,x_mm,y_mm,z_mm,radius_mm\nmedial_condyle,1,2,3,\n";
        let error = format!("{:#}", Landmarks::parse(text).unwrap_err());
        assert!(error.contains("medial_condyle"), "{error}");
        let error = format!("{:#}", Landmarks::parse("x\n").unwrap_err());
        assert!(error.contains("line 1"), "{error}");
        let text = "landmark,x_mm,y_mm,z_mm,radius_mm\nankle,1,two,3,\n";
        let error = format!("{:#}", Landmarks::parse(text).unwrap_err());
        assert!(error.contains("line 2") && error.contains("two"), "{error}");
    }
}
