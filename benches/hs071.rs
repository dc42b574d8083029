//! Median wall time of an HS071 solve through the safe API, split into callbacks and IPOPT.
//!
//! `cargo bench --bench hs071` (100 solves after 10 warm-up solves).

use codesign::ipopt::{solve, Hs071, Options};
use std::time::Duration;

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
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
    let total = median(runs.iter().map(|s| s.timing.total).collect());
    let callbacks = median(runs.iter().map(|s| s.timing.callbacks).collect());
    let ipopt = median(runs.iter().map(|s| s.timing.ipopt).collect());
    println!(
        "hs071: {} iterations, f = {:.7}; median of 100 solves: total {:.1} us, callbacks {:.1} us, ipopt {:.1} us",
        iterations,
        runs[0].objective,
        total.as_secs_f64() * 1e6,
        callbacks.as_secs_f64() * 1e6,
        ipopt.as_secs_f64() * 1e6
    );
}
