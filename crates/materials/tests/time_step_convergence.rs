//! Time-step convergence of the active material-point example (issue: foundation, item 8):
//! `hill` with n2 = 1, stretch 0:1, 0.5:1, 2.5:1.2, in uniaxial stress, with Δt halved
//! from 1e-3 s to 1.25e-4 s. The local update is backward Euler in the CE rate with f_λ
//! lagged by one step, so the expected order is 1.

use std::collections::BTreeMap;

use musclefem_materials::MaterialLibrary;
use musclefem_materials::driver::{StretchHistory, UniaxialRow, run_uniaxial_stress};

fn active_run(dt: f64) -> Vec<UniaxialRow> {
    let material = MaterialLibrary::with_builtins()
        .create("hill", &BTreeMap::from([("n2".to_string(), 1.0)]))
        .unwrap();
    let history = StretchHistory::parse("0:1,0.5:1,2.5:1.2").unwrap();
    run_uniaxial_stress(material.as_ref(), &history, dt).unwrap()
}

/// Largest engineering-stress difference at the times common to both runs (every 1e-3 s).
fn largest_difference(coarse: &[UniaxialRow], fine: &[UniaxialRow]) -> f64 {
    let ratio = (fine.len() - 1) / (coarse.len() - 1);
    coarse
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let other = &fine[i * ratio];
            assert!((other.time - row.time).abs() < 1e-9);
            (row.engineering_stress - other.engineering_stress).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn active_example_converges_at_first_order_in_the_time_step() {
    let steps = [1e-3, 5e-4, 2.5e-4, 1.25e-4];
    let runs: Vec<Vec<UniaxialRow>> = steps.iter().map(|&dt| active_run(dt)).collect();
    let differences: Vec<f64> = runs
        .windows(2)
        .map(|pair| largest_difference(&pair[0], &pair[1]))
        .collect();
    let orders: Vec<f64> = differences
        .windows(2)
        .map(|pair| (pair[0] / pair[1]).log2())
        .collect();
    let peak = runs[3]
        .iter()
        .map(|r| r.engineering_stress.abs())
        .fold(0.0, f64::max);
    println!("dt [s]           : {steps:?}");
    println!("max |Δσ_eng| [Pa]: {differences:?} (peak stress {peak:.1} Pa)");
    println!("observed orders  : {orders:?}");
    for order in &orders {
        assert!(
            (0.8..1.25).contains(order),
            "observed order {order} is not first order"
        );
    }
    // The finest pair differs by well under 1 % of the peak stress.
    assert!(differences[2] < 1e-2 * peak);
}
