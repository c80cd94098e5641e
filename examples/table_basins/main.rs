//! Basin stability of the ball on a vibrating table with sticking, by hycont's sampling API
//! (no rocking block): for the table's amplitude `a` in 15 cells of `[0.5, 2)`, trials with
//! random drop height, velocity and forcing phase, drawn cell by cell until every class's 95 %
//! Wilson half-width is at most 0.1 ([`hycont::hycont_sample::adaptive`]); each trial
//! classified by its stroboscopic map (stuck, chattering with sticking phases, period 1, 2 or
//! higher, undecided). The table shows where the closed forms put the bouncing orbits
//! (`omega = g = 1`, `e = 1/2`): below `a = g / omega^2 = 1` a ball at rest is never lifted;
//! the period-1 orbit exists from its fold `a_SN = pi g (1 - e) / (1 + e) / omega^2 = 1.047`
//! and is stable up to its period doubling `a_PD = 1.527` (see `vibrating_table`).
//!
//! Run with `cargo run --release --example table_basins`.

mod model;

use hycont::hycont_sample::adaptive::{Adaptive, CellCounts, run_cells};
use hycont::hycont_sample::basin::{Classifier, Progress};
use hycont::hycont_sample::classify::StrobeSettings;
use model::{CLASSES, TableClassifier};
use std::f64::consts::PI;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (omega, e, g) = (1.0, 0.5, 1.0);
    let classifier = TableClassifier {
        omega,
        e,
        g,
        settings: StrobeSettings::default(),
    };
    let study = model::amplitude_study(1);
    let rule = Adaptive {
        halfwidth: 0.1,
        ..Adaptive::default()
    };
    let mut counts = CellCounts::new(classifier.classes(), study.cells());
    let cells: Vec<usize> = (0..study.cells()).collect();
    run_cells(
        &study,
        &classifier,
        &rule,
        &mut counts,
        &cells,
        &Progress::default(),
    )?;
    let a_sn = PI * g * (1.0 - e) / (1.0 + e) / (omega * omega);
    println!(
        "a_SN = {a_sn:.4}, a_PD = 1.5268, lift-off from rest above a = {}",
        g / (omega * omega)
    );
    print!("{:>12} {:>7}", "a", "trials");
    for c in CLASSES {
        print!(" {c:>13}");
    }
    println!("  largest half-width");
    for cell in 0..study.cells() {
        let lo = 0.5 + 0.1 * cell as f64;
        print!("[{lo:.1}, {:.1}) {:>7}", lo + 0.1, counts.trials[cell]);
        for k in 0..CLASSES.len() {
            print!(" {:>13.3}", counts.fraction(cell, k).0);
        }
        println!("  {:.3}", counts.halfwidth(cell));
    }
    Ok(())
}
