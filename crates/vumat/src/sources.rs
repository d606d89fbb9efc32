//! The adapter's sources (`plugins/abaqus_vumat`) and the plugin ABI header, compiled into
//! this crate so that an installed `musclefem` builds VUMAT plugins without the repository.

use musclefem_materials::plugin::C_HEADER;

/// (file name, contents) of every file the build writes next to `vumat_config.h`.
pub const ADAPTER_FILES: [(&str, &str); 7] = [
    ("musclefem_material.h", C_HEADER),
    (
        "matrix3.h",
        include_str!("../../../plugins/abaqus_vumat/matrix3.h"),
    ),
    (
        "musclefem_vumat.h",
        include_str!("../../../plugins/abaqus_vumat/musclefem_vumat.h"),
    ),
    (
        "adapter.c",
        include_str!("../../../plugins/abaqus_vumat/adapter.c"),
    ),
    (
        "kinematics.c",
        include_str!("../../../plugins/abaqus_vumat/kinematics.c"),
    ),
    (
        "abaqus_utilities.c",
        include_str!("../../../plugins/abaqus_vumat/abaqus_utilities.c"),
    ),
    (
        "vaba_param.inc",
        include_str!("../../../plugins/abaqus_vumat/vaba_param.inc"),
    ),
];

/// The C files among [`ADAPTER_FILES`], compiled one by one.
pub const C_FILES: [&str; 3] = ["adapter.c", "kinematics.c", "abaqus_utilities.c"];
