//! A material implemented by a plugin: the [`Material`] the host's solvers see.

use std::ffi::c_char;
use std::path::PathBuf;
use std::sync::Arc;

use libloading::Library;

use super::abi;
use crate::material::{PointBlock, PointResponse, StateVariable, check_shapes};
use crate::{Material, MaterialError};

/// Size of the buffer the plugin may write an error message into.
const MESSAGE_CAPACITY: usize = 1024;

/// A plugin material with its resolved parameter values.
///
/// Thread safety: every field is `Send + Sync` on its own (owned strings and vectors, a
/// plain function pointer, and `Arc<Library>`; libloading implements `Send`/`Sync` for
/// `Library`, whose handle may be used from any thread), so no `unsafe impl` is needed and
/// the compiler derives `Send + Sync` as [`Material`] requires. What the type system
/// cannot see is whether the plugin's `update` may really run on several threads at once:
/// that is part of the ABI contract (`include/musclefem_material.h`, rule 2: `update` is
/// reentrant, each call gets its own block and output arrays, no unsynchronised global
/// state). A call never shares a mutable array with another call, because each `compute`
/// gets its own `&mut` response.
#[derive(Debug)]
pub(crate) struct PluginMaterial {
    pub name: String,
    pub path: PathBuf,
    /// Parameter values in declared order: the `properties` of every block.
    pub properties: Vec<f64>,
    pub states: Vec<StateVariable>,
    pub provides_tangent: bool,
    /// Points into `library`'s code: valid exactly as long as the library stays loaded,
    /// which `_library` below guarantees for as long as this value exists.
    pub update: unsafe extern "C" fn(*const abi::PointBlock, *mut c_char, u64) -> i32,
    /// Keeps the shared library loaded while this material (and so `update`) exists,
    /// even after the factory and the `MaterialLibrary` that loaded it are dropped.
    pub _library: Arc<Library>,
}

impl Material for PluginMaterial {
    fn name(&self) -> &str {
        &self.name
    }

    fn state_variables(&self) -> &[StateVariable] {
        &self.states
    }

    fn provides_tangent(&self) -> bool {
        self.provides_tangent
    }

    /// One serial call of the plugin for the whole block (callers parallelise over
    /// blocks). The slices are handed over by pointer casts, without copying (layouts
    /// checked in `abi.rs`).
    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        let n = block.len();
        check_shapes(self.states.len(), block, response)?;
        if n == 0 {
            return Ok(());
        }
        // A tangent is only handed to a plugin that says it fills it; for the others
        // `<dyn Material>::update` builds it by finite differences.
        let tangent_ptr = match response.tangent.as_deref_mut() {
            Some(t) if self.provides_tangent => t.as_mut_ptr().cast::<f64>(),
            _ => std::ptr::null_mut(),
        };
        let c_block = abi::PointBlock {
            struct_size: size_of::<abi::PointBlock>() as u64,
            point_count: n as u64,
            time: block.time,
            dt: block.dt,
            properties: self.properties.as_ptr(),
            property_count: self.properties.len() as u64,
            deformation_gradient_old: block.deformation_gradient_old.as_ptr().cast(),
            deformation_gradient_new: block.deformation_gradient_new.as_ptr().cast(),
            fiber_direction: block.fiber_direction.as_ptr().cast(),
            state_old: block.state_old.as_ptr(),
            state_new: response.state_new.as_mut_ptr(),
            cauchy_stress: response.cauchy_stress.as_mut_ptr().cast(),
            tangent: tangent_ptr,
        };
        let mut message = [0u8; MESSAGE_CAPACITY];
        // SAFETY: `update` comes from a table that passed the load checks and its library
        // is kept loaded by `self._library`. Every array pointer covers the lengths the
        // header promises: `check_shapes` above made sure all slices hold n points
        // (n·state_count state values; `compute` is a safe public method, so it does not
        // rely on `<dyn Material>::update` having checked); the nalgebra element types are
        // exactly 9, 3, 6 and 81 contiguous f64 (asserted in abi.rs); outputs are borrowed
        // mutably and exclusively for this call. The message buffer holds
        // MESSAGE_CAPACITY bytes.
        let code = unsafe {
            (self.update)(
                &c_block,
                message.as_mut_ptr().cast::<c_char>(),
                MESSAGE_CAPACITY as u64,
            )
        };
        if code != 0 {
            let end = message
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(message.len());
            let text = String::from_utf8_lossy(&message[..end]);
            let text = if text.trim().is_empty() {
                "(no message)".into()
            } else {
                text
            };
            return Err(MaterialError::Plugin {
                path: self.path.clone(),
                message: format!(
                    "material '{}' failed on a block of {n} points (error code {code}): {text}",
                    self.name
                ),
            });
        }
        Ok(())
    }
}
