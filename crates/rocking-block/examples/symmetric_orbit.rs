//! The symmetric period-1 orbit of the rocking block at (omega, alpha) = (1.3, 0.66), by multiple
//! shooting and by collocation, with its Floquet multipliers.
//!
//! Run with `cargo run --release -p rocking-block --example symmetric_orbit`.

use hycont_core::orbit::CollocationSettings;
use rocking_block::Parameters;
use rocking_block::orbits::{OrbitKind, orbit};

fn main() -> Result<(), rocking_block::Error> {
    let params = Parameters::new(1.3, 0.66);
    let shooting = orbit(&params, OrbitKind::Symmetric, None)?;
    let collocation = shooting.by_collocation(CollocationSettings::default())?;
    for (name, o) in [("shooting", &shooting), ("collocation", &collocation)] {
        let r = o.report(name)?;
        println!(
            "{name}: period {:.12}, Amp {:.12}, stable {}",
            r.period, r.amp, r.stable
        );
        for (m, trivial) in r.multipliers.iter().zip(&r.trivial) {
            println!(
                "  multiplier {:+.12} {}",
                m[0],
                if *trivial { "(trivial)" } else { "" }
            );
        }
    }
    Ok(())
}
