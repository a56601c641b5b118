//! The C structs hold what nav-fsw's types hold: `NavHealth` has every counter of
//! `HealthCounters`, in its order (a counter added to nav-fsw fails here until the C struct
//! has it).

/// The field names of a struct's `Debug` output, in order.
fn field_names(debug: &str) -> Vec<String> {
    let inner = debug.split_once('{').unwrap().1.trim_end_matches('}');
    inner
        .split(',')
        .filter_map(|field| field.split_once(':'))
        .map(|(name, _)| name.trim().to_string())
        .collect()
}

#[test]
fn nav_health_has_every_health_counter_in_order() {
    let rust = field_names(&format!("{:?}", nav_fsw::health::HealthCounters::default()));
    let c = field_names(&format!("{:?}", nav_c::NavHealth::default()));
    assert_eq!(rust.len(), nav_fsw::health::HEALTH_COUNTER_COUNT);
    assert_eq!(c, rust);
}
