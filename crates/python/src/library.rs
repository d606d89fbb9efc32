//! The material library every call of the module uses: the built-in materials (and,
//! once registered, those defined in Python).

use musclefem_materials::MaterialLibrary;

/// The library a scene, a material point or `materials()` sees.
pub(crate) fn material_library() -> MaterialLibrary {
    MaterialLibrary::with_builtins()
}
