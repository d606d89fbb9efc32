//! The data lines of the Abaqus keywords that define the mesh: `*NODE`, `*ELEMENT`,
//! `*NSET`, `*ELSET`, `*SURFACE`, `*INSTANCE`.

use super::super::abaqus_keywords::{element_shape, supported_types, surface_element};
use super::super::build::{Entry, Member, RawBlock, RawSurfaceElement};
use super::{Data, Instance, Keyword, Reader, Scope, SetKind, short};
use crate::mesh_import::ImportError;

/// A positive integer label.
fn label(field: &str) -> Option<i64> {
    field.parse::<i64>().ok().filter(|&l| l > 0)
}

/// A real number in Abaqus notation (`1.`, `.5`, `1e3`, Fortran `1.0D+03`).
fn real(field: &str) -> Option<f64> {
    field.replace(['d', 'D'], "e").parse::<f64>().ok()
}

impl Reader {
    /// Errors unless the reader is in one of `scopes`.
    fn in_scope(&self, keyword: &Keyword, scopes: &[Scope], what: &str) -> Result<(), ImportError> {
        if scopes.contains(&self.scope) {
            return Ok(());
        }
        Err(self.error(
            keyword.loc,
            format!("*{} inside {:?} scope: {what}", keyword.name, self.scope),
        ))
    }

    /// Mesh data belongs in the part, or in a flat model without parts.
    fn mesh_scope(&self, keyword: &Keyword) -> Result<(), ImportError> {
        if self.scope == Scope::Model && self.part.is_some() {
            return Err(self.error(
                keyword.loc,
                format!("*{} outside the *PART in a file with a part", keyword.name),
            ));
        }
        self.in_scope(
            keyword,
            &[Scope::Model, Scope::Part],
            "nodes and elements must be in the *PART (assembly-level nodes such as reference \
             points are not supported)",
        )
    }

    pub(super) fn nodes(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        self.check_params(keyword, &["NSET"])?;
        self.mesh_scope(keyword)?;
        let mut entries = Vec::new();
        for d in data {
            let err = |m: String| self.error(d.loc, format!("*NODE: {m}"));
            let fields = &d.fields;
            if !(4..=7).contains(&fields.len()) {
                return Err(err(format!(
                    "expected a node label and 3 coordinates, found {} fields",
                    fields.len()
                )));
            }
            let l = label(fields[0]).ok_or_else(|| {
                err(format!(
                    "node label '{}' is not a positive integer",
                    short(fields[0])
                ))
            })?;
            let mut x = [0.0; 3];
            for (c, field) in x.iter_mut().zip(&fields[1..4]) {
                *c = real(field).ok_or_else(|| {
                    err(format!(
                        "node {l}: coordinate '{}' is not a number",
                        short(field)
                    ))
                })?;
                if !c.is_finite() {
                    return Err(err(format!("node {l}: coordinate '{field}' is not finite")));
                }
            }
            self.raw.node_labels.push(l);
            self.raw.nodes.x.push(x[0]);
            self.raw.nodes.y.push(x[1]);
            self.raw.nodes.z.push(x[2]);
            self.raw.node_locs.push(d.loc);
            entries.push(Entry {
                member: Member::Label(l),
                loc: d.loc,
            });
        }
        match keyword.get("NSET") {
            Some(name) => self.add_to(SetKind::Node, name, entries, keyword.loc),
            None => Ok(()),
        }
    }

    pub(super) fn elements(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        self.check_params(keyword, &["TYPE", "ELSET"])?;
        self.mesh_scope(keyword)?;
        let type_name = self.require(keyword, "TYPE")?.to_ascii_uppercase();
        if let Some((corners, n)) = surface_element(&type_name) {
            return self.surface_elements(keyword, data, &type_name, corners, n);
        }
        let shape = element_shape(&type_name).ok_or_else(|| {
            self.error(
                keyword.loc,
                format!(
                    "*ELEMENT: element type {} is not supported (supported: {})",
                    short(&type_name),
                    supported_types()
                ),
            )
        })?;
        let n = shape.nodes_per_element();
        let elset = keyword.get("ELSET").filter(|s| !s.is_empty());
        let block = self.block(&type_name, shape, elset);
        let mut entries = Vec::new();
        for (l, nodes, loc) in self.element_rows(data, &type_name, n)? {
            let raw = &mut self.raw.blocks[block];
            raw.labels.push(l);
            raw.nodes.extend_from_slice(&nodes);
            raw.locs.push(loc);
            entries.push(Entry {
                member: Member::Label(l),
                loc,
            });
        }
        match elset {
            Some(name) => self.add_to(SetKind::Element, name, entries, keyword.loc),
            None => Ok(()),
        }
    }

