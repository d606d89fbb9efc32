//! The material registry: built-in materials register themselves with `inventory`;
//! plugins are added at run time from shared libraries. A [`MaterialLibrary`] is the
//! one place that turns a name and a parameter map into a ready material.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::hosted::HostedMaterial;
use crate::parameters::{ParameterSet, ParameterSpec};
use crate::plugin::PluginMaterialFactory;
use crate::{Material, MaterialError};

/// A built-in material's entry in the registry (submitted with `inventory::submit!`).
pub struct MaterialRegistration {
    /// Registry name (what scene files and `--material` use).
    pub name: &'static str,
    /// One line: what the material models.
    pub description: &'static str,
    /// Declared parameters with units, defaults and ranges.
    pub parameters: &'static [ParameterSpec],
    /// Build the material from checked parameter values.
    pub build: fn(&ParameterSet) -> Result<Arc<dyn Material>, MaterialError>,
}

inventory::collect!(MaterialRegistration);

/// Where a material comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialOrigin {
    BuiltIn,
    Plugin(PathBuf),
    /// Defined at run time by the host program, e.g. "Python" ([`HostedMaterial`]).
    Host(String),
}

/// What `musclefem materials` lists about one material.
#[derive(Debug, Clone)]
pub struct MaterialInfo {
    pub name: String,
    pub description: String,
    pub parameters: Vec<ParameterSpec>,
    pub origin: MaterialOrigin,
}

/// The built-in materials plus the plugins loaded and the hosted materials added so far.
#[derive(Default)]
pub struct MaterialLibrary {
    plugins: Vec<PluginMaterialFactory>,
    hosted: Vec<HostedMaterial>,
}

impl MaterialLibrary {
    /// A library holding the built-in materials only.
    pub fn with_builtins() -> Self {
        MaterialLibrary::default()
    }

    /// Load a plugin shared library and add its material. Its name must not clash with
    /// a material already known.
    pub fn load_plugin(&mut self, path: &Path) -> Result<MaterialInfo, MaterialError> {
        let factory = PluginMaterialFactory::load(path)?;
        let info = factory.info();
        if self.names().contains(&info.name) {
            return Err(MaterialError::Plugin {
                path: path.to_path_buf(),
                message: format!(
                    "it provides material '{}', which is already registered",
                    info.name
                ),
            });
        }
        self.plugins.push(factory);
        Ok(info)
    }

    /// Add a material defined by the host program. Its name must not clash with a
    /// material already known.
    pub fn add_hosted(&mut self, material: HostedMaterial) -> Result<(), MaterialError> {
        if self.names().contains(&material.name) {
            return Err(MaterialError::Host {
                material: material.name.clone(),
                message: "a material of this name is already registered".into(),
            });
        }
        self.hosted.push(material);
        Ok(())
    }

    /// Every known material, sorted by name.
    pub fn materials(&self) -> Vec<MaterialInfo> {
        let mut all: Vec<MaterialInfo> = builtin_registrations()
            .map(|r| MaterialInfo {
                name: r.name.to_string(),
                description: r.description.to_string(),
                parameters: r.parameters.to_vec(),
                origin: MaterialOrigin::BuiltIn,
            })
            .chain(self.plugins.iter().map(|p| p.info()))
            .chain(self.hosted.iter().map(HostedMaterial::info))
            .collect();
        all.sort_by(|a, b| a.name.cmp(&b.name));
        all
    }

    /// Names of every known material, sorted.
    pub fn names(&self) -> Vec<String> {
        self.materials().into_iter().map(|m| m.name).collect()
    }

    /// Description of one material, or an error listing the known ones.
    pub fn info(&self, name: &str) -> Result<MaterialInfo, MaterialError> {
        self.materials()
            .into_iter()
            .find(|m| m.name == name)
            .ok_or_else(|| MaterialError::UnknownMaterial {
                name: name.to_string(),
                valid: self.names(),
            })
    }

    /// Build material `name` from `given` parameter values (defaults fill the rest).
    pub fn create(
        &self,
        name: &str,
        given: &BTreeMap<String, f64>,
    ) -> Result<Arc<dyn Material>, MaterialError> {
        if let Some(registration) = builtin_registrations().find(|r| r.name == name) {
            let parameters = ParameterSet::resolve(name, registration.parameters, given)?;
            return (registration.build)(&parameters);
        }
        if let Some(plugin) = self.plugins.iter().find(|p| p.name() == name) {
            return plugin.create(given);
        }
        if let Some(hosted) = self.hosted.iter().find(|h| h.name == name) {
            return hosted.create(given);
        }
        Err(MaterialError::UnknownMaterial {
            name: name.to_string(),
            valid: self.names(),
        })
    }
}

/// The built-in registrations collected by `inventory`.
pub fn builtin_registrations() -> impl Iterator<Item = &'static MaterialRegistration> {
    inventory::iter::<MaterialRegistration>.into_iter()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_holds_every_builtin() {
        let names = MaterialLibrary::with_builtins().names();
        assert_eq!(
            names,
            vec![
                "hill".to_string(),
                "mooney-rivlin".to_string(),
                "neo-hookean".to_string(),
                "neo-hookean-coupled".to_string(),
                "tendon".to_string(),
                "trans-iso-mooney-rivlin".to_string(),
            ]
        );
    }

    #[test]
    fn a_hosted_material_is_listed_and_built_and_may_not_take_a_known_name() {
        use crate::hosted::HostedMaterial;
        use crate::neo_hookean::{NEO_HOOKEAN_PARAMETERS, NeoHookean};
        let hosted = |name: &str| HostedMaterial {
            name: name.to_string(),
            description: "a neo-Hookean solid defined by the host".into(),
            parameters: NEO_HOOKEAN_PARAMETERS.to_vec(),
            host: "a test".into(),
            build: Arc::new(
                |p: &ParameterSet| -> Result<Arc<dyn Material>, MaterialError> {
                    Ok(Arc::new(NeoHookean {
                        shear_modulus: p.get("mu")?,
                        compressibility: p.get("D")?,
                    }))
                },
            ),
        };
        let mut library = MaterialLibrary::with_builtins();
        library.add_hosted(hosted("hosted")).unwrap();
        let info = library.info("hosted").unwrap();
        assert_eq!(info.origin, MaterialOrigin::Host("a test".into()));
        let given = BTreeMap::from([("mu".to_string(), 2.0e4)]);
        assert_eq!(
            library.create("hosted", &given).unwrap().name(),
            "neo-hookean"
        );
        let wrong = BTreeMap::from([("sigma0".to_string(), 1.0)]);
        assert!(library.create("hosted", &wrong).is_err());
        for taken in ["hill", "hosted"] {
            let error = library.add_hosted(hosted(taken)).unwrap_err().to_string();
            assert!(error.contains("already registered"), "{error}");
        }
    }

    #[test]
    fn unknown_material_lists_valid_ones() {
        let err = MaterialLibrary::with_builtins()
            .create("neohooke", &BTreeMap::new())
            .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("'neohooke'") && text.contains(
                    "hill, mooney-rivlin, neo-hookean, neo-hookean-coupled, tendon, trans-iso-mooney-rivlin"
                ),
            "{text}"
        );
    }
}
