use hycont_continuation::{OrbitMethod, RunDirection};
use hycont_core::orbit::CollocationSettings;
use rocking_block::continuation::{Free, study_run};
use rocking_block::model::Parameters;
use rocking_block::orbits::{OrbitKind, orbit};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
struct A;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static TOTAL: AtomicUsize = AtomicUsize::new(0);
static BIG: AtomicUsize = AtomicUsize::new(0);
thread_local!(static IN: std::cell::Cell<bool> = const { std::cell::Cell::new(false) });
unsafe impl GlobalAlloc for A {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(l.size(), Relaxed) + l.size();
        PEAK.fetch_max(live, Relaxed);
        TOTAL.fetch_add(l.size(), Relaxed);
        if l.size() > 60_000 && std::env::var("BT").is_ok() {
            BIG.fetch_add(1, Relaxed);
            IN.with(|g| {
                if !g.get() {
                    g.set(true);
                    let bt = std::backtrace::Backtrace::force_capture().to_string();
                    let frames: Vec<&str> = bt
                        .lines()
                        .filter(|l| l.contains("hycont") || l.contains("rocking"))
                        .filter(|l| !l.contains(" at "))
                        .take(4)
                        .collect();
                    eprintln!("ALLOC {} {:?}", l.size(), frames);
                    g.set(false);
                }
            });
        }
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Relaxed);
        unsafe { System.dealloc(p, l) }
    }
}
#[global_allocator]
static G: A = A;
fn main() {
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    println!(
        "after orbit: peak {} KB total {} KB",
        PEAK.load(Relaxed) / 1024,
        TOTAL.load(Relaxed) / 1024
    );
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let mut run = study_run(Free::Omega, &params, (0.5, 4.0), method).unwrap();
    run.max_points(3);
    let b = run.run("symmetric", &start, RunDirection::Up).unwrap();
    std::hint::black_box(b);
    println!(
        "after run: peak {} KB total {} KB big {}",
        PEAK.load(Relaxed) / 1024,
        TOTAL.load(Relaxed) / 1024,
        BIG.load(Relaxed)
    );
}
