//! Materials defined at run time by the program that hosts this library — the Python
//! module's `musclefem.register_material` — rather than compiled in or loaded from a
//! plugin: a parameter table and a function that builds the material from checked
//! values. A [`MaterialLibrary`](crate::MaterialLibrary) holds them beside the built-in
//! materials and the plugins ([`MaterialLibrary::add_hosted`](crate::MaterialLibrary::add_hosted)).

use std::fmt;
use std::sync::Arc;

use crate::parameters::{ParameterSet, ParameterSpec};
use crate::registry::{MaterialInfo, MaterialOrigin};
use crate::{Material, MaterialError};

/// Builds a hosted material from its resolved parameter values.
pub type HostedBuild =
    Arc<dyn Fn(&ParameterSet) -> Result<Arc<dyn Material>, MaterialError> + Send + Sync>;

/// A material defined by the host program.
#[derive(Clone)]
pub struct HostedMaterial {
    /// Registry name (what scene files use as `model`).
    pub name: String,
    /// One line: what the material models.
    pub description: String,
    /// Declared parameters with units, defaults and ranges.
    pub parameters: Vec<ParameterSpec>,
    /// Who defined it, e.g. "Python".
    pub host: String,
    pub build: HostedBuild,
}

impl HostedMaterial {
    /// What `materials()` lists (origin: the host).
    pub fn info(&self) -> MaterialInfo {
        MaterialInfo {
            name: self.name.clone(),
            description: self.description.clone(),
            parameters: self.parameters.clone(),
            origin: MaterialOrigin::Host(self.host.clone()),
        }
    }

    /// The material from `given` parameter values: resolved against the declared
    /// parameters by [`ParameterSet::resolve`], exactly like a built-in.
    pub fn create(
        &self,
        given: &std::collections::BTreeMap<String, f64>,
    ) -> Result<Arc<dyn Material>, MaterialError> {
        let parameters = ParameterSet::resolve(&self.name, &self.parameters, given)?;
        (self.build)(&parameters)
    }
}

impl fmt::Debug for HostedMaterial {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HostedMaterial")
            .field("name", &self.name)
            .field("host", &self.host)
            .field("parameters", &self.parameters)
            .finish_non_exhaustive()
    }
}
