//! Fiber directions from Abaqus material orientations: `*ORIENTATION` (rectangular
//! system from points a, b and an optional origin c, or from a `*DISTRIBUTION` of a and b
//! per element), an optional additional rotation about a local axis, hooked to elements by
//! `*SOLID SECTION, ELSET=..., ORIENTATION=...`.
//!
//! The fiber is the local 1-axis, the convention of transversely isotropic UMATs:
//!
//! e1 = (a − c)/|a − c|,  e3 = e1 × (b − c)/|e1 × (b − c)|,  e2 = e3 × e1,
//!
//! then, for the second data line `axis, θ` [deg]: about e1 the fiber is unchanged,
//! about e2 it is cos θ e1 − sin θ e3, about e3 it is cos θ e1 + sin θ e2.

use std::collections::HashMap;

use super::super::build::{Entry, FiberAssignment, FiberRule, Loc, Member};
use super::{Data, Keyword, Reader, SetKind, short};
use crate::mesh_import::ImportError;

/// An `*ORIENTATION` as read.
pub(super) struct Orientation {
    name: String,
    loc: Loc,
    frame: Frame,
    /// Local axis (1, 2 or 3) and angle [deg] of the additional rotation.
    rotation: Option<(u8, f64)>,
}

enum Frame {
    /// Points a, b and origin c [length].
    Points([f64; 3], [f64; 3], [f64; 3]),
    /// Name of a `*DISTRIBUTION` of a and b per element.
    Distribution(String, Loc),
}

/// A `*DISTRIBUTION, LOCATION=ELEMENT` of two vectors (a, b) per element.
pub(super) struct Distribution {
    name: String,
    loc: Loc,
    table: Option<(String, Loc)>,
    default: Option<([f64; 3], [f64; 3])>,
    entries: Vec<(Entry, [f64; 3], [f64; 3])>,
}

/// A `*SOLID SECTION` that names an orientation.
pub(super) struct Section {
    elset: String,
    orientation: String,
    loc: Loc,
}

/// What the reader keeps of the orientation keywords until the end of the file.
#[derive(Default)]
pub(super) struct Orientations {
    orientations: HashMap<String, Orientation>,
    distributions: HashMap<String, Distribution>,
    /// `*DISTRIBUTION TABLE`s: whether the columns are `COORD3D, COORD3D`.
    tables: HashMap<String, (bool, Loc)>,
    sections: Vec<Section>,
}

/// A real number in Abaqus notation.
fn real(field: &str) -> Option<f64> {
    field
        .replace(['d', 'D'], "e")
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n > 1e-300 && n.is_finite()).then(|| v.map(|c| c / n))
}

/// The fiber (rotated local 1-axis) of the rectangular system of points a, b, origin c.
pub(crate) fn fiber_direction(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    rotation: Option<(u8, f64)>,
) -> Result<[f64; 3], String> {
    let e1 = unit(sub(a, c)).ok_or("point a coincides with the origin c: no local 1-axis")?;
    let e3 = unit(cross(e1, sub(b, c)))
        .ok_or("point b lies on the local 1-axis: the local 1-2 plane is undefined")?;
    let e2 = cross(e3, e1);
    let Some((axis, degrees)) = rotation else {
        return Ok(e1);
    };
    let (s, co) = degrees.to_radians().sin_cos();
    Ok(match axis {
        1 => e1,
        2 => std::array::from_fn(|i| co * e1[i] - s * e3[i]),
        _ => std::array::from_fn(|i| co * e1[i] + s * e2[i]),
    })
}

