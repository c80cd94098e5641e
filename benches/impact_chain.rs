//! How the cost of a branch point grows with the state dimension: the impacting period-1
//! orbits of a chain of `N` masses against a stop (`examples/impact_chain/model.rs`, state
//! dimension `n = 2N + 2`), continued in the forcing frequency `w` from the exact orbit
//! (`reference.rs`) with a fixed step, for N = 1, 2, 5, 10, 25, 50, by multiple shooting and
//! by collocation (NTST 20, NCOL 4). Throughput in points: criterion's time per element is
//! the time per branch point; `.../two` times a run of two points (set-up, the start, one
//! step), so that `(T_branch - T_two) / (points - 2)` is the cost of a step. Run with `cargo bench --bench impact_chain` (one size:
//! `cargo bench --bench impact_chain -- /50`).
//!
//! Targets (issue 39): at N = 50 a point in at most 50 ms by shooting and 200 ms by
//! collocation on a 2-core machine; from N = 10 to 50 no steeper than n^2 by shooting.
//!
//! Run whole (no filter), the bench ends with each method's cost of a step per size, from the
//! medians criterion stored for this run, and the growth exponent fitted to it from N = 10 to
//! 50: the least-squares slope of $\ln t$ against $\ln n$.

#[path = "../examples/impact_chain/model.rs"]
mod model;
#[path = "../examples/impact_chain/reference.rs"]
#[allow(dead_code)]
mod reference;
#[path = "../examples/impact_chain/setup.rs"]
mod setup;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hycont::hycont_continuation::{OrbitMethod, OrbitRun, RunDirection};
use hycont::orbit::{CollocationSettings, PeriodicOrbit, ShootingSettings};
use model::{ImpactChain, W};
use std::hint::black_box;

/// Points of each benchmarked branch.
const POINTS: usize = 6;

/// The branch from `orbit` up in `w` with a fixed step, of at most `points` points; its
/// number of points.
fn branch(chain: &ImpactChain, orbit: &PeriodicOrbit, method: OrbitMethod, points: usize) -> usize {
    let mut run = OrbitRun::new(chain, W).expect("a parameter");
    run.method(method).max_points(points);
    run.steps(1e-3, 1e-3, 1e-3);
    run.run("impacting", orbit, RunDirection::Up)
        .expect("the branch")
        .branch
        .points
        .len()
}

/// The methods compared.
fn methods() -> [(&'static str, OrbitMethod); 2] {
    [
        (
            "shooting",
            OrbitMethod::Shooting(ShootingSettings::default()),
        ),
        (
            "collocation",
            OrbitMethod::Collocation(CollocationSettings::default()),
        ),
    ]
}

/// Criterion's stored median time of benchmark `id` of this group, in seconds (`None` where
/// it has none): `$CRITERION_HOME`, or `criterion` in the target directory holding this
/// executable (`target/<profile>/deps/`), as criterion places it.
fn stored_median(id: &str) -> Option<f64> {
    let home = match std::env::var_os("CRITERION_HOME") {
        Some(h) => std::path::PathBuf::from(h),
        None => std::env::current_exe()
            .ok()?
            .ancestors()
            .nth(3)?
            .join("criterion"),
    };
    let path = home
        .join("impact_chain")
        .join(id.replace('/', "_"))
        .join("new")
        .join("estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(json["median"]["point_estimate"].as_f64()? * 1e-9)
}

/// The least-squares slope of $\ln t$ against $\ln n$ over the points `(n, t)`.
fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|(n, t)| (n.ln(), t.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Prints each method's cost of a step per size, `(T_branch - T_two) / (points - 2)` from
/// criterion's medians (`points[m][i]`: the branch's points by method `m` at size `i`), and
/// its growth exponent from N = 10 to 50.
fn report_growth(points: &[[usize; setup::SIZES.len()]; 2]) {
    for ((name, _), points) in methods().into_iter().zip(points) {
        let mut fit = Vec::new();
        for (n, &count) in setup::SIZES.into_iter().zip(points) {
            let (Some(long), Some(two)) = (
                stored_median(&format!("{name}/{n}")),
                stored_median(&format!("{name}/{n}/two")),
            ) else {
                eprintln!("{name}, N = {n}: no stored medians");
                continue;
            };
            let step = (long - two) / count.saturating_sub(2).max(1) as f64;
            let dim = 2 * n + 2;
            eprintln!(
                "{name}, N = {n} (n = {dim}): a step {:.2} ms, set-up and start {:.1} ms",
                1e3 * step,
                1e3 * two
            );
            if n >= 10 && step > 0.0 {
                fit.push((dim as f64, step));
            }
        }
        if fit.len() >= 2 {
            eprintln!(
                "{name}: a step grows as n^{:.2} from N = 10 to 50",
                fitted_exponent(&fit)
            );
        }
    }
}

fn growth(c: &mut Criterion) {
    hycont::hycont_continuation::check_branches(false);
    let methods = methods();
    let mut group = c.benchmark_group("impact_chain");
    group.sample_size(10);
    let mut counts = [[0; setup::SIZES.len()]; 2];
    for (i, n) in setup::SIZES.into_iter().enumerate() {
        let chain = ImpactChain { masses: n };
        let orbit = setup::exact_orbit(n).expect("an impacting orbit");
        for (m, (name, method)) in methods.into_iter().enumerate() {
            let points = branch(&chain, &orbit, method, POINTS);
            counts[m][i] = points;
            group.throughput(Throughput::Elements(points as u64));
            group.bench_function(format!("{name}/{n}"), |b| {
                b.iter(|| black_box(branch(&chain, &orbit, method, POINTS)));
            });
            // The start and one step (the run's set-up, the start's correction and analysis):
            // the branch's time less this, over its other points, is the cost of a step.
            group.throughput(Throughput::Elements(2));
            group.bench_function(format!("{name}/{n}/two"), |b| {
                b.iter(|| black_box(branch(&chain, &orbit, method, 2)));
            });
        }
    }
    group.finish();
    // A filter (e.g. `-- /50`) measures some sizes only, `--list` none: the report needs them
    // all from this run.
    if !std::env::args()
        .skip(1)
        .any(|a| !a.starts_with('-') || a == "--list")
    {
        report_growth(&counts);
    }
}

criterion_group!(benches, growth);
criterion_main!(benches);