    /// The rows of an `*ELEMENT`: label, `n` node labels and line (a row may continue on
    /// the next lines when it ends with a comma).
    fn element_rows(
        &self,
        data: &[Data],
        type_name: &str,
        n: usize,
    ) -> Result<Vec<(i64, Vec<i64>, crate::mesh_import::build::Loc)>, ImportError> {
        let mut out = Vec::new();
        let mut rows = data.iter();
        while let Some(first) = rows.next() {
            let mut fields = first.fields.clone();
            let mut continued = first.continued;
            while continued && fields.len() < n + 1 {
                let Some(next) = rows.next() else { break };
                fields.extend(next.fields.iter().copied());
                continued = next.continued;
            }
            let err = |m: String| self.error(first.loc, format!("*ELEMENT, TYPE={type_name}: {m}"));
            let first_field = fields.first().copied().unwrap_or("");
            let l = label(first_field).ok_or_else(|| {
                err(format!(
                    "element label '{}' is not a positive integer",
                    short(first_field)
                ))
            })?;
            if fields.len() != n + 1 {
                return Err(err(format!(
                    "element {l}: a {type_name} has {n} nodes, found {} node labels",
                    fields.len().saturating_sub(1)
                )));
            }
            let mut nodes = Vec::with_capacity(n);
            for field in fields.iter().skip(1) {
                nodes.push(label(field).ok_or_else(|| {
                    err(format!(
                        "element {l}: node label '{}' is not a positive integer",
                        short(field)
                    ))
                })?);
            }
            out.push((l, nodes, first.loc));
        }
        Ok(out)
    }

    /// An `*ELEMENT` of 2-D elements (R3D3, S4, M3D3, ...): kept to become a surface.
    fn surface_elements(
        &mut self,
        keyword: &Keyword,
        data: &[Data],
        type_name: &str,
        corners: usize,
        n: usize,
    ) -> Result<(), ImportError> {
        let elset = keyword.get("ELSET").filter(|s| !s.is_empty());
        let surface = elset.unwrap_or(type_name).to_string();
        let mut entries = Vec::new();
        for (l, nodes, loc) in self.element_rows(data, type_name, n)? {
            self.raw.surface_elements.push(RawSurfaceElement {
                label: l,
                type_name: type_name.to_string(),
                surface: surface.clone(),
                nodes,
                corners,
                loc,
            });
            entries.push(Entry {
                member: Member::Label(l),
                loc,
            });
        }
        match elset {
            Some(name) => self.add_to(SetKind::Element, name, entries, keyword.loc),
            None => Ok(()),
        }
    }

    /// The block of (type, element set), created on first use with a unique name.
    fn block(
        &mut self,
        type_name: &str,
        shape: musclefem_mesh::ElementShape,
        elset: Option<&str>,
    ) -> usize {
        let key = (
            type_name.to_string(),
            elset.unwrap_or("").to_ascii_lowercase(),
        );
        if let Some(&b) = self.blocks.get(&key) {
            return b;
        }
        let base = elset.unwrap_or(type_name).to_string();
        let mut name = base.clone();
        let mut k = 1;
        while self.raw.blocks.iter().any(|b| b.name == name) {
            name = if k == 1 {
                format!("{base}_{type_name}")
            } else {
                format!("{base}_{type_name}_{k}")
            };
            k += 1;
        }
        self.raw.blocks.push(RawBlock {
            name,
            type_name: type_name.to_string(),
            shape,
            labels: Vec::new(),
            nodes: Vec::new(),
            locs: Vec::new(),
        });
        self.blocks.insert(key, self.raw.blocks.len() - 1);
        self.raw.blocks.len() - 1
    }

    /// The entries of a set named in the data; `instance.set` names a set of the part.
    pub(super) fn named(&self, kind: SetKind, name: &str) -> Option<&[Entry]> {
        let (names, list) = match kind {
            SetKind::Node => (&self.node_sets, &self.raw.node_sets),
            SetKind::Element => (&self.element_sets, &self.raw.element_sets),
        };
        let lower = name.to_ascii_lowercase();
        let index = names.get(&lower).or_else(|| {
            let (prefix, rest) = lower.split_once('.')?;
            let instance = self.instance.as_ref()?;
            (instance.name.to_ascii_lowercase() == prefix)
                .then(|| names.get(rest))
                .flatten()
        })?;
        list.get(*index).map(|(_, entries)| entries.as_slice())
    }

