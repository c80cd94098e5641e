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
//! The study runs through hycont's study runner ([`hycont::hycont_sample::study`]): Ctrl-C
//! keeps the cells counted so far in `DIR/table_basins.partial.json` (`DIR`: the first
//! argument, default `target/table_basins`), which the next run resumes to the same table
//! (written whole to `DIR/table_basins.json`);
//! built with `--features mpi` and started under `mpirun -n N`, the ranks share the cells and
//! print the same table as one process.
//!
//! Run with `cargo run --release --example table_basins [DIR]`.

mod model;

use hycont::hycont_sample::adaptive::Adaptive;
use hycont::hycont_sample::basin::Progress;
use hycont::hycont_sample::classify::StrobeSettings;
use hycont::hycont_sample::study::{self, CountFile, Outcome, Plan, Ranks, StudyFile};
use model::{CLASSES, TableClassifier};
use std::f64::consts::PI;
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    #[cfg(feature = "mpi")]
    let _mpi = study::start_mpi();
    if let Some(n) = Ranks::unjoinable_job() {
        return Err(format!("started as one of {n} MPI ranks: build with --features mpi").into());
    }
    let (omega, e, g) = (1.0, 0.5, 1.0);
    let dir = std::env::args()
        .nth(1)
        .unwrap_or("target/table_basins".into());
    let partial = std::path::Path::new(&dir).join("table_basins.partial.json");
    let file = if partial.exists() {
        StudyFile::read(&partial)?
    } else {
        let classifier = TableClassifier {
            omega,
            e,
            g,
            settings: StrobeSettings::default(),
        };
        let rule = Adaptive {
            halfwidth: 0.1,
            ..Adaptive::default()
        };
        let study = model::amplitude_study(1);
        StudyFile::cells("table_basins", study, classifier, rule, (0, 1))?
    };
    let progress = Arc::new(Progress::default());
    let stop = Arc::clone(&progress);
    ctrlc::set_handler(move || stop.stop.store(true, std::sync::atomic::Ordering::Relaxed))?;
    let file = match study::sample(file, dir.as_ref(), &progress, Ranks::current())? {
        Outcome::Complete { file, .. } => file,
        Outcome::Partial { path, .. } => {
            eprintln!("interrupted: run again to resume {}", path.display());
            std::process::exit(1);
        }
        _ => return Ok(()),
    };
    // The complete counts, for later merges or plots; the partial file is used up.
    file.write(&file.paths(dir.as_ref()).0)?;
    let _ = std::fs::remove_file(&partial);
    let Plan::Cells { counts, .. } = &file.plan else {
        unreachable!("a study by cells")
    };
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
    for cell in 0..file.study.cells() {
        let lo = 0.5 + 0.1 * cell as f64;
        print!("[{lo:.1}, {:.1}) {:>7}", lo + 0.1, counts.trials[cell]);
        for k in 0..CLASSES.len() {
            print!(" {:>13.3}", counts.fraction(cell, k).0);
        }
        println!("  {:.3}", counts.halfwidth(cell));
    }
    Ok(())
}
