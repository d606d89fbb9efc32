//! The Hill model's normalised force–length relations against measured rabbit tibialis
//! anterior data (Winters, Takahashi, Lieber & Ward 2011, J Biomech 44:109, Fig. 3C, as
//! digitised by M. Millard, MIT licence), read from `../shared/data/rabbit_ta/`.
//!
//! - active: f_λ(r) with r = fiber length / optimal length against `RelForce`/100;
//! - passive: σ_PE/σ₀ = A (λ̄_f − 1)² with λ̄_f = λ_opt (1 + strain) (the data's strain is
//!   relative to the optimal length, the model's stretch to the rest length) against
//!   `ta`/100.
//!
//! The model was not fitted to these points (Table 1 comes from other sources), so this is
//! a check of size, not a fit: with Table 1 the RMS errors are 0.119 (active) and 0.098
//! (passive) of P₀. The bound of 0.15 would catch, for instance, the passive stretch taken
//! without λ_opt (RMS 0.177); it does not resolve a 5 % shift of the active curve
//! (RMS 0.132).

use std::path::PathBuf;

use musclefem_materials::hill::HillParameters;
use musclefem_materials::hill::functions::{force_length, parallel_element};

fn data_file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/rabbit_ta")
        .join(name)
}

/// Rows of a two-column numeric CSV with a header line.
fn read_pairs(name: &str) -> Vec<(f64, f64)> {
    let path = data_file(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "reference data {} is missing ({e}); it lives in ../shared/data beside the checkout",
            path.display()
        )
    });
    text.lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let mut fields = line.split(',').map(|f| f.trim().parse::<f64>().unwrap());
            (fields.next().unwrap(), fields.next().unwrap())
        })
        .collect()
}

fn rms(errors: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = errors.fold((0.0, 0usize), |(s, n), e| (s + e * e, n + 1));
    (sum / count as f64).sqrt()
}

#[test]
fn active_force_length_matches_the_rabbit_data_in_size() {
    let points = read_pairs("rabbit_TA_TMWinters2011_TA_falN_mjhmilla_digitized.csv");
    assert_eq!(points.len(), 165);
    let error = rms(points.iter().map(|&(strain_percent, force_percent)| {
        force_length(1.0 + strain_percent / 100.0) - force_percent / 100.0
    }));
    println!(
        "active f_λ vs Winters 2011: RMS {error:.3} P0 over {} points",
        points.len()
    );
    assert!(error < 0.15, "RMS {error}");
}

#[test]
fn passive_parallel_element_matches_the_rabbit_data_in_size() {
    let p = HillParameters::default();
    let points = read_pairs("rabbit_TA_TMWinters2011_TA_fpeN_mjhmilla_digitized.csv");
    assert_eq!(points.len(), 111);
    let error = rms(points.iter().map(|&(strain_percent, force_percent)| {
        let stretch = p.optimal_stretch * (1.0 + strain_percent / 100.0);
        let (stress, _) = parallel_element(1.0, p.parallel_factor, p.parallel_slack, stretch);
        stress - force_percent / 100.0
    }));
    println!(
        "passive σ_PE/σ0 vs Winters 2011: RMS {error:.3} P0 over {} points",
        points.len()
    );
    assert!(error < 0.15, "RMS {error}");
}
