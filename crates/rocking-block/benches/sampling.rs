//! Sampling benchmarks (issue: sampling). Run with `cargo bench -p rocking-block --bench sampling`.
//!
//! Reference: a Python/scipy implementation of the same classifier costs 0.04-2.4 s per trial
//! and ~15-20 ms per forcing period of brute-force simulation on the project machine. Targets
//! on 2 cores: Fig. 5 at the study's settings (300 + 100 periods at each of 301 alpha values)
//! under 5 s; Fig. 7 at 20,000 trials per omega under 60 s; Fig. 9 at 1,000,000 trials per beta
//! under 10 min. Throughput is measured on 2,000-trial basins (trials per second = 2000 / time).
//!
//! `classifier_mix`: the classifier alone on one thread over the first 2,000 trials of each
//! sampling figure's mix (Fig. 7 at omega = 1.3; Fig. 9 at beta = 0 and pi/2; Fig. 10): trials
//! per second per core = 2000 / time (issue 27's targets: 7,500 for Fig. 9, 6,750 for Fig. 10).

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_sample::basin::{Classifier, Study};
use hycont_sample::basin::{Progress, run};
use rocking_block::block::Block;
use rocking_block::classes::RockingClassifier;
use rocking_block::figures::sampling::{fig7_study, fig9_study, fig10_study, figure5};
use rocking_block::output::OutDir;
use rocking_block::provenance::Provenance;
use std::hint::black_box;

fn sampling(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("hycont-bench-sampling");
    std::fs::create_dir_all(&dir).unwrap();
    let mut g = c.benchmark_group("sampling");
    g.sample_size(10);
    g.bench_function("figure5_study_settings_both_sweeps", |b| {
        b.iter(|| {
            black_box(
                figure5(
                    &OutDir::new(&dir),
                    &Provenance::default(),
                    &Progress::default(),
                )
                .unwrap(),
            )
        });
    });
    let classifier = RockingClassifier::default();
    for omega in [1.16, 4.0] {
        let study = fig7_study(omega, 1, &Block::default());
        g.bench_function(format!("fig7_basin_omega_{omega}_2000_trials"), |b| {
            b.iter(|| black_box(run(&study, &classifier, 0..2000, &Progress::default()).unwrap()));
        });
    }
    g.finish();
}

/// The first `n` trials of `study`, classified one after another on this thread.
fn classify_all(study: &Study, classifier: &RockingClassifier, n: u64) -> usize {
    (0..n)
        .filter_map(|i| classifier.classify(&study.trial(i)).ok())
        .sum()
}

fn classifier_mix(c: &mut Criterion) {
    let block = Block::default();
    let classifier = RockingClassifier::default();
    let mixes = [
        ("fig7_omega_1.3", fig7_study(1.3, 1, &block)),
        ("fig9_beta_0", fig9_study(0.0, 1, &block)),
        (
            "fig9_beta_pi_2",
            fig9_study(std::f64::consts::FRAC_PI_2, 1, &block),
        ),
        ("fig10", fig10_study(1, &block).0),
    ];
    let mut g = c.benchmark_group("classifier_mix");
    g.sample_size(10);
    for (name, study) in &mixes {
        g.bench_function(format!("{name}_2000_trials_one_thread"), |b| {
            b.iter(|| black_box(classify_all(study, &classifier, 2000)));
        });
    }
    g.finish();
}

criterion_group!(benches, sampling, classifier_mix);
criterion_main!(benches);
