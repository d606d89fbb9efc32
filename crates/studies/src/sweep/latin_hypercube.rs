//! Latin-hypercube sampling: N runs that cover each parameter's range evenly. Each axis's
//! range [min, max] of its values is cut into N equal strata; every stratum holds exactly
//! one run, at a uniformly random point inside it, and the strata of the different axes
//! are paired by independent random permutations. Reproducible: the same seed gives the
//! same runs.

use super::vary::Axis;

/// `samples` runs (one `Vec` per run in axis order) from the generator seeded with `seed`.
pub fn latin_hypercube(axes: &[Axis], samples: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut runs = vec![Vec::with_capacity(axes.len()); samples];
    for axis in axes {
        let (lo, hi) = axis.range();
        let mut strata: Vec<usize> = (0..samples).collect();
        rng.shuffle(&mut strata);
        for (run, stratum) in runs.iter_mut().zip(strata) {
            let u = (stratum as f64 + rng.f64()) / samples as f64;
            run.push(lo + (hi - lo) * u);
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_stratum_of_each_axis_holds_one_run() {
        let axes = [
            Axis {
                name: "b".into(),
                values: vec![10.0, 20.0],
            },
            Axis {
                name: "sigma0".into(),
                values: vec![5e5, 9e5, 7e5],
            },
        ];
        let samples = 8;
        let runs = latin_hypercube(&axes, samples, 7);
        assert_eq!(runs.len(), samples);
        for (j, axis) in axes.iter().enumerate() {
            let (lo, hi) = axis.range();
            let mut strata: Vec<usize> = runs
                .iter()
                .map(|run| {
                    assert!((lo..=hi).contains(&run[j]));
                    ((run[j] - lo) / (hi - lo) * samples as f64) as usize
                })
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..samples).collect::<Vec<_>>());
        }
        assert_eq!(runs, latin_hypercube(&axes, samples, 7));
        assert_ne!(runs, latin_hypercube(&axes, samples, 8));
    }
}