impl Reader {
    /// `*ORIENTATION, NAME=..., [SYSTEM=RECTANGULAR], [DEFINITION=COORDINATES]`.
    pub(super) fn orientation(
        &mut self,
        keyword: &Keyword,
        data: &[Data],
    ) -> Result<(), ImportError> {
        self.check_params(keyword, &["NAME", "SYSTEM", "DEFINITION"])?;
        let name = self.require(keyword, "NAME")?.to_string();
        let head = format!("*ORIENTATION, NAME={}", short(&name));
        let unsupported = |what: String| {
            self.error(
                keyword.loc,
                format!(
                    "{head}: {what} is not supported (supported: SYSTEM=RECTANGULAR, \
                     DEFINITION=COORDINATES, points a, b[, c] or a *DISTRIBUTION name)"
                ),
            )
        };
        if let Some(system) = keyword.get("SYSTEM")
            && !system.eq_ignore_ascii_case("RECTANGULAR")
        {
            return Err(unsupported(format!("SYSTEM={}", short(system))));
        }
        if let Some(definition) = keyword.get("DEFINITION")
            && !definition.eq_ignore_ascii_case("COORDINATES")
        {
            return Err(unsupported(format!("DEFINITION={}", short(definition))));
        }
        let Some(first) = data.first() else {
            return Err(self.error(keyword.loc, format!("{head}: the data line is missing")));
        };
        let numbers = |d: &Data| -> Result<Vec<f64>, ImportError> {
            d.fields
                .iter()
                .map(|f| {
                    real(f).ok_or_else(|| {
                        self.error(
                            d.loc,
                            format!("{head}: '{}' is not a finite number", short(f)),
                        )
                    })
                })
                .collect()
        };
        let frame = match first.fields.as_slice() {
            [distribution] if real(distribution).is_none() => {
                Frame::Distribution(distribution.to_string(), first.loc)
            }
            _ => {
                let v = numbers(first)?;
                if v.len() != 6 && v.len() != 9 {
                    return Err(self.error(
                        first.loc,
                        format!(
                            "{head}: expected a1, a2, a3, b1, b2, b3[, c1, c2, c3] or the name \
                             of a *DISTRIBUTION, found {} fields",
                            v.len()
                        ),
                    ));
                }
                let at = |i: usize| [v[i], v[i + 1], v[i + 2]];
                let c = if v.len() == 9 { at(6) } else { [0.0; 3] };
                fiber_direction(at(0), at(3), c, None)
                    .map_err(|m| self.error(first.loc, format!("{head}: {m}")))?;
                Frame::Points(at(0), at(3), c)
            }
        };
        let rotation = match data.get(1) {
            None => None,
            Some(d) => {
                let v = numbers(d)?;
                let axis = v.first().copied().unwrap_or(0.0);
                if !(v.len() <= 2 && [1.0, 2.0, 3.0].contains(&axis)) {
                    return Err(self.error(
                        d.loc,
                        format!(
                            "{head}: the second line must be 'local axis (1, 2 or 3), angle \
                             [deg]', found '{}'",
                            short(&d.fields.join(", "))
                        ),
                    ));
                }
                Some((axis as u8, v.get(1).copied().unwrap_or(0.0)))
            }
        };
        if let Some(d) = data.get(2) {
            return Err(self.error(d.loc, format!("{head}: at most 2 data lines")));
        }
        let lower = name.to_ascii_lowercase();
        if let Some(first) = self.orientations.orientations.get(&lower) {
            return Err(self.error(
                keyword.loc,
                format!("{head}: defined twice (first at line {})", first.loc.line),
            ));
        }
        self.orientations.orientations.insert(
            lower,
            Orientation {
                name,
                loc: keyword.loc,
                frame,
                rotation,
            },
        );
        Ok(())
    }

    /// `*DISTRIBUTION, NAME=..., LOCATION=ELEMENT, TABLE=...` with lines
    /// `element or set, a1, a2, a3, b1, b2, b3` (an empty first field: the default).
    pub(super) fn distribution(
        &mut self,
        keyword: &Keyword,
        data: &[Data],
    ) -> Result<(), ImportError> {
        self.check_params(keyword, &["NAME", "LOCATION", "TABLE"])?;
        let name = self.require(keyword, "NAME")?.to_string();
        let head = format!("*DISTRIBUTION, NAME={}", short(&name));
        match keyword.get("LOCATION") {
            Some(l) if l.eq_ignore_ascii_case("ELEMENT") => {}
            other => {
                return Err(self.error(
                    keyword.loc,
                    format!(
                        "{head}: LOCATION={} is not supported: an orientation's distribution \
                         is given per element (LOCATION=ELEMENT)",
                        short(other.unwrap_or("(missing)"))
                    ),
                ));
            }
        }
        let mut distribution = Distribution {
            name: name.clone(),
            loc: keyword.loc,
            table: keyword.get("TABLE").map(|t| (t.to_string(), keyword.loc)),
            default: None,
            entries: Vec::new(),
        };
        for d in data {
            let err = |m: String| self.error(d.loc, format!("{head}: {m}"));
            if d.fields.len() != 7 {
                return Err(err(format!(
                    "expected 'element or element set, a1, a2, a3, b1, b2, b3', found {} fields",
                    d.fields.len()
                )));
            }
            let mut v = [0.0; 6];
            for (x, f) in v.iter_mut().zip(&d.fields[1..]) {
                *x =
                    real(f).ok_or_else(|| err(format!("'{}' is not a finite number", short(f))))?;
            }
            let (a, b) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
            fiber_direction(a, b, [0.0; 3], None).map_err(err)?;
            let target = d.fields[0];
            if target.is_empty() {
                if distribution.default.is_some() || !distribution.entries.is_empty() {
                    return Err(err(
                        "the default line (empty first field) must come first, once".into(),
                    ));
                }
                distribution.default = Some((a, b));
            } else if let Some(label) = target.parse::<i64>().ok().filter(|&l| l > 0) {
                let entry = Entry {
                    member: Member::Label(label),
                    loc: d.loc,
                };
                distribution.entries.push((entry, a, b));
            } else {
                let named = self.named(SetKind::Element, target).ok_or_else(|| {
                    err(format!(
                        "'{}' is neither an element label nor an element set defined before \
                         this line",
                        short(target)
                    ))
                })?;
                let entries: Vec<Entry> =
                    named.iter().map(|e| Entry { loc: d.loc, ..*e }).collect();
                distribution
                    .entries
                    .extend(entries.into_iter().map(|e| (e, a, b)));
            }
        }
        self.count_copies(distribution.entries.len(), keyword.loc)?;
        self.orientations
            .distributions
            .insert(name.to_ascii_lowercase(), distribution);
        Ok(())
    }

