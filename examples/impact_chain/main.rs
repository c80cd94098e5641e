//! A chain of `N` masses against a rigid stop (`model.rs`), the scalable test system with an
//! exact reference (`reference.rs`): for N = 1, 2, 5, 10, 25, 50 (state dimension 4 to 102),
//! the impacting period-1 orbit by multiple shooting and by collocation next to its closed
//! form (start and Floquet multipliers), and the time each took.
//!
//! Run with `cargo run --release --example impact_chain`.

mod model;
mod reference;

use hycont::orbit::{
    CollocationSettings, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings, Signature,
    solve_collocation, solve_shooting,
};
use hycont::problem::NewtonSettings;
use model::{FREE, IMPACT, ImpactChain};

/// The parameters `(k, c, A, w, d, e)` of the chain of `n` masses: the stop at `GAP_RATIO`
/// of the free response's amplitude at the last mass.
pub fn parameters(n: usize) -> Vec<f64> {
    let mut p = vec![1.0, 0.1, 1.0, 1.3, 1.0, 0.8];
    p[4] = 0.0;
    let amplitude = reference::response(n, &p)[n - 1].norm();
    p[4] = 0.9 * amplitude;
    p
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for n in [1, 2, 5, 10, 25, 50] {
        let chain = ImpactChain { masses: n };
        let p = parameters(n);
        let exact: Vec<_> = reference::exact_orbits(n, &p)
            .into_iter()
            .filter(|o| reference::is_physical(n, &p, o))
            .collect();
        println!("N = {n}: {} physical orbits; d = {:.6}", exact.len(), p[4]);
        for o in &exact {
            let signature = Signature::new(
                &chain,
                vec![SegmentSpec {
                    mode: FREE,
                    end: SegmentEnd::Event(IMPACT),
                }],
            )?;
            let guess = PeriodicOrbit::new(
                &chain,
                signature,
                vec![o.start.clone()],
                vec![o.period],
                p.clone(),
            )?;
            let t0 = std::time::Instant::now();
            let sh = solve_shooting(
                &chain,
                &guess,
                ShootingSettings::default(),
                &NewtonSettings::default(),
            )?;
            let t_sh = t0.elapsed();
            let t0 = std::time::Instant::now();
            let co = solve_collocation(
                &chain,
                &guess,
                CollocationSettings::default(),
                &NewtonSettings::default(),
            )?;
            let t_co = t0.elapsed();
            let dist = |a: &[f64]| {
                a.iter()
                    .zip(&o.start)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            };
            let mults = |f: &hycont::orbit::Floquet| -> f64 {
                let nontrivial: Vec<(f64, f64)> = f.nontrivial().collect();
                o.multipliers
                    .iter()
                    .map(|m| {
                        nontrivial
                            .iter()
                            .map(|q| (q.0 - m.0).hypot(q.1 - m.1))
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max)
            };
            println!(
                "  |mu|max {:.6}: shooting start {:.1e} mult {:.1e} ({:.1?}); collocation start {:.1e} mult {:.1e} ({:.1?})",
                o.multipliers[0].0.hypot(o.multipliers[0].1),
                dist(&sh.orbit.starts[0]),
                mults(&sh.floquet),
                t_sh,
                dist(&co.solution.orbit.starts[0]),
                mults(&co.solution.floquet),
                t_co
            );
        }
    }
    Ok(())
}
