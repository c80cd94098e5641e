use hycont_continuation::{OrbitMethod, RunDirection};
use hycont_core::orbit::CollocationSettings;
use rocking_block::continuation::{Free, default_method, study_run};
use rocking_block::model::Parameters;
use rocking_block::orbits::{OrbitKind, orbit};
fn main() {
    let which = std::env::args().nth(1).unwrap_or("collocation".into());
    let reps: usize = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(50);
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let method = if which == "shooting" {
        default_method()
    } else {
        OrbitMethod::Collocation(CollocationSettings {
            ntst: 20,
            ncol: 4,
            adapt: 1,
        })
    };
    let mut times = vec![];
    let mut last = None;
    for _ in 0..reps {
        let t = std::time::Instant::now();
        let mut run = study_run(Free::Omega, &params, (0.5, 4.0), method).unwrap();
        let b = run
            .run("symmetric", &start, RunDirection::Both)
            .unwrap()
            .branch;
        times.push(t.elapsed().as_secs_f64());
        last = Some(b);
    }
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let b = last.unwrap();
    let points = b.points.len() + b.special_points.len();
    let it: usize = b.points.iter().map(|p| p.newton_iterations).sum();
    println!(
        "{which}: {points} pts, min {:.3} median {:.3} ms/pt ({:.2} ms), it/pt {:.2}; {:?}",
        1e3 * times[0] / points as f64,
        1e3 * times[reps / 2] / points as f64,
        1e3 * times[reps / 2],
        it as f64 / b.points.len() as f64,
        b.statistics
    );
    for s in &b.special_points {
        println!("  {:?} {:.12}", s.kind, s.point.u[s.point.u.len() - 1]);
    }
}
