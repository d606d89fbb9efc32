//! The full-factorial design: every combination of the axes' values.

use super::vary::Axis;

/// Every combination of the axes' values, one `Vec` per run in axis order, the last axis
/// varying fastest. No axes: one run with the base parameters.
pub fn full_factorial(axes: &[Axis]) -> Vec<Vec<f64>> {
    let mut runs = vec![Vec::new()];
    for axis in axes {
        runs = runs
            .into_iter()
            .flat_map(|run| {
                axis.values.iter().map(move |&v| {
                    let mut next = run.clone();
                    next.push(v);
                    next
                })
            })
            .collect();
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_combination_once_last_axis_fastest() {
        let axes = [
            Axis {
                name: "b".into(),
                values: vec![10.0, 20.0],
            },
            Axis {
                name: "c".into(),
                values: vec![1.0, 2.0, 3.0],
            },
        ];
        let runs = full_factorial(&axes);
        assert_eq!(
            runs,
            vec![
                vec![10.0, 1.0],
                vec![10.0, 2.0],
                vec![10.0, 3.0],
                vec![20.0, 1.0],
                vec![20.0, 2.0],
                vec![20.0, 3.0],
            ]
        );
        assert_eq!(full_factorial(&[]), vec![Vec::<f64>::new()]);
    }
}
