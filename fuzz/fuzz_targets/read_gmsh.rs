//! Any text given to the Gmsh reader returns a mesh or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = musclefem_io::mesh_import::parse_gmsh(text, "fuzz.msh");
    }
});
