//! Measures the classifier on the trials of the sampling figures: where its time goes, and how
//! far other settings change its decisions. The tool behind the classifier's speed work: a
//! change of a decision rule must keep at least 99.5 % of the trials of each mix in their
//! class and every class fraction inside the reference's 95 % (Wilson) interval.
//!
//! - `profile MIX N [KEY=VALUE]...`: the first `N` trials of the mix (seed 1) with the default
//!   settings (or those changed as for `agree`): share
//!   of trials, share of time, milliseconds and forcing periods per trial, by class and by
//!   decision, and how many periods decided trials took;
//! - `agree MIX N [KEY=VALUE]...`: the same trials with the default settings and with the
//!   settings changed (`max`, `min`, `chunk`, `newton`, `rtol`, `atol`, `tol`, `xtol`: the
//!   fields of `ClassifierSettings`): trials per second of each, the share of trials in the same
//!   class, each class fraction against the reference's interval, and the trials that moved.
//!
//! - `record MIX N [KEY=VALUE]...`: one line per trial (index, class, seconds), to compare the
//!   classifier of another build: `compare REFERENCE VARIANT` reports two records as `agree` does.
//!
//! Mixes: `7` (Fig. 7 at omega = 1.3), `9a` and `9b` (Fig. 9 at beta = 0 and pi/2), `10`.
//! Run with `cargo run --release -p rocking-block --example classifier_mix -- profile 10 20000`.

use hycont_sample::basin::{Study, wilson};
use rocking_block::block::Block;
use rocking_block::classes::{ClassifierSettings, classify};
use rocking_block::figures::sampling::{fig7_study, fig9_study, fig10_study};
use std::collections::BTreeMap;
use std::time::Instant;

fn study(mix: &str, block: &Block) -> Result<Study, String> {
    Ok(match mix {
        "7" => fig7_study(1.3, 1, block),
        "9a" => fig9_study(0.0, 1, block),
        "9b" => fig9_study(std::f64::consts::FRAC_PI_2, 1, block),
        "10" => fig10_study(1, block).0,
        other => return Err(format!("unknown mix {other} (7, 9a, 9b, 10)")),
    })
}

/// The class of trial `v` (with `+rest` for motions with rest phases), its decision and
/// periods, and the seconds it took.
fn run(v: &[f64], block: &Block, s: &ClassifierSettings) -> (String, String, usize, f64) {
    let t = Instant::now();
    let c = classify(&block.at(v[0], v[1]), v[2], v[3], v[4], s);
    let dt = t.elapsed().as_secs_f64();
    match c {
        Ok(c) => (
            format!("{:?}{}", c.class, if c.with_rest { "+rest" } else { "" }),
            format!("{:?}", c.decision),
            c.periods,
            dt,
        ),
        Err(_) => ("error".into(), "error".into(), 0, dt),
    }
}

