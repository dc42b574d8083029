//! Median wall time of an HS071 solve through the safe API, split into callbacks and IPOPT.
//!
//! `cargo bench --bench hs071` (100 solves after 10 warm-up solves).

use codesign::stats::median;
use codesign_core::ipopt::{solve, Hs071, Options};
use std::time::Duration;

/// The median of `samples`, us.
fn median_us(samples: impl Iterator<Item = Duration>) -> f64 {
    median(&samples.map(|d| d.as_secs_f64()).collect::<Vec<_>>()) * 1e6
}

fn main() {
    let options = Options::new().num("tol", 1e-8);
    for _ in 0..10 {
        solve(&mut Hs071, &options).expect("HS071 solves");
    }
    let runs: Vec<_> = (0..100)
        .map(|_| solve(&mut Hs071, &options).expect("HS071 solves"))
        .collect();
    let iterations = runs[0].iterations;
    let total = median_us(runs.iter().map(|s| s.timing.total));
    let callbacks = median_us(runs.iter().map(|s| s.timing.callbacks));
    let ipopt = median_us(runs.iter().map(|s| s.timing.ipopt));
    println!(
        "hs071: {} iterations, f = {:.7}; median of 100 solves: total {:.1} us, callbacks {:.1} us, ipopt {:.1} us",
        iterations,
        runs[0].objective,
        total,
        callbacks,
        ipopt
    );
}
