//! The Abaqus vocabulary the reader knows: element types, the keywords it reads, the
//! keywords it skips, those it refuses, and the nearest-keyword suggestion.

use musclefem_mesh::ElementShape;

/// Abaqus element types read, with their shape. The type is kept per block, so the solver
/// can tell `C3D8R` (one-point) from `C3D8`.
pub(crate) const ELEMENT_TYPES: [(&str, ElementShape); 11] = [
    ("C3D4", ElementShape::Tet4),
    ("C3D4H", ElementShape::Tet4),
    ("C3D8", ElementShape::Hex8),
    ("C3D8H", ElementShape::Hex8),
    ("C3D8I", ElementShape::Hex8),
    ("C3D8R", ElementShape::Hex8),
    ("C3D8RH", ElementShape::Hex8),
    ("C3D10", ElementShape::Tet10),
    ("C3D10H", ElementShape::Tet10),
    ("C3D10M", ElementShape::Tet10),
    ("C3D10MH", ElementShape::Tet10),
];

/// Abaqus 2-D element types read as surfaces: name, corner count, node count.
pub(crate) const SURFACE_ELEMENT_TYPES: [(&str, usize, usize); 16] = [
    ("R3D3", 3, 3),
    ("S3", 3, 3),
    ("S3R", 3, 3),
    ("M3D3", 3, 3),
    ("SFM3D3", 3, 3),
    ("M3D6", 3, 6),
    ("SFM3D6", 3, 6),
    ("STRI65", 3, 6),
    ("R3D4", 4, 4),
    ("S4", 4, 4),
    ("S4R", 4, 4),
    ("M3D4", 4, 4),
    ("M3D4R", 4, 4),
    ("SFM3D4", 4, 4),
    ("SFM3D4R", 4, 4),
    ("M3D8", 4, 8),
];

/// Corner and node counts of a 2-D element type (upper case) read as a surface.
pub(crate) fn surface_element(type_name: &str) -> Option<(usize, usize)> {
    SURFACE_ELEMENT_TYPES
        .iter()
        .find(|(name, ..)| *name == type_name)
        .map(|&(_, corners, nodes)| (corners, nodes))
}

/// The shape of an Abaqus element type (upper case), if it is supported.
pub(crate) fn element_shape(type_name: &str) -> Option<ElementShape> {
    ELEMENT_TYPES
        .iter()
        .find(|(name, _)| *name == type_name)
        .map(|&(_, shape)| shape)
}

/// The supported element types as a list for messages.
pub(crate) fn supported_types() -> String {
    let volumes = ELEMENT_TYPES.iter().map(|(name, _)| *name);
    let surfaces = SURFACE_ELEMENT_TYPES.iter().map(|(name, ..)| *name);
    format!(
        "{}; as surfaces: {}",
        volumes.collect::<Vec<_>>().join(", "),
        surfaces.collect::<Vec<_>>().join(", ")
    )
}

/// Keywords the reader interprets.
pub(crate) const READ: [&str; 17] = [
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "SURFACE",
    "PART",
    "END PART",
    "ASSEMBLY",
    "END ASSEMBLY",
    "INSTANCE",
    "END INSTANCE",
    "INCLUDE",
    "HEADING",
    "SOLID SECTION",
    "ORIENTATION",
    "DISTRIBUTION",
    "DISTRIBUTION TABLE",
];

/// Mesh-defining keywords the reader refuses: skipping them would give a wrong mesh.
pub(crate) const REFUSED: [&str; 13] = [
    "NGEN",
    "NFILL",
    "NCOPY",
    "NMAP",
    "ELGEN",
    "ELCOPY",
    "SYSTEM",
    "PARAMETER",
    "NODAL THICKNESS",
    "IMPORT",
    "SUBMODEL",
    "EMBEDDED ELEMENT",
    "TRANSFORM",
];

/// Model and history keywords that do not change the mesh: skipped with their data
/// lines and listed in [`super::ImportedMesh::skipped_keywords`].
pub(crate) const SKIPPED: [&str; 87] = [
    "PREPRINT",
    "PHYSICAL CONSTANTS",
    "MATERIAL",
    "ELASTIC",
    "HYPERELASTIC",
    "HYPERFOAM",
    "VISCOELASTIC",
    "PLASTIC",
    "DENSITY",
    "DEPVAR",
    "USER MATERIAL",
    "USER DEFINED FIELD",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "DAMPING",
    "DAMAGE INITIATION",
    "DAMAGE EVOLUTION",
    "MULLINS EFFECT",
    "ANISOTROPIC HYPERELASTIC",
    "SHELL SECTION",
    "MEMBRANE SECTION",
    "BEAM SECTION",
    "COHESIVE SECTION",
    "CONNECTOR SECTION",
    "SECTION CONTROLS",
    "HOURGLASS STIFFNESS",
    "AMPLITUDE",
    "INITIAL CONDITIONS",
    "BOUNDARY",
    "CLOAD",
    "DLOAD",
    "DSLOAD",
    "DSFLUX",
    "TEMPERATURE",
    "FIELD",
    "PREDEFINED FIELD",
    "STEP",
    "END STEP",
    "STATIC",
    "DYNAMIC",
    "VISCO",
    "FREQUENCY",
    "BUCKLE",
    "HEAT TRANSFER",
    "COUPLED TEMPERATURE-DISPLACEMENT",
    "CONTROLS",
    "SOLVER CONTROLS",
    "BULK VISCOSITY",
    "FIXED MASS SCALING",
    "VARIABLE MASS SCALING",
    "RESTART",
    "OUTPUT",
    "NODE OUTPUT",
    "ELEMENT OUTPUT",
    "CONTACT OUTPUT",
    "ENERGY OUTPUT",
    "NODE PRINT",
    "EL PRINT",
    "ENERGY PRINT",
    "CONTACT PRINT",
    "NODE FILE",
    "EL FILE",
    "FILE FORMAT",
    "MONITOR",
    "PRINT",
    "DIAGNOSTICS",
    "SURFACE INTERACTION",
    "SURFACE BEHAVIOR",
    "FRICTION",
    "COHESIVE BEHAVIOR",
    "CONTACT",
    "CONTACT PAIR",
    "CONTACT INCLUSIONS",
    "CONTACT EXCLUSIONS",
    "CONTACT PROPERTY ASSIGNMENT",
    "CONTACT CONTROLS",
    "TIE",
    "COUPLING",
    "KINEMATIC",
    "DISTRIBUTING",
    "RIGID BODY",
    "MASS",
    "ROTARY INERTIA",
    "EQUATION",
    "MPC",
    "MODEL CHANGE",
];

