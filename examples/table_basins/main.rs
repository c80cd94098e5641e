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
//! What the table shows, and why. The drops (`z0 < 1`, `|w0| < 1`) carry less energy than the
//! bouncing orbit (take-off velocity `w+ = e g T / (1 + e) = 2.09`, apex 2.2 above the
//! table); its impacts take energy out, and from `a = 1` to 1.6 every drop ends on the orbit
//! that coexists with it: chattering down onto the table, riding on it, lifted off once per
//! period ("chattering"). Its period-1 column is therefore about 0 although the bouncing orbit
//! is stable there. A second table shows that orbit's own basin: trials started near it (its
//! take-off velocity within 20 % and its phase within 0.2 rad) are period 1 from the fold to
//! `a_PD`, with the closed form's largest multiplier beside them, and not above `a_PD`.
//! Above 1.6 "undecided" is chaotic bouncing (it stays undecided over 2,000 periods and
//! periods up to 24; Holmes 1982) and, within `[1.9, 2)`, sticking orbits of period 11 that
//! `max_period = 8` does not look for (periods 5 and 6 nearby are counted as chattering).
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
use model::{CLASSES, NearOrbit, TableClassifier};
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
    near_orbit(omega, e, g)
}

/// The second table: the bouncing period-1 orbit's neighbourhood, cell by cell in `a` from
/// above the fold to beyond the period doubling.
fn near_orbit(omega: f64, e: f64, g: f64) -> Result<(), Box<dyn std::error::Error>> {
    use hycont::hycont_sample::adaptive::{CellCounts, run_cells};
    use hycont::hycont_sample::basin::Classifier;
    let near = NearOrbit {
        table: TableClassifier {
            omega,
            e,
            g,
            settings: StrobeSettings::default(),
        },
        spread: 0.2,
    };
    let (lo, width, bins) = (1.1, 0.1, 6);
    let study = model::near_orbit_study(lo, lo + width * bins as f64, bins, 2);
    let rule = Adaptive {
        halfwidth: 0.1,
        ..Adaptive::default()
    };
    let mut counts = CellCounts::new(near.classes(), bins);
    let cells: Vec<usize> = (0..bins).collect();
    run_cells(
        &study,
        &near,
        &rule,
        &mut counts,
        &cells,
        &Progress::default(),
    )?;
    println!(
        "\nstarted near the bouncing period-1 orbit (take-off velocity within 20 %, phase within 0.2 rad):"
    );
    println!(
        "{:>12} {:>7} {:>9} {:>9} {:>11} {:>6}  largest |multiplier| at the middle (closed form)",
        "a", "trials", "period-1", "period-2", "chattering", "other"
    );
    for cell in 0..bins {
        let a = lo + width * cell as f64;
        let f = |k: usize| counts.fraction(cell, k).0;
        let mu = model::orbit_multiplier(a + 0.5 * width, omega, e, g).unwrap_or(f64::NAN);
        let other = f(0) + f(4) + f(5);
        print!(
            "[{a:.1}, {:.1}) {:>7} {:>9.3} {:>9.3}",
            a + width,
            counts.trials[cell],
            f(2),
            f(3)
        );
        println!(" {:>11.3} {other:>6.3}  {mu:.3}", f(1));
    }
    Ok(())
}
