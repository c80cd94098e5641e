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
//! The study runs through hycont's study runner ([`hycont::hycont_sample::study`]) with its
//! command line, so that `scripts/slurm/submit.sh` drives it (`STUDY_BIN` this example,
//! `STUDY_NAME=table_basins`): `table_basins run [--shard I/N] [--out DIR]` counts the study
//! (or a shard of its cells) into `DIR/table_basins[.shard-I-of-N].json` (default DIR:
//! `results`) and prints the table of a whole run; Ctrl-C keeps the cells counted in a
//! `.partial.json` file that `table_basins run --resume FILE` completes; `table_basins merge
//! FILES...` merges shards. Built with `--features mpi` and started under `mpirun -n N`, the
//! ranks share the cells and print and write what one process does.
//!
//! Run with `cargo run --release --example table_basins -- run`.

mod model;

use hycont::hycont_sample::adaptive::Adaptive;
use hycont::hycont_sample::basin::Progress;
use hycont::hycont_sample::classify::StrobeSettings;
use hycont::hycont_sample::study::{self, Invocation, Outcome, Plan, Ranks, StudyFile};
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
    let invocation = Invocation::parse(std::env::args().skip(1))?;
    let new = |shard| {
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
        StudyFile::cells(
            "table_basins",
            model::amplitude_study(1),
            classifier,
            rule,
            shard,
        )
    };
    let progress = Arc::new(Progress::default());
    let stop = Arc::clone(&progress);
    ctrlc::set_handler(move || stop.stop.store(true, std::sync::atomic::Ordering::Relaxed))?;
    let file = match study::serve(&invocation, new, &progress, Ranks::current())? {
        Outcome::Complete { file, .. } if file.shard == (0, 1) => file,
        Outcome::Partial { path, .. } => {
            eprintln!("incomplete: complete it with `--resume {}`", path.display());
            std::process::exit(1);
        }
        _ => return Ok(()),
    };
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
