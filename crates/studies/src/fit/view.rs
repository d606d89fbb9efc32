//! How a fit's curve is described on the terminal, in fit.txt, fit_curve.csv and
//! fit.png: the elongation test's engineering strain and stress, or a scene's history
//! columns in their own units.

use super::data::Range;
use crate::elongation::options::TestOptions;
use crate::elongation::protocol::Activation;
use crate::scene_study::SceneStudy;

/// How a fit's curve is described, tabulated and drawn.
pub(super) struct View {
    /// The terminal's description of the base, e.g. "passive elongation (fusiform, …)".
    pub(super) what: String,
    /// fit.txt's line on the base.
    pub(super) summary_line: String,
    /// "engineering strain" or the --x column, for the range of the data kept.
    pub(super) x_name: String,
    /// The range's scale and unit on the terminal: (100, "%") for strain.
    pub(super) x_range_scale: f64,
    pub(super) x_range_unit: &'static str,
    pub(super) curve_header: String,
    pub(super) title: String,
    pub(super) x_label: String,
    pub(super) y_label: String,
    /// Plotted value = value [SI] × scale.
    pub(super) x_scale: f64,
    pub(super) y_scale: f64,
    /// The unit of y and of the residual [SI].
    pub(super) y_unit: &'static str,
    /// "stress" or the --y column, in fit.txt.
    pub(super) y_quantity: String,
}

impl View {
    pub(super) fn elongation(test: Activation, options: &TestOptions) -> Self {
        View {
            what: format!("{} elongation ({})", test.name(), options.describe()),
            summary_line: format!("test = {} elongation ({})", test.name(), options.describe()),
            x_name: "strain".into(),
            x_range_scale: 100.0,
            x_range_unit: " %",
            curve_header: "engineering_strain,measured_stress_pa,fitted_stress_pa".into(),
            title: format!("{} elongation", test.name()),
            x_label: "engineering strain [%]".into(),
            y_label: "engineering stress [kPa]".into(),
            x_scale: 100.0,
            y_scale: 1e-3,
            y_unit: "Pa",
            y_quantity: "stress".into(),
        }
    }

    pub(super) fn scene(study: &SceneStudy, x: &str, y: &str) -> Self {
        let name = study.path().display().to_string();
        View {
            what: format!("scene {name} ({y} against {x})"),
            summary_line: format!("scene = {name}\nx = {x}\ny = {y}"),
            x_name: x.to_string(),
            x_range_scale: 1.0,
            x_range_unit: "",
            curve_header: format!("{x},measured_{y},fitted_{y}"),
            title: format!("scene {name}"),
            x_label: x.to_string(),
            y_label: y.to_string(),
            x_scale: 1.0,
            y_scale: 1.0,
            y_unit: unit_of(y),
            y_quantity: y.to_string(),
        }
    }

    /// "0 < strain ≤ 20 %" or "0.1 ≤ time_s ≤ 1".
    pub(super) fn range_text(&self, range: Range) -> String {
        let below = if range.low_inclusive { "≤" } else { "<" };
        if self.x_range_unit == " %" {
            format!(
                "{:.0} {below} {} ≤ {:.0} %",
                self.x_range_scale * range.low,
                self.x_name,
                self.x_range_scale * range.high
            )
        } else {
            format!(
                "{} {below} {} ≤ {}{}",
                self.x_range_scale * range.low,
                self.x_name,
                self.x_range_scale * range.high,
                self.x_range_unit
            )
        }
    }
}

/// The SI unit a history column's name ends with (see `musclefem_io::output::history`).
fn unit_of(column: &str) -> &'static str {
    [
        ("_n_m", "N m"),
        ("_n", "N"),
        ("_j", "J"),
        ("_m2", "m²"),
        ("_s", "s"),
        ("_pa", "Pa"),
    ]
    .iter()
    .find(|(suffix, _)| column.ends_with(suffix))
    .map_or("", |(_, unit)| unit)
}
