//! The layers of a swept muscle along its centreline: cross-sections spaced in proportion
//! to the local section size √(ab), Z(s) = ∫ ds / √(ab), segment by segment between
//! junctions.

use super::centreline::invert;
use super::{HALF_THICKNESS, HALF_WIDTH, MeshError, SweptSolid, invalid};

impl SweptSolid {
    /// Arclengths s_0 = 0 < … < s_layers = L [m] of `layers + 1` cross-sections spaced in
    /// proportion to the local size √(ab): equal steps of Z(s) = ∫ ds / √(ab).
    pub fn graded_stations(&self, layers: usize) -> Vec<f64> {
        self.graded_stations_with_junctions(layers, &[])
            .expect("without junctions the grading cannot fail")
    }

    /// [`Self::graded_stations`] with a cross-section at each of the `junctions`
    /// (arclengths [m], increasing, inside (0, L)): the segments between them get
    /// layers in proportion to their share of Z (at least one each, `layers` in all), and
    /// each segment is graded on its own. Errors if a junction is out of order or out of
    /// range, or if there are fewer layers than segments.
    pub fn graded_stations_with_junctions(
        &self,
        layers: usize,
        junctions: &[f64],
    ) -> Result<Vec<f64>, MeshError> {
        self.graded_segments(junctions, |shares| {
            if layers.max(1) < shares.len() {
                return Err(invalid(format!(
                    "{layers} layers cannot mesh {} segments between junctions",
                    shares.len()
                )));
            }
            Ok(apportion(layers.max(1), shares))
        })
    }

    /// Arclengths of the cross-sections with `segment_layers[i]` layers in the segment
    /// before junction `i` (and the last after the last junction), each segment graded
    /// on its own. Errors as [`Self::graded_stations_with_junctions`], and unless there is
    /// one count (≥ 1) per segment.
    pub fn graded_stations_per_segment(
        &self,
        junctions: &[f64],
        segment_layers: &[usize],
    ) -> Result<Vec<f64>, MeshError> {
        self.graded_segments(junctions, |shares| {
            if segment_layers.len() != shares.len() || segment_layers.contains(&0) {
                return Err(invalid(format!(
                    "{} segments need as many layer counts of at least 1, got {segment_layers:?}",
                    shares.len()
                )));
            }
            Ok(segment_layers.to_vec())
        })
    }

    /// The graded sections between 0, the `junctions` and L, with the layers per segment
    /// that `layers_of(shares of Z)` returns.
    fn graded_segments(
        &self,
        junctions: &[f64],
        layers_of: impl FnOnce(&[f64]) -> Result<Vec<usize>, MeshError>,
    ) -> Result<Vec<f64>, MeshError> {
        let length = self.length();
        let mut ends = vec![0.0];
        for &s in junctions {
            let previous = ends[ends.len() - 1];
            if !(s.is_finite() && s > previous && s < length) {
                return Err(invalid(format!(
                    "junction at arclength {s} m must lie after {previous} m and before the \
                     end of the centreline ({length} m)"
                )));
            }
            ends.push(s);
        }
        ends.push(length);
        let segments = ends.len() - 1;
        let density = |t: f64| self.size_density(t);
        let table = self.curve.cumulative(density);
        let z_ends: Vec<f64> = ends.iter().map(|&s| self.sizes_along(&table, s)).collect();
        let total = z_ends[segments] - z_ends[0];
        let counts = layers_of(
            &(0..segments)
                .map(|i| (z_ends[i + 1] - z_ends[i]) / total)
                .collect::<Vec<_>>(),
        )?;
        let mut stations = vec![0.0];
        for i in 0..segments {
            for k in 1..=counts[i] {
                if k == counts[i] {
                    stations.push(ends[i + 1]);
                } else {
                    let z = z_ends[i] + (z_ends[i + 1] - z_ends[i]) * k as f64 / counts[i] as f64;
                    stations.push(self.arclength_of(invert(&table, z, density)));
                }
            }
        }
        Ok(stations)
    }

    /// dZ/dt = |c'(t)| / √(a b): the density of the grading in section sizes [1].
    fn size_density(&self, t: f64) -> f64 {
        self.curve.derivative(t).norm()
            / (self.curve.profile(HALF_WIDTH, t) * self.curve.profile(HALF_THICKNESS, t)).sqrt()
    }

    /// Z(s) from the cumulative `table` of [`Self::size_density`] (linear between its
    /// entries).
    pub(super) fn sizes_along(&self, table: &[(f64, f64)], s: f64) -> f64 {
        let t = invert(&self.arclength, s, |t| self.curve.derivative(t).norm());
        let j = table
            .partition_point(|&(tj, _)| tj < t)
            .clamp(1, table.len() - 1);
        let ((t0, z0), (t1, z1)) = (table[j - 1], table[j]);
        if t1 == t0 {
            z0
        } else {
            z0 + (z1 - z0) * (t - t0) / (t1 - t0)
        }
    }

    /// Z(s₁) − Z(s₀) = ∫ ds / √(ab) between arclengths `from` and `to` [m]: how many
    /// local section sizes the stretch spans (the measure the layers are graded by).
    pub fn section_sizes_between(&self, from: f64, to: f64) -> f64 {
        let table = self.curve.cumulative(|t| self.size_density(t));
        self.sizes_along(&table, to) - self.sizes_along(&table, from)
    }
}

/// `total` items split by the `shares` (summing to 1), at least one each, by largest
/// remainders: Σ = `total` whenever `total` ≥ the number of shares.
fn apportion(total: usize, shares: &[f64]) -> Vec<usize> {
    let spare = total - shares.len();
    let exact: Vec<f64> = shares.iter().map(|s| s * spare as f64).collect();
    let mut counts: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&i, &j| (exact[j] - exact[j].floor()).total_cmp(&(exact[i] - exact[i].floor())));
    let left = spare - counts.iter().sum::<usize>();
    for &i in order.iter().take(left) {
        counts[i] += 1;
    }
    counts.iter().map(|c| c + 1).collect()
}
