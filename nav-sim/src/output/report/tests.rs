//! Unit tests of the calibration report: table, JSON, CSV round trip and plots.

use plotters::prelude::BLUE;

use super::plot::{converged_window_start, log_range, BLOCK_PLOT_SIZE, PLOT_SIZE};
use super::*;

fn row(parameter: Parameter, axis: Axis, truth: f64, estimate: f64, sigma: f64) -> CalibrationRow {
    CalibrationRow {
        parameter,
        axis,
        truth,
        estimate,
        sigma,
    }
}

fn known_result() -> CalibrationResult {
    CalibrationResult {
        rows: vec![
            // Error 2e-7 < 1e-6: met.
            row(Parameter::GyroScaleFactor, Axis::X, 3e-5, 3.02e-5, 1e-7),
            // Error exactly the paper's 1e-6: "better than" is strict, so not met.
            row(Parameter::GyroScaleFactor, Axis::Y, 0.0, 1e-6, 1e-7),
            // Error −3e-4, |error| > 2.75e-4: not met.
            row(Parameter::AccelerometerBias, Axis::Z, 1e-3, 7e-4, 5e-5),
            // No paper figure.
            row(Parameter::Position, Axis::X, 0.0, 2.5, 3.0),
        ],
    }
}

#[test]
fn met_is_strictly_better_than_the_paper() {
    let result = known_result();
    let met: Vec<Option<bool>> = result.rows.iter().map(CalibrationRow::met).collect();
    assert_eq!(met, [Some(true), Some(false), Some(false), None]);
    assert!(!result.all_met());
    let just_inside = row(
        Parameter::GyroScaleFactor,
        Axis::Y,
        0.0,
        1e-6 * (1.0 - 1e-15),
        1e-7,
    );
    assert_eq!(just_inside.met(), Some(true));
    let nan = row(Parameter::GyroBias, Axis::X, 0.0, f64::NAN, 1e-7);
    assert_eq!(nan.met(), Some(false));
    assert!(CalibrationResult {
        rows: vec![result.rows[0], result.rows[3]]
    }
    .all_met());
}

#[test]
fn table_shows_every_column() {
    let text = summary(&known_result());
    println!("{text}");
    let lines: Vec<&str> = text.lines().collect();
    let header = lines
        .iter()
        .find(|line| line.contains("parameter"))
        .unwrap();
    for column in [
        "axis",
        "truth",
        "estimate",
        "error",
        "sigma",
        "paper accuracy",
        "met",
    ] {
        assert!(header.contains(column), "{column}");
    }
    let gyro_x = lines
        .iter()
        .find(|line| line.contains("gyro_scale_factor (-)") && line.contains(" x "))
        .unwrap();
    for cell in [
        "3.000e-5",
        "3.020e-5",
        "2.000e-7",
        "1.000e-7",
        "< 1.000e-6",
        "yes",
    ] {
        assert!(gyro_x.contains(cell), "{cell} in {gyro_x}");
    }
    let accel = lines
        .iter()
        .find(|line| line.contains("accel_bias (m/s²)"))
        .unwrap();
    assert!(
        accel.contains("-3.000e-4") && accel.contains("< 2.750e-4") && accel.contains(" no "),
        "{accel}"
    );
    let position = lines
        .iter()
        .find(|line| line.contains("position (m)"))
        .unwrap();
    assert!(position.contains(" - "), "{position}");
    assert!(text.ends_with("1 of 3 parameter axes meet the paper's accuracy"));
}

#[test]
fn json_has_exactly_the_documented_keys() {
    let json: serde_json::Value = serde_json::from_str(&known_result().json().unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), 4);
    for row in rows {
        let mut keys: Vec<&str> = row
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "axis",
                "error",
                "estimate",
                "met",
                "paper_accuracy",
                "parameter",
                "sigma",
                "truth"
            ]
        );
    }
    assert_eq!(rows[0]["parameter"], "gyro_scale_factor");
    assert_eq!(rows[0]["axis"], "x");
    assert!((rows[0]["error"].as_f64().unwrap() - 2e-7).abs() < 1e-20);
    assert_eq!(
        rows[0]["paper_accuracy"].as_f64().unwrap().to_bits(),
        1e-6_f64.to_bits()
    );
    assert_eq!(rows[0]["met"], true);
    assert_eq!(rows[1]["met"], false);
    assert_eq!(rows[2]["axis"], "z");
    assert_eq!(rows[2]["met"], false);
    assert!(rows[3]["paper_accuracy"].is_null() && rows[3]["met"].is_null());
}

