//! TEMPORARY placeholder while the plugin loader is written (not to be committed).
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use crate::registry::MaterialInfo;
use crate::{Material, MaterialError};

pub struct PluginMaterialFactory {
    info: MaterialInfo,
}

impl PluginMaterialFactory {
    pub fn load(path: &Path) -> Result<Self, MaterialError> {
        Err(MaterialError::Plugin { path: path.to_path_buf(), message: "todo".into() })
    }
    pub fn name(&self) -> &str {
        &self.info.name
    }
    pub fn info(&self) -> MaterialInfo {
        self.info.clone()
    }
    pub fn create(&self, _given: &BTreeMap<String, f64>) -> Result<Arc<dyn Material>, MaterialError> {
        todo!()
    }
}
