//! Every IPOPT problem is freed: thousands of solves do not grow the process. (A test binary of
//! its own, so that no other test allocates beside it while it measures.)

use codesign_core::ipopt::{solve, Hs071, Options};

/// Resident set size of this process in pages.
fn resident_pages() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    statm.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
fn many_solves_do_not_grow_the_process() {
    let options = Options::new();
    for _ in 0..200 {
        solve(&mut Hs071, &options).unwrap();
    }
    let before = resident_pages();
    for _ in 0..2000 {
        solve(&mut Hs071, &options).unwrap();
    }
    let grown_kib = resident_pages().saturating_sub(before) * 4;
    // A leaked IPOPT problem with its MUMPS workspace costs tens of KiB: 2000 of them would be
    // tens of MiB.
    assert!(grown_kib < 2048, "grew by {grown_kib} KiB over 2000 solves");
}
