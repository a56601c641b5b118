//! Host benchmarks (criterion, `cargo bench -p nav-core --bench filter`): each filter
//! operation with the structured (flight) and the dense (reference) implementation, side by
//! side, on the same state (nav-core `selftest::FilterPathFixture`, the sequence the target
//! checks cost in QEMU). Not part of `cargo test`.
//!
//! Each iteration runs on a fresh copy of the fixture made just before it, untimed
//! (`BatchSize::PerIteration`), so the filter is in the cache as in the flight loop, which
//! touches it every frame; a batch of copies (`SmallInput`) spans megabytes and times the
//! reads from memory instead. Each figure includes one clock read, whose cost
//! docs/guide/performance.md gives (an empty operation measured the same way).

use criterion::{criterion_main, BatchSize, Criterion};
use nav_core::arithmetic::FilterArithmetic;
use nav_core::selftest::FilterPathFixture;
use nav_core::NavError;

type Operation = fn(&mut FilterPathFixture, FilterArithmetic) -> Result<(), NavError>;

/// A fixture a few frames into the sequence (non-trivial covariance).
fn fixture() -> FilterPathFixture {
    let mut fixture = FilterPathFixture::new().expect("fixture");
    for _ in 0..5 {
        fixture.navigate().expect("navigate");
        fixture.propagate().expect("propagate");
    }
    fixture
}

fn compare(criterion: &mut Criterion, name: &str, prepare: Operation, operation: Operation) {
    let mut group = criterion.benchmark_group(name);
    let start = fixture();
    for (label, implementation) in [
        ("structured", FilterArithmetic::Structured),
        ("dense", FilterArithmetic::DenseReference),
    ] {
        group.bench_function(label, |bencher| {
            bencher.iter_batched_ref(
                || {
                    let mut copy = start;
                    prepare(&mut copy, implementation).expect("prepare");
                    copy
                },
                |copy| operation(copy, implementation).expect("operation"),
                BatchSize::PerIteration,
            )
        });
    }
    group.finish();
}

fn nothing(_: &mut FilterPathFixture, _: FilterArithmetic) -> Result<(), NavError> {
    Ok(())
}

fn filter_operations(criterion: &mut Criterion) {
    compare(criterion, "propagation", nothing, |f, i| {
        f.propagate_with(i)
    });
    compare(criterion, "star_update", nothing, |f, i| {
        f.star_update_with(i)
    });
    compare(criterion, "gnss_update", nothing, |f, i| {
        f.gnss_update_with(i, 0.0)
    });
    compare(criterion, "gnss_update_late", nothing, |f, i| {
        f.gnss_update_with(i, 0.01)
    });
    compare(
        criterion,
        "reset",
        |f, i| f.star_update_with(i),
        |f, i| f.reset_with(i),
    );
    compare(criterion, "strapdown_step", nothing, |f, _| f.navigate());
    compare(criterion, "worst_frame", nothing, |f, i| {
        f.worst_frame_with(i)
    });
}

// criterion_group! generates an undocumented function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::filter_operations);
}
use group::benches;
criterion_main!(benches);
