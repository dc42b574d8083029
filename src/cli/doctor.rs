//! `codesign doctor`: proves that the IPOPT this binary links works, end to end.

use codesign_core::ipopt::{
    check_derivatives, solve, DerivativeOrder, Hs071, Options, HS071_OPTIMUM, IPOPT_VERSION,
};

/// Flags of `codesign doctor`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Show IPOPT's own output of the solve.
    #[arg(long)]
    verbose: bool,
}

/// Solves HS071 and runs IPOPT's second-order derivative checker on it; fails if either is off.
pub fn run(args: &Args) -> Result<(), String> {
    say!(
        "codesign {} linked against IPOPT {IPOPT_VERSION}",
        env!("CARGO_PKG_VERSION")
    );
    let options = Options::new().num("tol", 1e-8).verbose(args.verbose);
    let solution = solve(&mut Hs071, &options).map_err(|e| e.to_string())?;
    say!(
        "HS071: {} after {} iterations, f = {:.7} (published {HS071_OPTIMUM}), {:.3} ms",
        solution.status,
        solution.iterations,
        solution.objective,
        solution.timing.total.as_secs_f64() * 1e3
    );
    if !solution.status.is_success() || (solution.objective - HS071_OPTIMUM).abs() > 1e-6 {
        return Err("HS071 did not solve to its published optimum".to_owned());
    }
    let report = check_derivatives(&mut Hs071, &Options::new(), DerivativeOrder::Second)
        .map_err(|e| e.to_string())?;
    say!(
        "IPOPT derivative checker on HS071: {} error(s)",
        report.errors
    );
    if report.errors > 0 {
        return Err(format!(
            "derivative checker flagged: {}",
            report.flagged.join("; ")
        ));
    }
    say!("ok");
    Ok(())
}
