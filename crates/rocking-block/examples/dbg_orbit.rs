use rocking_block::orbits::*;
use rocking_block::*;
fn main() {
    let params = Parameters::new(1.3, 0.66);
    for kind in [
        OrbitKind::Symmetric,
        OrbitKind::AsymmetricPos,
        OrbitKind::AsymmetricNeg,
    ] {
        let t = std::time::Instant::now();
        let o = orbit(&params, kind, None).unwrap();
        let r = o.report(&format!("{kind:?}")).unwrap();
        println!(
            "{kind:?} in {:?}: amp {} period {} stable {} mult {:?} half {:?} grazing {:?}",
            t.elapsed(),
            r.amp,
            r.period,
            r.stable,
            r.multipliers,
            r.half_multipliers,
            r.grazing
        );
        for s in &r.segments {
            println!("   {} {} {:?}", s.mode, s.duration, s.start);
        }
    }
}