    /// Checks `INSTANCE=` and whether labels may be given here.
    fn labels_allowed(&self, keyword: &Keyword) -> Result<bool, ImportError> {
        match keyword.get("INSTANCE") {
            Some(name) => {
                self.in_scope(
                    keyword,
                    &[Scope::Assembly],
                    "INSTANCE= belongs to the assembly",
                )?;
                match &self.instance {
                    Some(i) if i.name.eq_ignore_ascii_case(name) => Ok(true),
                    _ => Err(self.error(
                        keyword.loc,
                        format!(
                            "*{}: INSTANCE={} is not the instance defined so far ({})",
                            keyword.name,
                            short(name),
                            self.instance.as_ref().map_or("none", |i| i.name.as_str())
                        ),
                    )),
                }
            }
            None => Ok(self.scope != Scope::Assembly),
        }
    }

    /// `*NSET` (`element == false`) or `*ELSET`.
    pub(super) fn set(
        &mut self,
        keyword: &Keyword,
        data: &[Data],
        element: bool,
    ) -> Result<(), ImportError> {
        let (param, kind, what) = match element {
            true => ("ELSET", SetKind::Element, "element"),
            false => ("NSET", SetKind::Node, "node"),
        };
        self.check_params(
            keyword,
            &[param, "GENERATE", "INSTANCE", "INTERNAL", "UNSORTED"],
        )?;
        self.in_scope(
            keyword,
            &[Scope::Model, Scope::Part, Scope::Assembly],
            "sets belong to the part or the assembly",
        )?;
        let name = self.require(keyword, param)?.to_string();
        let labels_allowed = self.labels_allowed(keyword)?;
        let head = format!("*{}, {param}={}", keyword.name, short(&name));
        let mut entries = Vec::new();
        for d in data {
            let err = |m: String| self.error(d.loc, format!("{head}: {m}"));
            if keyword.has("GENERATE") {
                if !labels_allowed {
                    return Err(err("labels at assembly level need INSTANCE=".into()));
                }
                if !(2..=3).contains(&d.fields.len()) {
                    return Err(err(format!(
                        "GENERATE expects first, last[, step], found {} fields",
                        d.fields.len()
                    )));
                }
                let number = |f: &str| {
                    f.parse::<i64>()
                        .map_err(|_| err(format!("GENERATE: '{}' is not an integer", short(f))))
                };
                let first = number(d.fields[0])?;
                let last = number(d.fields[1])?;
                let step = match d.fields.get(2) {
                    Some(f) => number(f)?,
                    None => 1,
                };
                if step <= 0 || first <= 0 || last < first {
                    return Err(err(format!(
                        "GENERATE {first}, {last}, {step}: needs 0 < first <= last and step >= 1"
                    )));
                }
                entries.push(Entry {
                    member: Member::Range { first, last, step },
                    loc: d.loc,
                });
                continue;
            }
            for field in d.fields.iter().filter(|f| !f.is_empty()) {
                if field.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+') {
                    let l = label(field).ok_or_else(|| {
                        err(format!(
                            "{what} label '{}' is not a positive integer",
                            short(field)
                        ))
                    })?;
                    if !labels_allowed {
                        return Err(err(format!(
                            "{what} label {l} at assembly level needs INSTANCE="
                        )));
                    }
                    entries.push(Entry {
                        member: Member::Label(l),
                        loc: d.loc,
                    });
                } else {
                    let named = self.named(kind, field).ok_or_else(|| {
                        err(format!(
                            "no {what} set named '{}' is defined before this line",
                            short(field)
                        ))
                    })?;
                    entries.extend_from_slice(named);
                }
            }
        }
        self.add_to(kind, &name, entries, keyword.loc)
    }

    pub(super) fn surface(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        self.check_params(keyword, &["NAME", "TYPE", "INTERNAL"])?;
        self.in_scope(
            keyword,
            &[Scope::Model, Scope::Part, Scope::Assembly],
            "surfaces belong to the part or the assembly",
        )?;
        let name = self.require(keyword, "NAME")?.to_string();
        let head = format!("*SURFACE, NAME={}", short(&name));
        match keyword.get("TYPE").map(str::to_ascii_uppercase).as_deref() {
            None | Some("ELEMENT") => {}
            Some(other) => {
                return Err(self.error(
                    keyword.loc,
                    format!(
                        "{head}: TYPE={} is not supported (node-based and other surfaces are \
                         not read; use TYPE=ELEMENT with faces S1..S6)",
                        short(other)
                    ),
                ));
            }
        }
        let labels_allowed = self.scope != Scope::Assembly;
        let mut faces = Vec::new();
        for d in data {
            let err = |m: String| self.error(d.loc, format!("{head}: {m}"));
            let (Some(target), Some(face)) = (d.fields.first(), d.fields.get(1)) else {
                return Err(err(
                    "expected 'element set or label, Sn' (a face identifier is required)".into(),
                ));
            };
            if d.fields.len() > 2 {
                return Err(err(format!("expected 2 fields, found {}", d.fields.len())));
            }
            let face = face
                .strip_prefix(['S', 's'])
                .and_then(|n| n.parse::<u8>().ok())
                .filter(|&n| n >= 1)
                .ok_or_else(|| {
                    err(format!(
                        "face identifier '{}' is not supported (S1..S6 on hexes, S1..S4 on tets)",
                        short(face)
                    ))
                })?;
            let entries: Vec<Entry> = if target.starts_with(|c: char| c.is_ascii_digit()) {
                let l = label(target).ok_or_else(|| {
                    err(format!(
                        "element label '{}' is not a positive integer",
                        short(target)
                    ))
                })?;
                if !labels_allowed {
                    return Err(err(format!(
                        "element label {l} at assembly level: name an element set"
                    )));
                }
                vec![Entry {
                    member: Member::Label(l),
                    loc: d.loc,
                }]
            } else {
                let named = self.named(SetKind::Element, target).ok_or_else(|| {
                    err(format!(
                        "no element set named '{}' is defined before this line",
                        short(target)
                    ))
                })?;
                // The face line is where a wrong face is reported.
                named.iter().map(|e| Entry { loc: d.loc, ..*e }).collect()
            };
            faces.extend(entries.into_iter().map(|e| (e, face - 1)));
        }
        self.count_copies(faces.len(), keyword.loc)?;
        let lower = name.to_ascii_lowercase();
        match self.surfaces.get(&lower) {
            Some(&i) => {
                if let Some((_, list)) = self.raw.surfaces.get_mut(i) {
                    list.extend(faces);
                }
            }
            None => {
                self.raw.surfaces.push((name, faces));
                self.surfaces.insert(lower, self.raw.surfaces.len() - 1);
            }
        }
        Ok(())
    }

    pub(super) fn instance(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        self.check_params(keyword, &["NAME", "PART"])?;
        self.in_scope(
            keyword,
            &[Scope::Assembly],
            "an instance belongs to the assembly",
        )?;
        let name = self.require(keyword, "NAME")?.to_string();
        let part = self.require(keyword, "PART")?;
        if let Some(first) = &self.instance {
            return Err(self.error(
                keyword.loc,
                format!(
                    "second *INSTANCE '{}' (instance '{}' at line {}): only one part and one \
                     instance are supported",
                    short(&name),
                    first.name,
                    first.loc.line
                ),
            ));
        }
        match &self.part {
            Some((p, _)) if p.eq_ignore_ascii_case(part) => {}
            _ => {
                return Err(self.error(
                    keyword.loc,
                    format!(
                        "*INSTANCE '{}': PART={} is not the part defined before ({})",
                        short(&name),
                        short(part),
                        self.part.as_ref().map_or("none", |(p, _)| p.as_str())
                    ),
                ));
            }
        }
        let mut numbers = Vec::new();
        for (d, expected) in data.iter().zip([3, 7]) {
            if d.fields.len() != expected {
                return Err(self.error(
                    d.loc,
                    format!(
                        "*INSTANCE: expected {expected} numbers on this line (translation: 3; \
                         rotation: point a, point b, angle), found {}",
                        d.fields.len()
                    ),
                ));
            }
            for field in &d.fields {
                let value = real(field).filter(|v| v.is_finite()).ok_or_else(|| {
                    self.error(
                        d.loc,
                        format!("*INSTANCE: '{}' is not a finite number", short(field)),
                    )
                })?;
                numbers.push(value);
            }
        }
        if let Some(d) = data.get(2) {
            return Err(self.error(
                d.loc,
                "*INSTANCE: at most 2 data lines (translation, rotation)",
            ));
        }
        let n = |i: usize| numbers.get(i).copied().unwrap_or(0.0);
        self.instance = Some(Instance {
            name,
            translation: [n(0), n(1), n(2)],
            rotation: (numbers.len() == 10).then(|| ([n(3), n(4), n(5)], [n(6), n(7), n(8)], n(9))),
            loc: keyword.loc,
        });
        self.scope = Scope::Instance;
        self.scope_loc = keyword.loc;
        Ok(())
    }
}
