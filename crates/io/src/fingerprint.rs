//! A short, stable fingerprint of inputs: [`fnv1a`], so that results made from one input
//! are not taken for another's (sweep rows, checkpoints); [`model_fingerprint`] of what a
//! run computes (its settings as text and its mesh).

use musclefem_mesh::Mesh;

/// The 64-bit FNV-1a hash of `bytes` (stable across platforms and program versions).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The fingerprint of a model: [`fnv1a`] of `settings` (the scene text and the analysis,
/// or a study's settings, as text) followed by the mesh's node coordinates and each
/// block's name and connectivity. A checkpoint resumes only the model whose fingerprint
/// it carries.
pub fn model_fingerprint(settings: &str, mesh: &Mesh) -> u64 {
    let mut bytes = settings.as_bytes().to_vec();
    for node in 0..mesh.nodes.len() {
        let x = mesh.nodes.position(node);
        x.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    for block in &mesh.blocks {
        bytes.extend(block.name.as_bytes());
        block
            .connectivity
            .iter()
            .for_each(|id| bytes.extend(id.to_le_bytes()));
    }
    fnv1a(&bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        // The reference values of the FNV-1a specification.
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
