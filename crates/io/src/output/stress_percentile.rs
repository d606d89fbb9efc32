//! History columns of each part's von Mises percentile (`[output] von_mises_percentile`):
//! at every recorded instant, the p-quantile over the part's elements of the von Mises
//! stress of each element's mean Cauchy stress, each element counted once
//! ([`musclefem_core::solver::element_fields::percentile`]): the paper's outcome measure,
//! "the 95 % von Mises stress" of a muscle. Columns `von_mises_p<P>_<part>_pa`, after all
//! the others.

use std::path::Path;

use musclefem_core::solver::Snapshot;
use musclefem_core::solver::element_fields::percentile;

use crate::OutputError;

/// Which percentile, of which parts.
#[derive(Clone, Debug, PartialEq)]
pub struct VonMisesPercentile {
    /// The percentile P ∈ (0, 100) (95: the value 95 % of the elements do not exceed).
    pub percent: f64,
    /// (part name, its block in the mesh), in the order of the columns.
    pub parts: Vec<(String, usize)>,
}

impl VonMisesPercentile {
    /// The column names: `von_mises_p95_<part>_pa` (the percent as written, e.g. p99.5).
    pub fn columns(&self) -> Vec<String> {
        self.parts
            .iter()
            .map(|(name, _)| format!("von_mises_p{}_{name}_pa", self.percent))
            .collect()
    }

    /// The value of each column at the instant of `snapshot` [Pa].
    pub fn values(&self, snapshot: &Snapshot, path: &Path) -> Result<Vec<f64>, OutputError> {
        let fields = snapshot.element_fields().map_err(|e| OutputError::Data {
            path: path.to_path_buf(),
            message: format!("the element fields at t = {} s: {e}", snapshot.time),
        })?;
        self.parts
            .iter()
            .map(|(name, block)| {
                let part =
                    fields
                        .iter()
                        .find(|f| f.block == *block)
                        .ok_or_else(|| OutputError::Data {
                            path: path.to_path_buf(),
                            message: format!("no element fields of part '{name}' (block {block})"),
                        })?;
                Ok(percentile(&part.von_mises(), self.percent / 100.0).unwrap_or(0.0))
            })
            .collect()
    }
}
