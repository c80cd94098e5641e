//! Starts on or past an event surface, from the command line (omega 1.3, alpha 0.66, beta 0).
//!
//! At $\varphi_0 = \psi_0 = 0$ with $\beta = 0$ the forcing is below the lift-off threshold: the
//! block rests, lifts off into mode `-` and overturns to the left at $t = 8.5702$. A start
//! within rounding of the ground ($\varphi_0 = \pm 10^{-30}$) is the same start and must give the
//! same run; a start at $|\varphi_0| \ge \pi/2$ is an overturned block, refused as bad input.

use crate::common;

use common::{RunOk, bin};

fn simulate_json(phi0: &str) -> serde_json::Value {
    let out = bin()
        .args([
            "simulate", "--omega", "1.3", "--alpha", "0.66", "--beta", "0",
        ])
        .arg(format!("--phi0={phi0}"))
        .args(["--psi0", "0", "--periods", "20", "--json"])
        .run_ok();
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn a_start_within_rounding_of_the_ground_is_the_start_on_the_ground() {
    let reference = simulate_json("0");
    assert_eq!(reference["outcome"], "overturn_neg");
    let t_ref = reference["t_end"].as_f64().unwrap();
    approx::assert_abs_diff_eq!(t_ref, 8.5702, epsilon = 1e-4);
    for phi0 in ["1e-30", "-1e-30"] {
        let run = simulate_json(phi0);
        assert_eq!(run["outcome"], reference["outcome"], "phi0 = {phi0}");
        assert_eq!(run["impacts"], reference["impacts"], "phi0 = {phi0}");
        assert_eq!(run["t_end"], reference["t_end"], "phi0 = {phi0}");
    }
}

/// Just below pi/2 the block is past its balance point: it overturns at once, to the right.
#[test]
fn a_start_just_inside_the_overturn_angle_overturns_at_once() {
    let run = simulate_json("1.5707963");
    assert_eq!(run["outcome"], "overturn_pos");
    assert!(run["t_end"].as_f64().unwrap() < 0.01, "{run}");
}

fn assert_refused(args: &[&str], needle: &str) {
    let out = bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
}

#[test]
fn overturned_starts_are_refused_with_exit_code_2() {
    let msg = "|phi0| < pi/2";
    assert_refused(&["simulate", "--phi0", "1.6"], msg);
    assert_refused(&["simulate", "--phi0=-1.5707963267948966"], msg);
    assert_refused(&["classify", "--phi0", "1e308"], "phi0 = 1e308");
    assert_refused(&["classify", "--phi0", "inf"], "phi0");
    assert_refused(&["orbit", "--phi0", "2"], msg);
}