/// Why a skipped keyword is not read, for its warning.
pub(crate) fn skip_reason(keyword: &str) -> &'static str {
    const MATERIAL: [&str; 17] = [
        "MATERIAL",
        "ELASTIC",
        "HYPERELASTIC",
        "HYPERFOAM",
        "VISCOELASTIC",
        "PLASTIC",
        "DENSITY",
        "DEPVAR",
        "USER MATERIAL",
        "EXPANSION",
        "CONDUCTIVITY",
        "SPECIFIC HEAT",
        "DAMPING",
        "DAMAGE INITIATION",
        "DAMAGE EVOLUTION",
        "MULLINS EFFECT",
        "ANISOTROPIC HYPERELASTIC",
    ];
    const INTERACTION: [&str; 16] = [
        "SURFACE INTERACTION",
        "SURFACE BEHAVIOR",
        "FRICTION",
        "COHESIVE BEHAVIOR",
        "CONTACT",
        "CONTACT PAIR",
        "CONTACT INCLUSIONS",
        "CONTACT EXCLUSIONS",
        "CONTACT PROPERTY ASSIGNMENT",
        "CONTACT CONTROLS",
        "TIE",
        "COUPLING",
        "KINEMATIC",
        "DISTRIBUTING",
        "EQUATION",
        "MPC",
    ];
    if MATERIAL.contains(&keyword) {
        "musclefem takes materials and densities from the scene file"
    } else if INTERACTION.contains(&keyword) {
        "musclefem takes contact and ties from the scene file's interactions"
    } else if keyword.contains("OUTPUT")
        || keyword.contains("PRINT")
        || keyword.contains("FILE")
        || ["MONITOR", "RESTART", "DIAGNOSTICS"].contains(&keyword)
    {
        "musclefem writes the output its scene file's [output] asks for"
    } else if keyword.contains("SECTION") || keyword == "HOURGLASS STIFFNESS" {
        "musclefem takes each part's element and material from the scene file"
    } else if keyword == "PREPRINT" {
        "a printing option of Abaqus"
    } else {
        "musclefem takes loads, boundary conditions and steps from the scene file"
    }
}

/// What the reader does with a keyword (upper case, single spaces).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Class {
    Read,
    Refused,
    Skipped,
    Unknown,
}

pub(crate) fn classify(keyword: &str) -> Class {
    if READ.contains(&keyword) {
        Class::Read
    } else if REFUSED.contains(&keyword) {
        Class::Refused
    } else if SKIPPED.contains(&keyword) {
        Class::Skipped
    } else {
        Class::Unknown
    }
}

/// The known keyword nearest to `keyword` by edit distance (ties: the reader's own
/// keywords first).
pub(crate) fn nearest(keyword: &str) -> &'static str {
    READ.iter()
        .chain(&REFUSED)
        .chain(&SKIPPED)
        .min_by_key(|k| edit_distance(keyword, k))
        .copied()
        .unwrap_or("NODE")
}

/// Levenshtein distance over characters (short strings: O(n·m) is fine; inputs longer
/// than 64 characters are cut, so a garbage keyword cannot cost much).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().take(64).collect();
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0; b.len() + 1];
    for (i, ca) in a.iter().enumerate() {
        current[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = previous[j] + usize::from(ca != cb);
            current[j + 1] = substitute.min(previous[j + 1] + 1).min(current[j] + 1);
        }
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_and_classes() {
        assert_eq!(edit_distance("NDOE", "NODE"), 2);
        assert_eq!(edit_distance("", "NODE"), 4);
        assert_eq!(nearest("NOD"), "NODE");
        assert_eq!(nearest("ELEMNT"), "ELEMENT");
        assert_eq!(nearest("MATERAIL"), "MATERIAL");
        assert_eq!(classify("NGEN"), Class::Refused);
        assert_eq!(classify("STEP"), Class::Skipped);
        assert_eq!(classify("TRANSFORM"), Class::Refused);
        assert!(skip_reason("STEP").contains("steps"));
        assert!(skip_reason("DENSITY").contains("materials"));
        assert!(skip_reason("NODE OUTPUT").contains("[output]"));
        assert_eq!(classify("FOO"), Class::Unknown);
        assert_eq!(element_shape("C3D8R"), Some(ElementShape::Hex8));
        assert_eq!(element_shape("C3D20"), None);
        // No keyword is listed twice.
        let all: Vec<_> = READ.iter().chain(&REFUSED).chain(&SKIPPED).collect();
        let mut sorted = all.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), all.len());
    }
}