    /// `*DISTRIBUTION TABLE, NAME=...` with the column types `COORD3D, COORD3D`.
    pub(super) fn distribution_table(
        &mut self,
        keyword: &Keyword,
        data: &[Data],
    ) -> Result<(), ImportError> {
        self.check_params(keyword, &["NAME"])?;
        let name = self.require(keyword, "NAME")?.to_ascii_lowercase();
        let coordinates = data.len() == 1
            && data[0].fields.len() == 2
            && data[0]
                .fields
                .iter()
                .all(|f| f.eq_ignore_ascii_case("COORD3D"));
        self.orientations
            .tables
            .insert(name, (coordinates, keyword.loc));
        Ok(())
    }

    /// `*SOLID SECTION, ELSET=..., MATERIAL=..., [ORIENTATION=...]`: the orientation is
    /// kept; the material (and the data line) are read over with a warning.
    pub(super) fn solid_section(&mut self, keyword: &Keyword) -> Result<(), ImportError> {
        let elset = self.require(keyword, "ELSET")?.to_string();
        self.warn(
            keyword.loc,
            &keyword.name,
            format!(
                "*SOLID SECTION, ELSET={}: material and section data ignored: musclefem \
                 takes each part's element and material from the scene file{}",
                short(&elset),
                if keyword.has("ORIENTATION") {
                    " (its ORIENTATION gives the fibers)"
                } else {
                    ""
                }
            ),
        );
        if let Some(orientation) = keyword.get("ORIENTATION") {
            self.orientations.sections.push(Section {
                elset,
                orientation: orientation.to_string(),
                loc: keyword.loc,
            });
        }
        Ok(())
    }

