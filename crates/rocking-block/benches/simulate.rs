//! Simulation benchmarks (issue: foundation). Run with `cargo bench -p rocking-block --bench simulate`.
//!
//! The reference figure: scipy's DOP853 integrating 400 forcing periods of the rocking block at
//! (omega, alpha) = (1.3, 0.66), rtol 1e-10, atol 1e-12, takes 1.5-2.4 s with 190,764 RHS
//! evaluations on the project machine. The run below starts from phi0 = 0.01, psi0 = 0 with
//! forcing phase beta = pi/2 and settles on the asymmetric period-1 orbit, so it really covers
//! 400 periods (from beta = 0 the block overturns at t = 8.57; see the study tests).

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_core::{SampleTimes, Sensitivities, SimulationSettings, Simulator};
use rocking_block::{Parameters, RockingBlock, initial_mode, initial_state};
use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;

fn setup() -> (Parameters, Vec<f64>, [f64; 4], f64) {
    let params = Parameters::new(1.3, 0.66);
    let x0 = initial_state(0.01, 0.0, FRAC_PI_2);
    let t_end = 400.0 * 2.0 * PI / params.omega;
    (params, params.to_vec(), x0, t_end)
}

fn simulate_400_periods(c: &mut Criterion) {
    let (params, p, x0, t_end) = setup();
    let mode = initial_mode(&x0, &params);
    let settings = SimulationSettings::default().rtol(1e-10).atol(1e-12);
    let mut sim = Simulator::new(settings.clone()).unwrap();
    let traj = sim.run(&RockingBlock, mode, 0.0, &x0, &p, t_end).unwrap();
    eprintln!(
        "400 periods: stop {:?}, {} steps ({} rejected), {} RHS evaluations, {} events",
        traj.stop,
        traj.stats.steps,
        traj.stats.rejected_steps,
        traj.stats.rhs_evaluations,
        traj.stats.events
    );
    c.bench_function("rocking_block/400_periods", |b| {
        b.iter(|| {
            black_box(
                sim.run(&RockingBlock, mode, 0.0, black_box(&x0), &p, t_end)
                    .unwrap(),
            )
        });
    });

    let mut strobe = Simulator::new(
        settings
            .clone()
            .samples(SampleTimes::stroboscopic(params.omega))
            .record_events(false),
    )
    .unwrap();
    c.bench_function("rocking_block/400_periods_stroboscopic", |b| {
        b.iter(|| {
            black_box(
                strobe
                    .run(&RockingBlock, mode, 0.0, black_box(&x0), &p, t_end)
                    .unwrap(),
            )
        });
    });
}

fn monodromy_one_period(c: &mut Criterion) {
    let (params, p, x0, _) = setup();
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let settled = sim
        .run(
            &RockingBlock,
            initial_mode(&x0, &params),
            0.0,
            &x0,
            &p,
            100.0 * 2.0 * PI / params.omega,
        )
        .unwrap();
    let (xs, ms) = (settled.state_final.clone(), settled.mode_final);
    let period = 2.0 * PI / params.omega;
    c.bench_function("rocking_block/one_period_with_state_sensitivities", |b| {
        b.iter(|| {
            black_box(
                sim.run_with_sensitivities(
                    &RockingBlock,
                    ms,
                    0.0,
                    black_box(&xs),
                    &p,
                    period,
                    Sensitivities::State,
                )
                .unwrap(),
            )
        });
    });
}

criterion_group!(benches, simulate_400_periods, monodromy_one_period);
criterion_main!(benches);
