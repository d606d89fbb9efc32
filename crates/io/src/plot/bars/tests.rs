use super::*;
use crate::atomic::tests::test_dir;

const ANGLES: [&str; 4] = ["30°", "45°", "60°", "90°"];

/// Four panels (one per muscle) of passive and active values per angle.
fn knee_like_chart() -> BarChart {
    let mut chart = BarChart::new("Peak stress");
    for (m, muscle) in ["VI", "VL", "VM", "RF"].iter().enumerate() {
        let scale = 1.0 + m as f64;
        chart = chart.with_panel(
            BarPanel::new(*muscle, "peak stress [kPa]", ANGLES)
                .with_x_label("knee angle")
                .with_series(BarSeries::new(
                    "passive",
                    [1.0, 2.0, 3.0, 4.0].map(|v| v * scale),
                ))
                .with_series(BarSeries::new(
                    "active",
                    [5.0, f64::NAN, 7.0, 8.0].map(|v| v * scale),
                )),
        );
    }
    chart.panel_size = (400, 300);
    chart
}

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24.
    (
        u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
        u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
    )
}

#[test]
fn a_2x2_chart_is_written_with_the_requested_size() {
    let dir = test_dir("bars-2x2");
    let path = dir.join("peak_stress.png");
    let chart = knee_like_chart();
    assert_eq!(chart.size(), (800, 644));
    let pending = stage_bar_png(&path, &chart).unwrap();
    assert!(!path.exists(), "visible before commit");
    pending.commit().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.len() > 5_000, "{} bytes", bytes.len());
    assert_eq!(png_size(&bytes), (800, 644));
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

/// Pixels of exactly `color` in an RGB buffer.
fn count(buffer: &[u8], color: RGBColor) -> usize {
    buffer
        .chunks_exact(3)
        .filter(|p| *p == [color.0, color.1, color.2])
        .count()
}

#[test]
fn bar_areas_follow_the_values_and_nan_draws_nothing() {
    ensure_font().unwrap();
    // Passive: two bars of 1; active: one bar of 4 and none (NaN). So the active colour
    // covers twice the passive colour's area.
    let chart = BarChart::new("").with_panel(
        BarPanel::new("p", "y [Pa]", ["a", "b"])
            .with_series(BarSeries::new("passive", [1.0, 1.0]))
            .with_series(BarSeries::new("active", [4.0, f64::NAN]))
            .with_legend(LegendPosition::Hidden),
    );
    let (w, h) = chart.size();
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    render(
        BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area(),
        &chart,
    )
    .unwrap();
    let passive = count(&buffer, PALETTE[0]);
    let active = count(&buffer, PALETTE[1]);
    assert!(passive > 1_000, "{passive} passive pixels");
    let ratio = active as f64 / passive as f64;
    assert!((1.9..2.1).contains(&ratio), "active/passive area {ratio}");
    assert_eq!(count(&buffer, PALETTE[2]), 0);
}

#[test]
fn y_range_per_panel_or_shared() {
    let mut chart = BarChart::new("")
        .with_panel(BarPanel::new("small", "y", ["a"]).with_series(BarSeries::new("s", [2.0])))
        .with_panel(BarPanel::new("big", "y", ["a"]).with_series(BarSeries::new("s", [10.0])))
        .with_panel(
            BarPanel::new("empty", "y", ["a"]).with_series(BarSeries::new("s", [f64::NAN])),
        );
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
    assert!(
        close(&chart.y_tops(), &[2.2, 11.0, 1.0]),
        "{:?}",
        chart.y_tops()
    );
    chart.shared_y = true;
    assert!(
        close(&chart.y_tops(), &[11.0, 11.0, 11.0]),
        "{:?}",
        chart.y_tops()
    );
    assert_eq!(chart.grid(), (2, 2));
    assert_eq!(chart.clone().with_columns(0).grid(), (3, 1));
    assert_eq!(chart.with_columns(5).grid(), (1, 3));
}

#[test]
fn a_series_of_the_wrong_length_is_an_error_naming_the_panel() {
    let dir = test_dir("bars-mismatch");
    let path = dir.join("bad.png");
    let mut chart = knee_like_chart();
    chart.panels[2].series[1].values.pop();
    let err = stage_bar_png(&path, &chart).unwrap_err().to_string();
    assert!(err.contains("bad.png"), "{err}");
    assert!(err.contains("panel 'VM'"), "{err}");
    assert!(
        err.contains("'active' has 3 values for 4 categories"),
        "{err}"
    );
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}

#[test]
fn a_name_not_ending_in_png_is_an_error() {
    let dir = test_dir("bars-name");
    for name in ["chart.jpg", "chart"] {
        let err = stage_bar_png(&dir.join(name), &knee_like_chart())
            .unwrap_err()
            .to_string();
        assert!(err.contains(name) && err.contains(".png"), "{err}");
    }
    assert!(stage_bar_png(&dir.join("CHART.PNG"), &knee_like_chart()).is_ok());
}

#[test]
fn empty_negative_and_non_finite_charts_are_errors() {
    let dir = test_dir("bars-bad");
    let path = dir.join("bad.png");
    let message = |chart: &BarChart| stage_bar_png(&path, chart).unwrap_err().to_string();

    assert!(message(&BarChart::new("t")).contains("no panel"));

    let mut negative = knee_like_chart();
    negative.panels[0].series[0].values[1] = -0.5;
    let err = message(&negative);
    assert!(
        err.contains("panel 'VI'") && err.contains("negative value -0.5"),
        "{err}"
    );

    let mut nan = knee_like_chart();
    for panel in &mut nan.panels {
        for series in &mut panel.series {
            series.values.fill(f64::NAN);
        }
    }
    assert!(
        message(&nan).contains("no finite value"),
        "{}",
        message(&nan)
    );

    let no_categories = BarChart::new("").with_panel(BarPanel::new("p", "y", [""; 0]));
    assert!(message(&no_categories).contains("panel 'p' has no category"));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}
