//! The knee study's vm95 table (printed) and chart (`peak_stress.png`).

use musclefem_io::plot::{BarChart, BarPanel, BarSeries, LegendPosition};

use crate::knee::Quadriceps;
use crate::knee::simulation::peak_stress::TABLE_ANGLES_DEGREES;
use crate::knee::simulation::{Activation, PeakStressRow, Phase, SquatSettings};

/// The vm95 table: one line per muscle and angle, passive and active in both phases.
pub(super) fn table_text(
    rows: &[PeakStressRow],
    muscles: &[Quadriceps],
    activations: &[Activation],
) -> String {
    let value = |m: Quadriceps, angle: f64, phase: Phase, a: Activation| {
        rows.iter()
            .find(|r| {
                r.muscle == m && r.angle_degrees == angle && r.phase == phase && r.activation == a
            })
            .map_or("-".to_string(), |r| format!("{:.1}", 1e-3 * r.vm95))
    };
    let mut header = "muscle  angle".to_string();
    for phase in [Phase::Flexion, Phase::Extension] {
        for &a in activations {
            header.push_str(&format!(
                "  {:>19}",
                format!("{} {}", a.name(), phase.name())
            ));
        }
    }
    let mut text = format!("vm95 [kPa]\n{header}\n");
    for &m in muscles {
        for angle in TABLE_ANGLES_DEGREES {
            let mut line = format!("{:<6}  {:>4}°", m.abbreviation(), angle);
            for phase in [Phase::Flexion, Phase::Extension] {
                for &a in activations {
                    line.push_str(&format!("  {:>19}", value(m, angle, phase, a)));
                }
            }
            text.push_str(&line);
            text.push('\n');
        }
    }
    text
}

/// One panel per muscle; per angle, a bar per (activation, phase).
pub(super) fn peak_stress_chart(
    rows: &[PeakStressRow],
    muscles: &[Quadriceps],
    settings: &SquatSettings,
) -> BarChart {
    let mut chart = BarChart::new(format!(
        "95th-percentile von Mises stress of the quadriceps, squat 0° → {}° → 0° in {} s",
        settings.squat.peak_flexion.to_degrees().round(),
        settings.squat.duration
    ))
    .with_columns(2);
    for &m in muscles {
        let mut panel = BarPanel::new(
            m.abbreviation(),
            "vm95 [kPa]",
            TABLE_ANGLES_DEGREES.iter().map(|a| format!("{a}°")),
        )
        .with_x_label("knee flexion angle")
        .with_legend(LegendPosition::UpperLeft);
        for phase in [Phase::Flexion, Phase::Extension] {
            for activation in [Activation::Passive, Activation::Active] {
                let values: Vec<f64> = TABLE_ANGLES_DEGREES
                    .iter()
                    .map(|&angle| {
                        rows.iter()
                            .find(|r| {
                                r.muscle == m
                                    && r.angle_degrees == angle
                                    && r.phase == phase
                                    && r.activation == activation
                            })
                            .map_or(f64::NAN, |r| 1e-3 * r.vm95)
                    })
                    .collect();
                if values.iter().any(|v| v.is_finite()) {
                    panel = panel.with_series(BarSeries::new(
                        format!("{}, {}", activation.name(), phase.name()),
                        values,
                    ));
                }
            }
        }
        chart = chart.with_panel(panel);
    }
    chart
}
