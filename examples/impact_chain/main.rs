//! A chain of `N` masses against a rigid stop (`model.rs`), the scalable test system with an
//! exact reference (`reference.rs`): for N = 1, 2, 5, 10, 25, 50 (state dimension 4 to 102),
//! the impacting period-1 orbit by multiple shooting and by collocation next to its closed
//! form (start and Floquet multipliers); then the one mass's branch up in the forcing
//! frequency `w`, through its fold (SN) back to the grazing (GR) where it ends, next to the
//! reference's roots. How the cost grows with N: `benches/impact_chain.rs`.
//!
//! Run with `cargo run --release --example impact_chain`.

mod model;
mod reference;
mod setup;

use hycont::hycont_continuation::{OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{
    CollocationSettings, PeriodicOrbit, ShootingSettings, solve_collocation, solve_shooting,
};
use hycont::problem::NewtonSettings;
use model::{ImpactChain, W};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for n in setup::SIZES {
        let chain = ImpactChain { masses: n };
        let p = setup::parameters(n);
        let exact: Vec<_> = reference::exact_orbits(n, &p)
            .into_iter()
            .filter(|o| reference::is_physical(n, &p, o))
            .collect();
        println!(
            "N = {n} (state dimension {}): stop at d = {:.6}",
            chain.dim(),
            p[4]
        );
        for o in &exact {
            let guess = PeriodicOrbit::new(
                &chain,
                setup::signature(&chain)?,
                vec![o.start.clone()],
                vec![o.period],
                p.clone(),
            )?;
            let sh = solve_shooting(
                &chain,
                &guess,
                ShootingSettings::default(),
                &NewtonSettings::default(),
            )?;
            let co = solve_collocation(
                &chain,
                &guess,
                CollocationSettings::default(),
                &NewtonSettings::default(),
            )?;
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
                "  largest |multiplier| {:.6}; distance to the closed form: shooting start {:.1e}, multipliers {:.1e}; collocation start {:.1e}, multipliers {:.1e}",
                o.multipliers[0].0.hypot(o.multipliers[0].1),
                dist(&sh.orbit.starts[0]),
                mults(&sh.floquet),
                dist(&co.solution.orbit.starts[0]),
                mults(&co.solution.floquet),
            );
        }
    }
    branch_of_one_mass()
}

/// The one mass's branch in `w` from `w = 1.3`: SN and GR next to the roots of the
/// reference's fold and grazing functions (bisection on the brackets a scan gives).
fn branch_of_one_mass() -> Result<(), Box<dyn std::error::Error>> {
    let chain = ImpactChain { masses: 1 };
    let p = setup::parameters(1);
    let at = |w: f64| {
        let mut q = p.clone();
        q[3] = w;
        q
    };
    let root = |f: &dyn Fn(f64) -> f64, (mut a, mut b): (f64, f64)| {
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if (f(m) > 0.0) == (f(a) > 0.0) {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    let fold = root(&|w| reference::fold_function(1, &at(w)), (1.6, 1.8));
    let graze = root(&|w| reference::grazing_function(1, &at(w)), (1.3, 1.4));
    let mut run = OrbitRun::new(&chain, W)?;
    run.bounds(1.0, 2.0);
    let branch = run.run("impacting", &setup::exact_orbit(1)?, RunDirection::Up)?;
    let sn = branch.first(SpecialKind::Fold)?.point[W];
    let gr = branch.first(SpecialKind::Grazing)?.point[W];
    println!("one mass, up in w: SN at w = {sn:.12} (reference {fold:.12})");
    println!(
        "                   GR at w = {gr:.12} (reference {graze:.12}), where the branch ends"
    );
    Ok(())
}