fn settings(pairs: &[String]) -> Result<ClassifierSettings, String> {
    let mut s = ClassifierSettings::default();
    for kv in pairs {
        let (k, v) = kv
            .split_once('=')
            .ok_or(format!("{kv}: expected KEY=VALUE"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{kv}: {e}");
        match k {
            "max" => s.max_periods = v.parse().map_err(|e| bad(&e))?,
            "min" => s.min_periods = v.parse().map_err(|e| bad(&e))?,
            "chunk" => s.chunk = v.parse().map_err(|e| bad(&e))?,
            "newton" => s.newton_every = v.parse().map_err(|e| bad(&e))?,
            "rtol" => s.rtol = v.parse().map_err(|e| bad(&e))?,
            "atol" => s.atol = v.parse().map_err(|e| bad(&e))?,
            "tol" => s.tol = v.parse().map_err(|e| bad(&e))?,
            "maxk" => s.max_period = v.parse().map_err(|e| bad(&e))?,
            "xtol" => s.extrapolation_tol = v.parse().map_err(|e| bad(&e))?,
            _ => return Err(format!("unknown setting {k}")),
        }
    }
    Ok(s)
}

fn profile(study: &Study, n: u64, block: &Block, s: &ClassifierSettings) {
    let mut by: [BTreeMap<String, (u64, f64, usize)>; 2] = Default::default();
    let mut late: BTreeMap<usize, u64> = BTreeMap::new();
    let mut total = 0.0;
    for i in 0..n {
        let (class, decision, periods, dt) = run(&study.trial(i), block, s);
        total += dt;
        for (map, key) in by.iter_mut().zip([class, decision]) {
            let e = map.entry(key).or_default();
            *e = (e.0 + 1, e.1 + dt, e.2 + periods);
        }
        if periods < s.max_periods {
            *late.entry(periods.div_ceil(50) * 50).or_default() += 1;
        }
    }
    println!(
        "{n} trials in {total:.2} s: {:.0} trials/s on one thread",
        n as f64 / total
    );
    for (title, map) in ["class", "decision"].iter().zip(&by) {
        println!(
            "{title:<24} {:>7} {:>7} {:>9} {:>8}",
            "trials", "time", "ms/trial", "periods"
        );
        for (k, (c, t, p)) in map {
            let c = *c as f64;
            println!(
                "{k:<24} {:>6.2}% {:>6.1}% {:>9.3} {:>8.1}",
                100.0 * c / n as f64,
                100.0 * t / total,
                1e3 * t / c,
                *p as f64 / c
            );
        }
    }
    println!("decided trials by periods taken (up to): {late:?}");
}

fn agree(study: &Study, n: u64, block: &Block, variant: &ClassifierSettings) {
    let reference = ClassifierSettings::default();
    let (mut tr, mut tv, mut same) = (0.0, 0.0, 0u64);
    let mut fractions: BTreeMap<String, (u64, u64)> = BTreeMap::new();
    let mut moved: BTreeMap<String, u64> = BTreeMap::new();
    for i in 0..n {
        let v = study.trial(i);
        let (a, _, _, ta) = run(&v, block, &reference);
        let (b, _, _, tb) = run(&v, block, variant);
        (tr, tv) = (tr + ta, tv + tb);
        fractions.entry(a.clone()).or_default().0 += 1;
        fractions.entry(b.clone()).or_default().1 += 1;
        if a == b {
            same += 1;
        } else {
            *moved.entry(format!("{a} -> {b}")).or_default() += 1;
        }
    }
    report(n, (tr, tv), same, &fractions, &moved);
}

/// Prints the speeds, the share of trials in the same class, each class fraction against the
/// reference's 95 % interval, and the trials that moved.
fn report(
    n: u64,
    (tr, tv): (f64, f64),
    same: u64,
    fractions: &BTreeMap<String, (u64, u64)>,
    moved: &BTreeMap<String, u64>,
) {
    println!(
        "reference {:.0} trials/s, variant {:.0} trials/s ({:.2}x); same class {:.3} %",
        n as f64 / tr,
        n as f64 / tv,
        tr / tv,
        100.0 * same as f64 / n as f64
    );
    for (name, (a, b)) in fractions {
        let (lo, hi) = wilson(*a, n);
        let q = *b as f64 / n as f64;
        let flag = if q < lo || q > hi { "  OUTSIDE" } else { "" };
        println!(
            "  {name:<24} {:.4} -> {q:.4}  [{lo:.4}, {hi:.4}]{flag}",
            *a as f64 / n as f64
        );
    }
    println!("  moved: {moved:?}");
}

/// Writes one line per trial: its index, class and seconds.
fn record(study: &Study, n: u64, block: &Block, s: &ClassifierSettings) {
    for i in 0..n {
        let (class, _, _, dt) = run(&study.trial(i), block, s);
        println!("{i} {class} {dt:.9}");
    }
}

/// Reads a file of [`record`].
fn read_record(path: &str) -> Result<Vec<(String, f64)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            match f.as_slice() {
                [_, class, dt] => Ok((class.to_string(), dt.parse().map_err(|_| l.to_string())?)),
                _ => Err(format!("{path}: bad line {l}")),
            }
        })
        .collect()
}

/// Compares two records of the same trials as `agree` does.
fn compare(reference: &str, variant: &str) -> Result<(), String> {
    let (a, b) = (read_record(reference)?, read_record(variant)?);
    if a.len() != b.len() {
        return Err("the records hold different numbers of trials".into());
    }
    let n = a.len() as u64;
    let (mut tr, mut tv, mut same) = (0.0, 0.0, 0u64);
    let mut fractions: BTreeMap<String, (u64, u64)> = BTreeMap::new();
    let mut moved: BTreeMap<String, u64> = BTreeMap::new();
    for ((ca, ta), (cb, tb)) in a.iter().zip(&b) {
        (tr, tv) = (tr + ta, tv + tb);
        fractions.entry(ca.clone()).or_default().0 += 1;
        fractions.entry(cb.clone()).or_default().1 += 1;
        if ca == cb {
            same += 1;
        } else {
            *moved.entry(format!("{ca} -> {cb}")).or_default() += 1;
        }
    }
    report(n, (tr, tv), same, &fractions, &moved);
    Ok(())
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [mode, a, b] = args.as_slice()
        && mode == "compare"
    {
        return compare(a, b);
    }
    let (mode, mix, n) = match args.as_slice() {
        [mode, mix, n, ..] => (
            mode.as_str(),
            mix.as_str(),
            n.parse::<u64>().map_err(|e| e.to_string())?,
        ),
        _ => return Err("usage: classifier_mix profile|agree MIX N [KEY=VALUE]...".into()),
    };
    let block = Block::default();
    let study = study(mix, &block)?;
    match mode {
        "profile" => profile(&study, n, &block, &settings(&args[3..])?),
        "agree" => agree(&study, n, &block, &settings(&args[3..])?),
        "record" => record(&study, n, &block, &settings(&args[3..])?),
        other => return Err(format!("unknown mode {other} (profile, agree)")),
    }
    Ok(())
}