/// A synthetic run: every block converges from −truth towards the truth with a shrinking σ.
fn synthetic_history() -> Vec<TimeHistorySample> {
    (0..=400)
        .map(|step| {
            let time_s = 600.0 + 0.5 * f64::from(step);
            let decay = (-(time_s - 600.0) / 40.0).exp();
            let mut sample = TimeHistorySample {
                time_s,
                ..TimeHistorySample::default()
            };
            for parameter in Parameter::ALL {
                let scale = parameter.paper_accuracy().unwrap_or(1.0);
                let truth = [10.0, 20.0, -30.0].map(|value| value * scale);
                sample.blocks[parameter.index()] = BlockSample {
                    truth,
                    estimate: truth
                        .map(|value| value * (1.0 - decay) + 0.1 * scale * (time_s / 7.0).sin()),
                    sigma: [1.0, 2.0, 3.0].map(|value| value * scale * (0.05 + 20.0 * decay)),
                };
            }
            sample
        })
        .collect()
}

#[test]
fn time_histories_round_trip_through_csv() {
    let directory = tempfile::tempdir().unwrap();
    let history = synthetic_history();
    let files = write_time_histories(directory.path(), &history).unwrap();
    assert_eq!(files.len(), 8);
    assert!(files[3].ends_with("gyro_bias.csv"));
    let read = read_time_histories(directory.path()).unwrap();
    assert_eq!(read.len(), history.len());
    let bits = |history: &[TimeHistorySample]| -> Vec<u64> {
        history
            .iter()
            .flat_map(|sample| {
                std::iter::once(sample.time_s).chain(sample.blocks.iter().flat_map(|block| {
                    block
                        .estimate
                        .into_iter()
                        .chain(block.sigma)
                        .chain(block.truth)
                }))
            })
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(&read), bits(&history));

    let text = std::fs::read_to_string(directory.path().join("position.csv")).unwrap();
    assert!(text.starts_with("time_s,estimate_x,estimate_y,estimate_z,sigma_x,"));

    // A damaged cell is named by file, line and column.
    let damaged = text.replacen("600.5,", "600.5x,", 1);
    std::fs::write(directory.path().join("position.csv"), damaged).unwrap();
    let message = read_time_histories(directory.path())
        .unwrap_err()
        .to_string();
    assert!(
        message.ends_with("position.csv, line 3, column `time_s`: `600.5x` is not a number"),
        "{message}"
    );
}

#[test]
fn log_range_spans_a_decade_below_the_sigma_to_twice_the_largest_value() {
    let curve = |points: Vec<(f64, f64)>| Curve {
        label: String::new(),
        color: BLUE,
        points,
    };
    let curves = [
        // |error|: a zero crossing (no floor) and the largest value.
        curve(vec![(0.0, 4e-3), (1.0, 0.0), (2.0, 1e-12)]),
        // 1σ falling to 2e-6, and an accuracy line above it.
        curve(vec![(0.0, 1e-3), (1.0, 1e-5), (2.0, 2e-6)]),
        curve(vec![(0.0, 5e-6), (2.0, 5e-6)]),
    ];
    let (low, high) = log_range(&curves);
    assert!((low - 2e-7).abs() < 1e-20, "{low}");
    assert!((high - 8e-3).abs() < 1e-15, "{high}");
    assert_eq!(converged_window_start(401), 200);
}

#[test]
fn plots_are_written() {
    let directory = tempfile::tempdir().unwrap();
    let files = write_plots(directory.path(), &synthetic_history()).unwrap();
    assert_eq!(files.len(), 9);
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        // A PNG signature and more than a blank image's worth of data.
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", file.display());
        assert!(
            bytes.len() > 20_000,
            "{}: {} bytes",
            file.display(),
            bytes.len()
        );
    }
    // Block plots are two columns wide (linear and log panels), the navigation plot one.
    let size = |file: &Path| -> (u32, u32) {
        let bytes = std::fs::read(file).unwrap();
        let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
        (word(16), word(20))
    };
    assert_eq!(size(&files[0]), BLOCK_PLOT_SIZE);
    assert_eq!(size(files.last().unwrap()), PLOT_SIZE);
    assert!(matches!(
        plot_block(
            &directory.path().join("empty.png"),
            &[],
            Parameter::GyroBias
        ),
        Err(ReportError::Empty)
    ));
    if let Ok(keep) = std::env::var("NAV_SIM_KEEP_PLOTS") {
        for file in &files {
            std::fs::copy(file, Path::new(&keep).join(file.file_name().unwrap())).unwrap();
        }
    }
}
