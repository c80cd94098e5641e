use hycont_continuation::{OrbitMethod, RunDirection};
use hycont_core::orbit::CollocationSettings;
use rocking_block::continuation::{Free, study_run};
use rocking_block::model::Parameters;
use rocking_block::orbits::{OrbitKind, orbit};
fn main() {
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let mut t = vec![];
    for _ in 0..50 {
        let s = std::time::Instant::now();
        let mut run = study_run(Free::Omega, &params, (0.5, 4.0), method).unwrap();
        run.max_points(3);
        let b = run.run("symmetric", &start, RunDirection::Up).unwrap();
        t.push(s.elapsed().as_secs_f64());
        std::hint::black_box(b);
    }
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    println!(
        "collocation run, 3 points: min {:.3} ms median {:.3} ms",
        1e3 * t[0],
        1e3 * t[25]
    );
}
