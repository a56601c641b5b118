//! The observability report as text: the paper's Table 1 beside ours and the paper-like
//! analysis, per motion state and per phase of the schedule (what `nav-sim observability`
//! prints).

use nav_core::state::STATE_DIMENSION;

use super::{state_name, CaseReport, ObservabilityReport, StateReport};

/// `+` / `-` for a verdict.
fn mark(observable: bool) -> char {
    if observable {
        '+'
    } else {
        '-'
    }
}

/// A per-case total shown below the state rows.
type CaseCount = fn(&CaseReport) -> usize;

/// Rows of a case table: state name, then per case one cell.
fn write_matrix(
    out: &mut String,
    cases: &[&CaseReport],
    cell: impl Fn(&StateReport) -> String,
    width: usize,
) {
    use std::fmt::Write as _;
    let _ = write!(out, "{:22}", "state");
    for case in cases {
        let _ = write!(out, " {:>width$}", case.label);
    }
    out.push('\n');
    for k in 0..STATE_DIMENSION {
        let _ = write!(out, "{:22}", state_name(k));
        for case in cases {
            let text = case.states.get(k).map_or_else(String::new, &cell);
            let _ = write!(out, " {text:>width$}");
        }
        out.push('\n');
    }
    let totals: [(&str, CaseCount); 4] = [
        ("rank (ours)", |c| c.rank),
        ("observable (ours)", |c| c.observable_count),
        ("σ ≥ 5e-8 (paper-like)", |c| c.paper_like_rank),
        ("observable (paper-like)", |c| c.paper_like_observable_count),
    ];
    for (name, total) in totals {
        let _ = write!(out, "{name:22}");
        for case in cases {
            let _ = write!(out, " {:>width$}", total(case));
        }
        out.push('\n');
    }
}

/// The report as text (what `nav-sim observability` prints).
pub fn render_text(report: &ObservabilityReport) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Observability of the 24-state model (paper Section 2, Table 1), scenario {}",
        report.scenario
    );
    let _ = writeln!(
        out,
        "ours: continuous [H; H Aτ; …], scaled (τ = {} s, or 1 rad / fastest rate when shorter; states in typical magnitudes {}; star rows in {:.3e} rad, GNSS rows in {} m);\n      degree = σ_k/σ_max, '+' observable by the null-space test (σ ≤ {:e} σ_max is zero, projection ≤ {:e})",
        report.scaling.time_unit_s,
        report
            .scaling
            .state_magnitudes
            .iter()
            .map(|entry| format!("{} {:e}", entry.block, entry.magnitude))
            .collect::<Vec<_>>()
            .join(", "),
        report.scaling.star_row_magnitude,
        report.scaling.gnss_row_magnitude,
        report.tolerance.relative_zero,
        report.tolerance.null_space_projection,
    );
    let _ = writeln!(
        out,
        "paper-like: discrete [H; H F; …], Δ = {} s, order {}, unscaled; assigned σ, '+' when ≥ {:e} (the paper's threshold)\n",
        report.paper_like_step_s, report.paper_like_order, report.tolerance.paper_absolute
    );

    let _ = writeln!(
        out,
        "== The paper's motion states (I: 2.4e-4 °/s per axis; II: (0,0,10) °/s; III: (0,20,0) m/s²), alone as in Table 1"
    );
    let _ = writeln!(
        out,
        "   per state: degree(ours) ours | σ(paper-like) paper-like | Table 1 value, its verdict"
    );
    let table_cases: Vec<&CaseReport> = report.paper_states.iter().take(3).collect();
    write_matrix(
        &mut out,
        &table_cases,
        |s| {
            format!(
                "{:8.1e} {} | {:8.1e} {} | {:8.1e} {}",
                s.degree,
                mark(s.observable),
                s.paper_like_singular_value,
                mark(s.observable_paper_threshold),
                s.paper_table_1.unwrap_or(f64::NAN),
                s.paper_table_1_observable.map_or('?', mark),
            )
        },
        36,
    );
    let _ = writeln!(
        out,
        "\n== PWCS: the paper's states as segments after the coast (degree, ours '+'/'-', paper-like '+'/'-')"
    );
    let pwcs: Vec<&CaseReport> = report.paper_states.iter().skip(3).collect();
    let degree_cell = |s: &StateReport| {
        format!(
            "{:8.1e}{}{}",
            s.degree,
            mark(s.observable),
            mark(s.observable_paper_threshold)
        )
    };
    write_matrix(&mut out, &pwcs, degree_cell, 11);

    let _ = writeln!(out, "\n== Scenario schedule, phases:");
    for phase in &report.phases {
        let _ = writeln!(
            out,
            "  {:2}: {:24} rate {:?} °/s, force {:?} m/s²",
            phase.index, phase.label, phase.body_rate_deg_per_s, phase.specific_force_mps2
        );
    }
    // Columns are phase numbers: relabel them for the matrices.
    let relabel = |case: &CaseReport, index: usize| CaseReport {
        label: index.to_string(),
        ..case.clone()
    };
    let after: Vec<CaseReport> = report
        .phases
        .iter()
        .map(|p| relabel(&p.after_previous, p.index))
        .collect();
    let alone: Vec<CaseReport> = report
        .phases
        .iter()
        .map(|p| relabel(&p.alone, p.index))
        .collect();
    let _ = writeln!(
        out,
        "\n== Each phase as a PWCS segment after the previous ones (column k = phases 1..k)"
    );
    write_matrix(&mut out, &after.iter().collect::<Vec<_>>(), degree_cell, 11);
    let _ = writeln!(out, "\n== Each phase alone");
    write_matrix(&mut out, &alone.iter().collect::<Vec<_>>(), degree_cell, 11);
    out
}
