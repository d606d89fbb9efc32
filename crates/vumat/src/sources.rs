//! The adapters' sources (`plugins/abaqus_vumat`) and the plugin ABI header, compiled into
//! this crate so that an installed `musclefem` builds VUMAT and UMAT plugins without the
//! repository.

use musclefem_materials::plugin::C_HEADER;

/// Abaqus/Standard's include file for UMATs (`INCLUDE 'ABA_PARAM.INC'`).
const ABA_PARAM: &str = include_str!("../../../plugins/abaqus_vumat/aba_param.inc");

/// (file name, contents) of every file the build writes next to `vumat_config.h`. Both
/// kinds get all of them; [`crate::Subroutine::c_files`] says which are compiled. The UMAT
/// include file is written under both spellings UMATs use (Linux file names are
/// case-sensitive).
pub const ADAPTER_FILES: [(&str, &str); 12] = [
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
        "musclefem_umat.h",
        include_str!("../../../plugins/abaqus_vumat/musclefem_umat.h"),
    ),
    (
        "adapter.c",
        include_str!("../../../plugins/abaqus_vumat/adapter.c"),
    ),
    (
        "umat_adapter.c",
        include_str!("../../../plugins/abaqus_vumat/umat_adapter.c"),
    ),
    (
        "umat_tangent.c",
        include_str!("../../../plugins/abaqus_vumat/umat_tangent.c"),
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
    ("aba_param.inc", ABA_PARAM),
    ("ABA_PARAM.INC", ABA_PARAM),
];
