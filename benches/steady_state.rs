//! Criterion benchmark of one steady state (issue: 400 transient + 64 kept periods at Omega 0.5,
//! zeta 0.02, F_hat 0.5, from rest) with the exact piecewise solver. `geardyn bench` reports the
//! same figures for both integrators and the 201 x 201 basin map.

use criterion::{criterion_group, criterion_main, Criterion};
use geardyn::model::GearPair;
use geardyn::sim::{steady_state, ExactFlow, SteadyOptions};

fn exact_steady_state(c: &mut Criterion) {
    let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).expect("valid parameters");
    let flow = ExactFlow::new(&model).expect("k = 1");
    let opts = SteadyOptions {
        transient: Some(400),
        keep: 64,
        settle: false,
        ..SteadyOptions::default()
    };
    c.bench_function("exact steady state 400+64 periods", |b| {
        b.iter(|| steady_state(&flow, [0.0, 0.0], &opts).expect("steady state"))
    });
}

criterion_group!(benches, exact_steady_state);
criterion_main!(benches);
