//! The view of a picture: an orthographic projection along a direction.
//!
//! A view is a right-handed screen frame (r, u, d): r points to the right of the picture,
//! u up, and d = r × u out of the screen towards the viewer. A point x is drawn at
//! (x·r, x·u), and x·d is its height towards the viewer (larger is nearer).
//!
//! The named views are those of the knee's frame, **x anterior, y superior (proximal),
//! z lateral** (a right knee): `anterior` looks at the front (d = +x, up = +y, so the
//! lateral side is on the left, as when facing the person), `posterior` at the back,
//! `lateral` at the outer side (d = +z, anterior to the right), `medial` at the inner side,
//! `superior` from above (d = +y, up = +x) and `inferior` from below. For any other mesh
//! they are simply views along ±x, ±y and ±z.

use std::fmt;
use std::str::FromStr;

use nalgebra::{Unit, Vector3};

/// A view along one of the frame's axes (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NamedView {
    Anterior,
    Posterior,
    Lateral,
    Medial,
    Superior,
    Inferior,
}

impl NamedView {
    pub const ALL: [NamedView; 6] = [
        NamedView::Anterior,
        NamedView::Posterior,
        NamedView::Lateral,
        NamedView::Medial,
        NamedView::Superior,
        NamedView::Inferior,
    ];

    pub fn name(self) -> &'static str {
        match self {
            NamedView::Anterior => "anterior",
            NamedView::Posterior => "posterior",
            NamedView::Lateral => "lateral",
            NamedView::Medial => "medial",
            NamedView::Superior => "superior",
            NamedView::Inferior => "inferior",
        }
    }

    /// The direction from the model towards the viewer, d.
    pub fn toward_viewer(self) -> Vector3<f64> {
        match self {
            NamedView::Anterior => Vector3::x(),
            NamedView::Posterior => -Vector3::x(),
            NamedView::Lateral => Vector3::z(),
            NamedView::Medial => -Vector3::z(),
            NamedView::Superior => Vector3::y(),
            NamedView::Inferior => -Vector3::y(),
        }
    }
}

/// An orthographic view: the screen frame (right, up, toward the viewer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// What the view is called in titles, e.g. "lateral" or "from (1, 0, 1)".
    pub name: ViewName,
    pub right: Unit<Vector3<f64>>,
    pub up: Unit<Vector3<f64>>,
    pub toward_viewer: Unit<Vector3<f64>>,
}

/// The name of a view, for titles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ViewName {
    Named(NamedView),
    /// A view from the direction (towards the viewer) as given.
    Direction(Vector3<f64>),
}

impl fmt::Display for ViewName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ViewName::Named(view) => f.write_str(view.name()),
            ViewName::Direction(d) => write!(f, "from ({}, {}, {})", d.x, d.y, d.z),
        }
    }
}

impl View {
    /// The view from the side `toward_viewer` points to (it need not be a unit vector),
    /// with the projection of +y (superior) up; looking along ±y, +x (anterior) is up.
    /// `None` for a zero or non-finite direction.
    pub fn from_direction(toward_viewer: Vector3<f64>) -> Option<Self> {
        let d = Unit::try_new(toward_viewer, 1e-12).filter(|d| d.iter().all(|c| c.is_finite()))?;
        let up_hint = if d.cross(&Vector3::y()).norm() > 1e-6 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let up = Unit::new_normalize(up_hint - d.into_inner() * d.dot(&up_hint));
        let right = Unit::new_normalize(up.cross(&d));
        Some(View {
            name: ViewName::Direction(toward_viewer),
            right,
            up,
            toward_viewer: d,
        })
    }

    /// The same view turned about its line of sight so that the projection of `up` points
    /// up; `None` if `up` is zero, not finite or along the line of sight.
    pub fn with_up(self, up: Vector3<f64>) -> Option<Self> {
        let d = self.toward_viewer;
        let up = Unit::try_new(up - d.into_inner() * d.dot(&up), 1e-9 * up.norm())
            .filter(|u| u.iter().all(|c| c.is_finite()))?;
        let right = Unit::new_normalize(up.cross(&d));
        Some(View { up, right, ..self })
    }

