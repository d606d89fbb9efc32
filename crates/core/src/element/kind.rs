//! The element formulations by name ([`ElementKind`]): the one table of the names scene
//! files, the command line and tables use, and the technology each stands for.

use super::Technology;
use crate::mesh::ElementShape;

/// The element formulations by name, without their parameters: what scene files, the
/// command line and tables call them. The one table of names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementKind {
    Hex8Full,
    Hex8FBar,
    Hex8OnePoint,
    Tet4,
    Tet4NodalAverage,
    Tet10,
    Tet10FBar,
}

impl ElementKind {
    /// Every kind, in the order scene files list them.
    pub const ALL: [ElementKind; 7] = [
        ElementKind::Hex8Full,
        ElementKind::Hex8FBar,
        ElementKind::Hex8OnePoint,
        ElementKind::Tet4,
        ElementKind::Tet4NodalAverage,
        ElementKind::Tet10,
        ElementKind::Tet10FBar,
    ];

    /// Their names, in the same order.
    pub const NAMES: [&'static str; 7] = {
        let mut names = [""; 7];
        let mut i = 0;
        while i < names.len() {
            names[i] = Self::ALL[i].name();
            i += 1;
        }
        names
    };

    /// The name in scene files and on the command line: `hex8-fbar`, `tet10`, ...
    pub const fn name(self) -> &'static str {
        match self {
            ElementKind::Hex8Full => "hex8-full",
            ElementKind::Hex8FBar => "hex8-fbar",
            ElementKind::Hex8OnePoint => "hex8-one-point",
            ElementKind::Tet4 => "tet4",
            ElementKind::Tet4NodalAverage => "tet4-nodal-average",
            ElementKind::Tet10 => "tet10",
            ElementKind::Tet10FBar => "tet10-fbar",
        }
    }

    /// The kind called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|kind| kind.name() == name)
    }

    /// Whether the element is a hexahedron (else a tetrahedron).
    pub fn is_hex(self) -> bool {
        self.shape() == ElementShape::Hex8
    }

    /// The element shape the kind works on.
    pub fn shape(self) -> ElementShape {
        match self {
            ElementKind::Hex8Full | ElementKind::Hex8FBar | ElementKind::Hex8OnePoint => {
                ElementShape::Hex8
            }
            ElementKind::Tet4 | ElementKind::Tet4NodalAverage => ElementShape::Tet4,
            ElementKind::Tet10 | ElementKind::Tet10FBar => ElementShape::Tet10,
        }
    }

    /// The technology, for a material of small-strain shear modulus `shear_modulus` [Pa]
    /// (only the one-point hex8 needs it, for its hourglass control: `None` there is an
    /// error message).
    pub fn technology(self, shear_modulus: Option<f64>) -> Result<Technology, &'static str> {
        Ok(match self {
            ElementKind::Hex8Full => Technology::Hex8Full,
            ElementKind::Hex8FBar => Technology::Hex8FBar,
            ElementKind::Hex8OnePoint => Technology::hex8_one_point(shear_modulus.ok_or(
                "the material gives no positive shear modulus at F = I, which the one-point \
                 hex8's hourglass control scales with",
            )?),
            ElementKind::Tet4 => Technology::Tet4,
            ElementKind::Tet4NodalAverage => Technology::Tet4NodalAverage,
            ElementKind::Tet10 => Technology::Tet10,
            ElementKind::Tet10FBar => Technology::Tet10FBar,
        })
    }
}

impl Technology {
    /// The technology's kind (its name without parameters).
    pub fn kind(self) -> ElementKind {
        match self {
            Technology::Hex8Full => ElementKind::Hex8Full,
            Technology::Hex8FBar => ElementKind::Hex8FBar,
            Technology::Hex8OnePoint { .. } => ElementKind::Hex8OnePoint,
            Technology::Tet4 => ElementKind::Tet4,
            Technology::Tet4NodalAverage => ElementKind::Tet4NodalAverage,
            Technology::Tet10 => ElementKind::Tet10,
            Technology::Tet10FBar => ElementKind::Tet10FBar,
        }
    }

    /// The name in scene files: [`ElementKind::name`].
    pub fn name(self) -> &'static str {
        self.kind().name()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind's name reads back as that kind, and every technology's name is its
    /// kind's.
    #[test]
    fn names_read_back_and_technologies_carry_their_kind() {
        for kind in ElementKind::ALL {
            assert_eq!(ElementKind::from_name(kind.name()), Some(kind));
            if let Ok(technology) = kind.technology(Some(1e4)) {
                assert_eq!(technology.kind(), kind);
                assert_eq!(technology.name(), kind.name());
                assert_eq!(technology.shape(), kind.shape());
            }
        }
        assert_eq!(ElementKind::NAMES[1], "hex8-fbar");
        assert_eq!(ElementKind::from_name("hex8"), None);
        assert!(ElementKind::Hex8OnePoint.technology(None).is_err());
        assert!(ElementKind::Tet10.technology(None).is_ok());
        assert_eq!(
            ElementKind::from_name("tet10-fbar"),
            Some(ElementKind::Tet10FBar)
        );
    }
}
