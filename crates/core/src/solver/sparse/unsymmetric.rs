//! The implicit solver's unsymmetric tangents (see `sparse.rs`): GMRES preconditioned
//! with a factor of the symmetric part, LU where that fails, and the mass shift of a
//! correction with negative curvature.

use std::time::Instant;

use super::{
    Factorization, GMRES_MAX_ITERATIONS, GMRES_TOLERANCE, MASS_SHIFTS, SparseSystem,
    SymmetricFactor,
};

impl SparseSystem {
    /// K x = `rhs` for an unsymmetric K (sliding interfaces and contact along smooth
    /// normals), shifted by the mass where K is indefinite along its own correction.
    ///
    /// **Solves.** By GMRES preconditioned with a factor of the symmetric part
    /// ½(K + Kᵀ) in the Cholesky analysis (METIS's order): its Cholesky factor, or its
    /// LBLᵀ factor when it is indefinite ([`GMRES_TOLERANCE`],
    /// [`GMRES_MAX_ITERATIONS`]); by LU when GMRES does not converge or the pattern is
    /// not symmetric. faer's LU orders the columns by COLAMD on the structure of KᵀK: on
    /// the coarse knee one LU cost several Cholesky factorizations of the same matrix.
    ///
    /// **Mass shift** (with `mass_shift`, as [`Self::solve`]). A correction x along
    /// which K has negative curvature (xᵀ K x = xᵀ b ≤ 0) is replaced, as a symmetric K
    /// is shifted when Cholesky finds it indefinite, by the solve with K + (s − 1) M c for
    /// the first of the [`MASS_SHIFTS`] s whose symmetric part Cholesky accepts (the
    /// matrix left shifted, as in [`Self::factorize_mass_shifted`]); K's own when none
    /// does. A definite symmetric part gives positive curvature by itself. Without this
    /// an unsymmetric tangent lost the protection the mass shift gives the symmetric one:
    /// on the active knee squat, single corrections that raised the residual to 1e200.
    /// (Testing the symmetric part at every solve and shifting it whenever indefinite
    /// shifted the passive squat's tangents from the start, and its increments fell from
    /// 20 ms to 1 ms.)
    pub(super) fn solve_unsymmetric(
        &mut self,
        rhs: &mut [f64],
        mass_shift: Option<(&[usize], &[f64])>,
    ) -> Result<Factorization, String> {
        let lu_failed = |e: String| format!("LU failed ({e})");
        if !self.pattern_is_symmetric() {
            self.factorize_lu(rhs).map_err(lu_failed)?;
            return Ok(Factorization::Lu);
        }
        let b = rhs.to_vec();
        // K's own correction.
        let definite = self.factorize_symmetric_part(0.0, mass_shift, SymmetricFactor::Cholesky);
        if definite && self.gmres_with_symmetric_factor(rhs, SymmetricFactor::Cholesky) {
            return Ok(Factorization::SymmetricPartGmres);
        }
        let used = if !definite
            && self.factorize_symmetric_part(0.0, mass_shift, SymmetricFactor::Lblt)
            && self.gmres_with_symmetric_factor(rhs, SymmetricFactor::Lblt)
        {
            Factorization::SymmetricPartGmres
        } else {
            self.factorize_lu(rhs).map_err(lu_failed)?;
            Factorization::Lu
        };
        let Some((positions, masses)) = mass_shift else {
            return Ok(used);
        };
        if rhs.iter().zip(&b).map(|(x, b)| x * b).sum::<f64>() > 0.0 {
            return Ok(used);
        }
        // Negative curvature along K's own correction: the first shift that makes the
        // symmetric part definite.
        let own = rhs.to_vec();
        for shift in MASS_SHIFTS {
            let added = shift - 1.0;
            if !self.factorize_symmetric_part(added, mass_shift, SymmetricFactor::Cholesky) {
                continue;
            }
            let values = self.matrix.val_mut();
            for (&position, &mass) in positions.iter().zip(masses) {
                values[position] += added * mass;
            }
            self.statistics.mass_shifted_factorizations += 1;
            rhs.copy_from_slice(&b);
            if self.gmres_with_symmetric_factor(rhs, SymmetricFactor::Cholesky) {
                return Ok(Factorization::SymmetricPartGmres);
            }
            self.factorize_lu(rhs).map_err(lu_failed)?;
            return Ok(Factorization::Lu);
        }
        rhs.copy_from_slice(&own);
        Ok(used)
    }

    /// Whether every stored entry's transpose is stored (the pattern is symmetric).
    fn pattern_is_symmetric(&mut self) -> bool {
        let transpose = self.take_transpose();
        let symmetric = !transpose.is_empty();
        self.transpose = Some(transpose);
        symmetric
    }

    /// Factorizes ½(K + Kᵀ) + `added` M c (`mass_shift`'s diagonal positions and mass
    /// terms; none without it) by `kind` in the Cholesky analysis, keeping the factor for
    /// [`Self::gmres_with_symmetric_factor`]; true when the factorization succeeded. K is
    /// left as it was; the pattern must be symmetric.
    fn factorize_symmetric_part(
        &mut self,
        added: f64,
        mass_shift: Option<(&[usize], &[f64])>,
        kind: SymmetricFactor,
    ) -> bool {
        let transpose = self.take_transpose();
        let original = self.matrix.val().to_vec();
        let values = self.matrix.val_mut();
        for (p, &t) in transpose.iter().enumerate() {
            values[p] = 0.5 * (original[p] + original[t]);
        }
        if let Some((positions, masses)) = mass_shift {
            for (&position, &mass) in positions.iter().zip(masses) {
                values[position] += added * mass;
            }
        }
        self.transpose = Some(transpose);
        let factorized = match kind {
            SymmetricFactor::Cholesky => {
                let mut scratch = vec![0.0; self.size()];
                self.factorize_cholesky(&mut scratch).is_ok()
            }
            SymmetricFactor::Lblt => self.factorize_lblt().is_ok(),
        };
        self.matrix.val_mut().copy_from_slice(&original);
        // The factor is of the symmetric part, not of a symmetric K to come.
        self.cholesky_is_fresh = false;
        factorized
    }

    /// GMRES on the stored K, preconditioned with the factor of `kind` at hand; true
    /// with the solution in `rhs`, false with `rhs` unchanged.
    fn gmres_with_symmetric_factor(&mut self, rhs: &mut [f64], kind: SymmetricFactor) -> bool {
        let start = Instant::now();
        let outcome = self.gmres_with_factor(rhs, kind, GMRES_TOLERANCE, GMRES_MAX_ITERATIONS);
        self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
        match outcome {
            Some(iterations) => {
                self.statistics.krylov_solves += 1;
                self.statistics.krylov_iterations += iterations;
                true
            }
            None => {
                self.statistics.krylov_failures += 1;
                false
            }
        }
    }

    /// For every stored entry (r, c), where (c, r) is stored; empty when the pattern is
    /// not symmetric. Built on the first call; put it back in `self.transpose` after use.
    fn take_transpose(&mut self) -> Vec<usize> {
        if self.transpose.is_none() {
            let symbolic = self.matrix.symbolic();
            let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
            let mut transpose = Vec::with_capacity(row_idx.len());
            for column in 0..self.size() {
                for &row in &row_idx[col_ptr[column]..col_ptr[column + 1]] {
                    match self.find(column, row) {
                        Some(p) => transpose.push(p),
                        None => {
                            transpose.clear();
                            break;
                        }
                    }
                }
            }
            self.transpose = Some(transpose);
        }
        self.transpose.take().expect("just built")
    }
}