    /// The fibers the sections give their elements, once the whole file is read.
    pub(super) fn fiber_assignments(&mut self) -> Result<Vec<FiberAssignment>, ImportError> {
        let orientations = std::mem::take(&mut self.orientations);
        let mut used = std::collections::HashSet::new();
        let mut assignments = Vec::new();
        for section in &orientations.sections {
            let head = format!("*SOLID SECTION, ELSET={}", short(&section.elset));
            let lower = section.orientation.to_ascii_lowercase();
            let Some(orientation) = orientations.orientations.get(&lower) else {
                return Err(self.error(
                    section.loc,
                    format!(
                        "{head}: no *ORIENTATION named '{}' in the file",
                        short(&section.orientation)
                    ),
                ));
            };
            used.insert(lower);
            let elements = self
                .named(SetKind::Element, &section.elset)
                .ok_or_else(|| {
                    self.error(
                        section.loc,
                        format!("{head}: no element set named '{}'", short(&section.elset)),
                    )
                })?
                .to_vec();
            let file = self.raw.file(orientation.loc);
            let source = format!(
                "*ORIENTATION {} ({}:{})",
                orientation.name,
                file.display(),
                orientation.loc.line
            );
            let at = |loc: Loc, m: String| {
                self.error(loc, format!("*ORIENTATION, NAME={}: {m}", orientation.name))
            };
            let rule = match &orientation.frame {
                Frame::Points(a, b, c) => FiberRule::Uniform(
                    fiber_direction(*a, *b, *c, orientation.rotation)
                        .map_err(|m| at(orientation.loc, m))?,
                ),
                Frame::Distribution(name, loc) => {
                    let distribution = orientations
                        .distributions
                        .get(&name.to_ascii_lowercase())
                        .ok_or_else(|| {
                        at(
                            *loc,
                            format!("no *DISTRIBUTION named '{}' in the file", short(name)),
                        )
                    })?;
                    self.check_table(distribution, &orientations.tables)?;
                    let fiber = |a: [f64; 3], b: [f64; 3]| {
                        fiber_direction(a, b, [0.0; 3], orientation.rotation)
                    };
                    let default = match distribution.default {
                        Some((a, b)) => Some(fiber(a, b).map_err(|m| at(distribution.loc, m))?),
                        None => None,
                    };
                    let mut per_element = Vec::with_capacity(distribution.entries.len());
                    for &(entry, a, b) in &distribution.entries {
                        per_element.push((entry, fiber(a, b).map_err(|m| at(entry.loc, m))?));
                    }
                    FiberRule::PerElement {
                        distribution: distribution.name.clone(),
                        default,
                        per_element,
                    }
                }
            };
            assignments.push(FiberAssignment {
                elements,
                section: section.loc,
                source,
                rule,
            });
        }
        let mut unused: Vec<&Orientation> = orientations
            .orientations
            .iter()
            .filter(|(name, _)| !used.contains(*name))
            .map(|(_, o)| o)
            .collect();
        unused.sort_by_key(|o| (o.loc.file, o.loc.line));
        for o in unused {
            let message = format!(
                "*ORIENTATION {} ignored: no *SOLID SECTION names it",
                o.name
            );
            self.warn(o.loc, "ORIENTATION", message);
        }
        Ok(assignments)
    }

    /// Errors unless the distribution's table (if named) is `COORD3D, COORD3D`.
    fn check_table(
        &self,
        distribution: &Distribution,
        tables: &HashMap<String, (bool, Loc)>,
    ) -> Result<(), ImportError> {
        let Some((table, loc)) = &distribution.table else {
            return Ok(());
        };
        match tables.get(&table.to_ascii_lowercase()) {
            Some((true, _)) => Ok(()),
            Some((false, table_loc)) => Err(self.error(
                *table_loc,
                format!(
                    "*DISTRIBUTION TABLE, NAME={}: an orientation's distribution needs the \
                     columns COORD3D, COORD3D (vectors a and b)",
                    short(table)
                ),
            )),
            None => Err(self.error(
                *loc,
                format!(
                    "*DISTRIBUTION, NAME={}: no *DISTRIBUTION TABLE named '{}'",
                    distribution.name,
                    short(table)
                ),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::fiber_direction;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-14)
    }

    #[test]
    fn the_fiber_is_the_rotated_local_1_axis() {
        let s = 0.5f64.sqrt();
        // a along (1, 1, 0): e1 = (s, s, 0); b = y: e3 = z, e2 = (−s, s, 0).
        let (a, b, o) = ([2.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0; 3]);
        assert!(close(fiber_direction(a, b, o, None).unwrap(), [s, s, 0.0]));
        // 90° about e3: the fiber is e2.
        let f = fiber_direction(a, b, o, Some((3, 90.0))).unwrap();
        assert!(close(f, [-s, s, 0.0]), "{f:?}");
        // 90° about e2: the fiber is −e3.
        let f = fiber_direction(a, b, o, Some((2, 90.0))).unwrap();
        assert!(close(f, [0.0, 0.0, -1.0]), "{f:?}");
        // About e1: unchanged.
        let f = fiber_direction(a, b, o, Some((1, 30.0))).unwrap();
        assert!(close(f, [s, s, 0.0]));
        // The origin c shifts a and b: a − c = (0, 0, 3).
        let f = fiber_direction([1.0, 1.0, 4.0], [2.0, 1.0, 1.0], [1.0, 1.0, 1.0], None);
        assert!(close(f.unwrap(), [0.0, 0.0, 1.0]));
        // Degenerate frames are refused.
        assert!(fiber_direction(o, b, o, None).is_err());
        assert!(fiber_direction(a, [4.0, 4.0, 0.0], o, None).is_err());
    }
}