    /// A named view (see the module documentation).
    pub fn named(view: NamedView) -> Self {
        let found = View::from_direction(view.toward_viewer()).expect("an axis is a direction");
        View {
            name: ViewName::Named(view),
            ..found
        }
    }

    /// Screen coordinates of `x`: (right, up, toward the viewer) [m].
    pub fn screen(&self, x: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            x.dot(&self.right),
            x.dot(&self.up),
            x.dot(&self.toward_viewer),
        )
    }
}

impl FromStr for View {
    type Err = String;

    /// A view's name (`anterior`, `posterior`, `lateral`, `medial`, `superior`,
    /// `inferior`) or a direction towards the viewer, `X,Y,Z`.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let text = text.trim();
        if let Some(named) = NamedView::ALL.iter().find(|v| v.name() == text) {
            return Ok(View::named(*named));
        }
        let names = NamedView::ALL.map(NamedView::name).join(", ");
        let numbers: Vec<&str> = text.split(',').collect();
        if numbers.len() != 3 {
            return Err(format!(
                "view '{text}' is neither one of {names} nor a direction X,Y,Z"
            ));
        }
        let mut d = Vector3::zeros();
        for (c, number) in d.iter_mut().zip(&numbers) {
            *c = number
                .trim()
                .parse()
                .map_err(|_| format!("view '{text}': '{}' is not a number", number.trim()))?;
        }
        View::from_direction(d)
            .ok_or_else(|| format!("view '{text}': the direction must be finite and not zero"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Vector3<f64>, b: Vector3<f64>) -> bool {
        (a - b).norm() < 1e-12
    }

    /// The named views in the knee's frame (x anterior, y superior, z lateral).
    #[test]
    fn named_views_put_the_anatomy_where_it_belongs() {
        let lateral = View::named(NamedView::Lateral);
        assert!(close(&lateral.right, Vector3::x()), "anterior to the right");
        assert!(close(&lateral.up, Vector3::y()), "superior up");
        let anterior = View::named(NamedView::Anterior);
        assert!(close(&anterior.right, -Vector3::z()), "lateral on the left");
        let superior = View::named(NamedView::Superior);
        assert!(close(&superior.up, Vector3::x()), "anterior up");
        assert!(close(&superior.right, Vector3::z()));
        for named in NamedView::ALL {
            let v = View::named(named);
            // A right-handed screen frame: r × u = d.
            assert!(close(&v.right.cross(&v.up), v.toward_viewer.into_inner()));
            assert_eq!(named.name().parse::<View>().unwrap(), v);
        }
    }

    #[test]
    fn a_direction_is_a_view_and_bad_text_is_refused() {
        let v: View = "1, 0, 1".parse().unwrap();
        let d = Vector3::new(1.0, 0.0, 1.0).normalize();
        assert!(close(&v.toward_viewer, d));
        assert!(close(&v.up, Vector3::y()));
        // The nearer of two points has the larger third screen coordinate.
        let (near, far) = (Vector3::new(1.0, 0.0, 1.0), Vector3::new(-1.0, 0.0, -1.0));
        assert!(v.screen(&near).z > v.screen(&far).z);
        assert_eq!(v.name.to_string(), "from (1, 0, 1)");
        // Turned so that +z is up: right = up × d.
        let turned = v.with_up(Vector3::z()).unwrap();
        let up = Vector3::new(-1.0, 0.0, 1.0).normalize();
        assert!(close(&turned.up, up) && close(&turned.toward_viewer, d));
        assert!(close(&turned.right, up.cross(&d)));
        assert!(v.with_up(d).is_none() && v.with_up(Vector3::zeros()).is_none());
        for bad in ["sideways", "1,2", "1,x,0", "0,0,0", "inf,0,0"] {
            let error = bad.parse::<View>().unwrap_err();
            assert!(error.contains(bad), "{error}");
        }
    }
}
