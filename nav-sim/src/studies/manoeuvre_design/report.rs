//! The design as text (what `nav-sim design` prints) and as a scenario file: the input's TOML
//! with its manoeuvre tables replaced by the designed schedule under a comment saying how it
//! was made.

use std::fmt::Write as _;

use super::{Axis, Constraints, ManoeuvreDesign};
use crate::scenario::ManoeuvreSegment;

impl ManoeuvreDesign {
    /// The design as text: parameters, schedule, predicted accuracy and wall times.
    pub fn text(&self) -> String {
        let p = &self.parameters;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "design: slews at {:.2} deg/s, {} turn(s) each way per axis, {} round(s); lateral \
             share of the first thrust axis {:.2} ({:.1} m/s of translation in all), {:.0} s \
             apart; outbound translations at {:.0} % of the first window's spare coast, \
             returns in window {} at {:.0} % of its spare coast",
            p.slew_rate_deg_per_s,
            p.turns_per_slew,
            p.slew_rounds,
            p.first_axis_share,
            self.lateral_delta_v_mps,
            p.translation_gap_s,
            100.0 * p.outbound_placement,
            p.return_window,
            100.0 * p.return_placement
        );
        if !self.left_out.is_empty() {
            let _ = writeln!(
                text,
                "left out (they end after the flight time): {}",
                self.left_out.join("; ")
            );
        }
        let _ = writeln!(text, "\nschedule:\n    start (s)  duration (s)  label");
        let mut start_s = 0.0;
        for segment in &self.scenario.manoeuvres {
            let _ = writeln!(
                text,
                "{:>13.1}  {:>12.3}  {}",
                start_s, segment.duration_s, segment.label
            );
            start_s += segment.duration_s;
        }
        let orbit = &self.report.orbit;
        let _ = writeln!(
            text,
            "\npredicted final accuracy (covariance analysis, every measurement epoch):\n{}\
             worst sigma/target {:.3}\norbit: lowest altitude {:.1} km, lowest osculating \
             perigee {:.1} km, final perigee {:.1} km, final apogee {:.1} km",
            self.report.table(),
            self.report.worst_ratio(),
            orbit.minimum_altitude_m / 1e3,
            orbit.minimum_perigee_altitude_m / 1e3,
            orbit.final_perigee_altitude_m / 1e3,
            orbit.final_apogee_altitude_m / 1e3,
        );
        self.imu_error_text(&mut text);
        let _ = writeln!(
            text,
            "wall time: search {:.1} s ({} schedules analysed), final {} {:.1} s",
            self.search_wall_s,
            self.evaluations,
            if self.input_report.is_some() {
                "analyses (designed and input schedule)"
            } else {
                "analysis"
            },
            self.final_wall_s
        );
        text
    }
}

impl ManoeuvreDesign {
    /// The twelve systematic IMU error states of the designed and the input schedule
    /// (`[filter.imu_errors]` on; nothing otherwise): reported, not searched for
    /// (`docs/guide/scenario-design.md`).
    fn imu_error_text(&self, text: &mut String) {
        let Some(imu) = &self.report.imu_errors else {
            return;
        };
        let _ = writeln!(
            text,
            "\nsystematic IMU error states (reported; the search minimises the calibration \
             ratios above, estimated beside them):\ndesigned schedule:\n{}",
            imu.table()
        );
        if let Some(history) = self.report.imu_error_history() {
            let _ = writeln!(
                text,
                "designed schedule, sigma/prior at the end of each segment:\n{history}"
            );
        }
        if let Some(input) = self
            .input_report
            .as_ref()
            .and_then(|r| r.imu_errors.as_ref())
        {
            let _ = writeln!(
                text,
                "input schedule (worst sigma/target {:.3}):\n{}",
                self.input_report
                    .as_ref()
                    .map_or(f64::NAN, |r| r.worst_ratio()),
                input.table()
            );
        }
    }
}

/// The TOML of one manoeuvre segment.
fn segment_toml(segment: &ManoeuvreSegment) -> String {
    let array = |values: &[f64; 3]| {
        let [x, y, z] = values;
        format!("[{x:?}, {y:?}, {z:?}]")
    };
    format!(
        "[[manoeuvre]]\nlabel = {:?}\nduration_s = {:?}\nramp_s = {:?}\nbody_rate_deg_per_s = {}\n\
         specific_force_mps2 = {}\n",
        segment.label,
        segment.duration_s,
        segment.ramp_s,
        array(&segment.body_rate_deg_per_s),
        array(&segment.specific_force_mps2)
    )
}

/// `text` (a scenario's TOML) with its `[[manoeuvre]]` tables replaced by `manoeuvres`,
/// preceded by `header` (comment lines): everything else is kept as written. The new list
/// takes the place of the first old table and of the comment block right above it.
pub fn replace_manoeuvres(text: &str, manoeuvres: &[ManoeuvreSegment], header: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let is_header = |line: &str| line.trim_start().starts_with('[');
    let is_manoeuvre = |line: &str| line.trim() == "[[manoeuvre]]";
    let is_comment = |line: &str| line.trim_start().starts_with('#');
    let mut kept: Vec<String> = Vec::new();
    let mut inserted = false;
    let mut index = 0;
    while let Some(line) = lines.get(index) {
        if !is_manoeuvre(line) {
            kept.push((*line).to_string());
            index += 1;
            continue;
        }
        let mut end = index + 1;
        while lines.get(end).is_some_and(|line| !is_header(line)) {
            end += 1;
        }
        // Comment lines right above the next table belong to it.
        while end > index + 1
            && lines
                .get(end - 1)
                .is_some_and(|line| is_comment(line) || line.trim().is_empty())
        {
            end -= 1;
        }
        if !inserted {
            while kept.last().is_some_and(|line| is_comment(line)) {
                kept.pop();
            }
            kept.extend(header.lines().map(|line| format!("# {line}")));
            for segment in manoeuvres {
                kept.extend(segment_toml(segment).lines().map(str::to_string));
                kept.push(String::new());
            }
            inserted = true;
        }
        index = end;
        while lines.get(index).is_some_and(|line| line.trim().is_empty()) {
            index += 1;
        }
    }
    let mut result = kept.join("\n");
    result.push('\n');
    result
}

impl ManoeuvreDesign {
    /// The comment above the written schedule: how it was made under `constraints` (those
    /// the design was made with).
    pub fn header(&self, constraints: &Constraints) -> String {
        let p = &self.parameters;
        format!(
            "The manoeuvre schedule, written by `nav-sim design` (docs/guide/scenario-design.md) under\n\
             max body rate {} deg/s, max lateral acceleration {} m/s^2, lateral delta-v {} m/s,\n\
             main engine along body {}: slews at {:.2} deg/s, {} turns each way per axis, {} \
             round(s);\nfirst thrust axis' share of the lateral delta-v {:.2}. Predicted worst \
             sigma/target {:.3}.",
            constraints.max_body_rate_deg_per_s,
            constraints.max_lateral_acceleration_mps2,
            constraints.lateral_delta_v_mps,
            Axis::name(constraints.main_engine_axis),
            p.slew_rate_deg_per_s,
            p.turns_per_slew,
            p.slew_rounds,
            p.first_axis_share,
            self.report.worst_ratio()
        )
    }
}
