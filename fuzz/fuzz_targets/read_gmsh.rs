//! Any bytes given to the Gmsh reader (text or 4.1 binary) return a mesh or an error,
//! never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = musclefem_io::mesh_import::parse_gmsh_bytes(data.to_vec(), "fuzz.msh");
});
