use rocking_block::model::Parameters;
use rocking_block::orbits::{OrbitKind, orbit};
fn main() {
    let params = Parameters::new(1.3, 0.66);
    let mut t = vec![];
    for _ in 0..50 {
        let s = std::time::Instant::now();
        let o = orbit(&params, OrbitKind::Symmetric, None).unwrap();
        t.push(s.elapsed().as_secs_f64());
        std::hint::black_box(o);
    }
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    println!(
        "orbit(): min {:.3} ms median {:.3} ms",
        1e3 * t[0],
        1e3 * t[25]
    );
}
