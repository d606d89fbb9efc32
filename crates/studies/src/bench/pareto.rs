//! The Pareto front of a set of runs: those that no other run beats in both wall time and
//! error (one run dominates another if it is no slower and no less accurate, and better in
//! one of the two).

/// Indices of the non-dominated points among `(wall time, error)`, in order of increasing
/// time. Points with a non-finite coordinate are left out, and so is a slower point whose
/// error is within [`EQUAL_ERROR`] of a faster one's (the same result at a higher cost).
/// Errors closer than this, relatively, are the same (round-off of one discretisation).
pub const EQUAL_ERROR: f64 = 1e-6;

pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let finite = |i: &usize| points[*i].0.is_finite() && points[*i].1.is_finite();
    let mut order: Vec<usize> = (0..points.len()).filter(finite).collect();
    // By time, ties by error: a point is on the front iff it is more accurate than every
    // faster one.
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front = Vec::new();
    let mut best_error = f64::INFINITY;
    for i in order {
        if points[i].1 < best_error * (1.0 - EQUAL_ERROR) {
            best_error = points[i].1;
            front.push(i);
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_and_failed_runs_are_not_on_the_front() {
        let points = [
            (1.0, 0.10),                 // front: fastest
            (2.0, 0.20),                 // dominated by 0
            (3.0, 0.01),                 // front
            (3.0, 0.05),                 // dominated by 2 (same time, larger error)
            (0.5, f64::NAN),             // failed
            (5.0, 0.001),                // front
            (6.0, 0.001),                // dominated by 5
            (7.0, 0.001 * (1.0 - 1e-9)), // the same error as 5, slower
        ];
        assert_eq!(pareto_front(&points), vec![0, 2, 5]);
        assert!(pareto_front(&[]).is_empty());
    }
}
