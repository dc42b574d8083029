//! CMA-ES as pagmo 2 implements it (`pagmo::cmaes`, the "classic" variant of Hansen's 2006
//! review), driven ask/tell so that designs are evaluated outside.
//!
//! The run, in pagmo's order:
//! 1. `initial_population`: lambda designs drawn uniformly in the bounds; `tell_initial` gives
//!    their fitness. The mean starts at the best of them, sigma = sigma0, B = I, D = the bound
//!    widths (each at least 1e-6), C = D^2, so the first steps are sigma0 times the box widths.
//! 2. Each generation draws lambda samples mean + sigma B D z, z ~ N(0, I), not clipped to the
//!    bounds. Before they are handed out the stopping tests run, as in pagmo: stop when the last
//!    sample's step |sigma B D z| < xtol, or when |f_best - f_worst| of the generation evaluated
//!    last (the initial population before generation 1) < ftol; the stopped run's samples are
//!    never evaluated. Unlike pagmo, neither test runs after a generation none of whose designs
//!    was feasible (the caller says which were, see `tell`): a generation penalised alike has
//!    spread 0 because of the penalty, not because the search converged. The run also stops after
//!    `generations` generations, and before it hands out a sample that is not finite (sigma or
//!    the mean grown past any number: no design that is no number is ever evaluated or logged).
//! 3. `tell` ranks the samples (a NaN fitness ranks last, ties keep sample order), moves the mean
//!    to the weighted mean of the best mu = lambda/2, updates the paths ps and pc, C (rank-one and
//!    rank-mu) and sigma, and re-decomposes C when pagmo does.
//!
//! Given the seed and the fitness values told, every design is the same on every machine: the
//! random numbers come from [`DesignRng`], the logarithms, exponentials and powers from `libm`,
//! and no product goes through a CPU-dependent matrix kernel.

use codesign_core::rng::DesignRng;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::cmp::Ordering;

/// Most QR sweeps the eigen-decomposition of C may take before it counts as failed (pagmo then
/// keeps the previous B and D).
const EIGEN_MAX_ITERATIONS: usize = 10_000;

mod error;
mod settings;

pub use error::CmaesError;
pub use settings::{CmaesSettings, SettingError, StopReason, MAX_GENERATIONS, MAX_POPULATION};

/// The constants of the strategy, pagmo's formulas with N = dimension.
#[derive(Clone, Debug)]
struct Strategy {
    /// Parents: lambda / 2.
    mu: usize,
    /// Recombination weights log(mu + 1/2) - log(i), i = 1..mu, normalised to sum 1.
    weights: DVector<f64>,
    /// Variance-effective selection mass 1 / sum w_i^2.
    mueff: f64,
    /// Cumulation constant of pc: (4 + mueff/N) / (N + 4 + 2 mueff/N).
    cc: f64,
    /// Cumulation constant of ps: (mueff + 2) / (N + mueff + 5).
    cs: f64,
    /// Rank-one learning rate: 2 / ((N + 1.3)^2 + mueff).
    c1: f64,
    /// Rank-mu learning rate: 2 (mueff - 2 + 1/mueff) / ((N + 2)^2 + mueff).
    cmu: f64,
    /// Damping of sigma: 1 + 2 max(0, sqrt((mueff - 1)/(N + 1)) - 1) + cs.
    damps: f64,
    /// E|N(0, I)|: sqrt(N) (1 - 1/(4N) + 1/(21 N^2)).
    chi_n: f64,
}

impl Strategy {
    fn new(lambda: usize, dim: usize) -> Strategy {
        let mu = lambda / 2;
        let n = dim as f64;
        let raw = DVector::from_iterator(
            mu,
            (1..=mu).map(|i| libm::log(mu as f64 + 0.5) - libm::log(i as f64)),
        );
        let weights = &raw / raw.sum();
        let mueff = 1.0 / weights.norm_squared();
        let cs = (mueff + 2.0) / (n + mueff + 5.0);
        Strategy {
            mu,
            mueff,
            cc: (4.0 + mueff / n) / (n + 4.0 + 2.0 * mueff / n),
            cs,
            c1: 2.0 / ((n + 1.3) * (n + 1.3) + mueff),
            cmu: 2.0 * (mueff - 2.0 + 1.0 / mueff) / ((n + 2.0) * (n + 2.0) + mueff),
            damps: 1.0 + 2.0 * f64::max(0.0, ((mueff - 1.0) / (n + 1.0)).sqrt() - 1.0) + cs,
            chi_n: n.sqrt() * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n)),
            weights,
        }
    }
}

/// Where the run stands.
#[derive(Clone, Debug)]
enum Phase {
    /// The initial population waits for its fitness.
    Initial,
    /// A generation has been drawn and waits for its fitness.
    Sampled(Vec<DVector<f64>>),
    /// No more designs.
    Stopped(StopReason),
}

/// Orders fitness values ascending with NaN after everything (pagmo's `less_than_f`).
fn nan_last(a: f64, b: f64) -> Ordering {
    match (a.is_nan(), b.is_nan()) {
        (false, false) => a.partial_cmp(&b).unwrap_or(Ordering::Equal),
        (false, true) => Ordering::Less,
        (true, false) => Ordering::Greater,
        (true, true) => Ordering::Equal,
    }
}

/// Index of the first smallest value (NaN last).
fn best_index(fitness: &[f64]) -> usize {
    (1..fitness.len()).fold(0, |best, i| {
        if nan_last(fitness[i], fitness[best]) == Ordering::Less {
            i
        } else {
            best
        }
    })
}

/// |f_best - f_worst|; NaN if any value is NaN, so that it never stops a run.
fn spread(fitness: &[f64]) -> f64 {
    let worst = fitness.iter().copied().fold(f64::NEG_INFINITY, |w, f| {
        if nan_last(f, w) == Ordering::Greater {
            f
        } else {
            w
        }
    });
    (fitness[best_index(fitness)] - worst).abs()
}

/// A CMA-ES run over a box, asked for designs and told their fitness (lower is better).
#[derive(Clone, Debug)]
pub struct Cmaes {
    settings: CmaesSettings,
    strategy: Strategy,
    rng: DesignRng,
    initial: Vec<Vec<f64>>,
    phase: Phase,
    /// Generations told so far (the initial population not counted).
    generation: usize,
    mean: DVector<f64>,
    sigma: f64,
    /// Eigenvectors of C, one per column.
    b: DMatrix<f64>,
    /// Square roots of the eigenvalues of C (standard deviations along the columns of b).
    d: DVector<f64>,
    c: DMatrix<f64>,
    inv_sqrt_c: DMatrix<f64>,
    pc: DVector<f64>,
    ps: DVector<f64>,
    /// Evaluations of sampled generations (pagmo's counteval: the initial population not counted).
    counteval: usize,
    /// counteval at the last eigen-decomposition.
    eigeneval: usize,
    /// Best design seen and its fitness (the first evaluated until something beats it).
    best: Option<(Vec<f64>, f64)>,
}

impl Cmaes {
    /// Checks the settings ([`CmaesSettings::validate`]) and the box (finite bounds, lower <=
    /// upper, at least one dimension)
    /// and draws the initial population.
    pub fn new(
        settings: CmaesSettings,
        lower: Vec<f64>,
        upper: Vec<f64>,
    ) -> Result<Cmaes, CmaesError> {
        settings.validate().map_err(CmaesError::Settings)?;
        if lower.len() != upper.len() || lower.is_empty() {
            return Err(CmaesError::Bounds(format!(
                "the bounds have {} lower and {} upper values; they must agree and not be empty",
                lower.len(),
                upper.len()
            )));
        }
        for (j, (lo, hi)) in lower.iter().zip(&upper).enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(CmaesError::Bounds(format!(
                    "bounds of x[{j}] = [{lo}, {hi}] must be finite with lower <= upper"
                )));
            }
        }
        let dim = lower.len();
        let mut rng = DesignRng::new(settings.seed);
        let initial = (0..settings.population)
            .map(|_| {
                lower
                    .iter()
                    .zip(&upper)
                    .map(|(lo, hi)| lo + rng.uniform() * (hi - lo))
                    .collect()
            })
            .collect();
        let d = DVector::from_iterator(
            dim,
            lower
                .iter()
                .zip(&upper)
                .map(|(lo, hi)| f64::max(hi - lo, 1e-6)),
        );
        Ok(Cmaes {
            strategy: Strategy::new(settings.population, dim),
            sigma: settings.sigma0,
            settings,
            rng,
            initial,
            phase: Phase::Initial,
            generation: 0,
            mean: DVector::zeros(dim),
            b: DMatrix::identity(dim, dim),
            c: DMatrix::from_diagonal(&d.component_mul(&d)),
            inv_sqrt_c: DMatrix::from_diagonal(&d.map(|v| 1.0 / v)),
            d,
            pc: DVector::zeros(dim),
            ps: DVector::zeros(dim),
            counteval: 0,
            eigeneval: 0,
            best: None,
        })
    }

    /// Generation 0: the lambda designs drawn uniformly in the bounds (the same on every call).
    pub fn initial_population(&self) -> Vec<Vec<f64>> {
        self.initial.clone()
    }

    /// Takes the fitness of the initial population, in its order, and whether each design was
    /// feasible (as in [`Cmaes::tell`]); the mean moves to its best. Then draws generation 1, or
    /// stops (generations = 0, or a stopping test).
    pub fn tell_initial(&mut self, fitness: &[f64], feasible: &[bool]) -> Result<(), CmaesError> {
        if !matches!(self.phase, Phase::Initial) {
            return Err(CmaesError::Order(
                "the initial population has already been told its fitness",
            ));
        }
        self.check_length(fitness)?;
        self.check_length(feasible)?;
        for (x, &f) in self.initial.iter().zip(fitness) {
            Self::update_best(&mut self.best, x, f);
        }
        self.mean = DVector::from_column_slice(&self.initial[best_index(fitness)]);
        self.advance(spread(fitness), feasible.contains(&true));
        Ok(())
    }

    /// The designs of the next generation, lambda of them (the same on every call until `tell`);
    /// None before `tell_initial` and once the run has stopped.
    pub fn ask(&self) -> Option<Vec<Vec<f64>>> {
        match &self.phase {
            Phase::Sampled(samples) => {
                Some(samples.iter().map(|x| x.as_slice().to_vec()).collect())
            }
            Phase::Initial | Phase::Stopped(_) => None,
        }
    }

    /// Takes the fitness of the designs `ask` gave, in their order, adapts the distribution and
    /// draws the next generation, or stops. `feasible[i]` says whether design i's fitness is its
    /// objective value rather than a penalty for breaking a constraint: when no design of the
    /// generation was feasible, the ftol and xtol tests are skipped (the run goes on, at most to
    /// `generations`), since a spread of 0 among penalties says nothing about convergence.
    pub fn tell(&mut self, fitness: &[f64], feasible: &[bool]) -> Result<(), CmaesError> {
        let samples = match &self.phase {
            Phase::Sampled(samples) => samples.clone(),
            Phase::Initial => return Err(CmaesError::Order("tell_initial must come before tell")),
            Phase::Stopped(reason) => return Err(CmaesError::Stopped(reason.to_string())),
        };
        self.check_length(fitness)?;
        self.check_length(feasible)?;
        for (x, &f) in samples.iter().zip(fitness) {
            Self::update_best(&mut self.best, x.as_slice(), f);
        }
        self.generation += 1;
        self.counteval += samples.len();
        let mut ranking: Vec<usize> = (0..samples.len()).collect();
        ranking.sort_by(|&i, &j| nan_last(fitness[i], fitness[j]));
        let elite: Vec<&DVector<f64>> = ranking[..self.strategy.mu]
            .iter()
            .map(|&i| &samples[i])
            .collect();
        self.adapt(&elite);
        self.advance(spread(fitness), feasible.contains(&true));
        Ok(())
    }

    /// Generations told so far; 0 until the first sampled generation has been told.
    pub fn generation(&self) -> usize {
        self.generation
    }

    /// The best design seen (the initial population included) and its fitness; None before
    /// `tell_initial`. A NaN fitness never beats a number; ties keep the earlier design.
    pub fn best(&self) -> Option<(&[f64], f64)> {
        self.best.as_ref().map(|(x, f)| (x.as_slice(), *f))
    }

    /// Why the run stopped, once it has.
    pub fn stop_reason(&self) -> Option<StopReason> {
        match self.phase {
            Phase::Stopped(reason) => Some(reason),
            Phase::Initial | Phase::Sampled(_) => None,
        }
    }

    /// The mean of the search distribution (units of x).
    pub fn mean(&self) -> &[f64] {
        self.mean.as_slice()
    }

    /// The step size sigma (relative to the initial bound widths, like sigma0).
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The settings of the run.
    pub fn settings(&self) -> &CmaesSettings {
        &self.settings
    }

    /// Fails unless `values` has one entry per design of a generation.
    fn check_length<T>(&self, values: &[T]) -> Result<(), CmaesError> {
        if values.len() != self.settings.population {
            return Err(CmaesError::Length {
                expected: self.settings.population,
                got: values.len(),
            });
        }
        Ok(())
    }

    fn update_best(best: &mut Option<(Vec<f64>, f64)>, x: &[f64], f: f64) {
        let better = match best {
            None => true,
            Some((_, best_f)) => nan_last(f, *best_f) == Ordering::Less,
        };
        if better {
            *best = Some((x.to_vec(), f));
        }
    }

    /// Draws the next generation and runs pagmo's stopping tests on it and on the fitness spread
    /// of the generation just told, unless none of that generation's designs was `feasible`.
    fn advance(&mut self, spread: f64, feasible: bool) {
        if self.generation >= self.settings.generations {
            self.phase = Phase::Stopped(StopReason::Generations);
            return;
        }
        let dim = self.mean.len();
        let mut samples = Vec::with_capacity(self.settings.population);
        let mut last_step = 0.0;
        for _ in 0..self.settings.population {
            let z = DVector::from_iterator(dim, (0..dim).map(|_| self.rng.normal()));
            let step = (&self.b * self.d.component_mul(&z)) * self.sigma;
            last_step = step.norm();
            samples.push(&self.mean + step);
        }
        let finite = |x: &DVector<f64>| x.iter().all(|v| v.is_finite());
        self.phase = if !samples.iter().all(finite) {
            Phase::Stopped(StopReason::Diverged { sigma: self.sigma })
        } else if !feasible {
            Phase::Sampled(samples)
        } else if last_step < self.settings.xtol {
            Phase::Stopped(StopReason::Xtol { step: last_step })
        } else if spread < self.settings.ftol {
            Phase::Stopped(StopReason::Ftol { spread })
        } else {
            Phase::Sampled(samples)
        };
    }

    /// Moves the mean to the elite's weighted mean and adapts ps, pc, C, sigma, and B and D.
    fn adapt(&mut self, elite: &[&DVector<f64>]) {
        let s = &self.strategy;
        let n = self.mean.len() as f64;
        let lambda = self.settings.population as f64;
        let old_mean = self.mean.clone();
        let mut mean = DVector::zeros(old_mean.len());
        for (x, w) in elite.iter().zip(s.weights.iter()) {
            mean.axpy(*w, *x, 1.0);
        }
        let shift = (&mean - &old_mean) / self.sigma;
        self.mean = mean;

        self.ps = &self.ps * (1.0 - s.cs)
            + (&self.inv_sqrt_c * &shift) * (s.cs * (2.0 - s.cs) * s.mueff).sqrt();
        let decay = 1.0 - libm::pow(1.0 - s.cs, 2.0 * self.counteval as f64 / lambda);
        let hsig = if self.ps.norm_squared() / n / decay < 2.0 + 4.0 / (n + 1.0) {
            1.0
        } else {
            0.0
        };
        self.pc =
            &self.pc * (1.0 - s.cc) + &shift * (hsig * (s.cc * (2.0 - s.cc) * s.mueff).sqrt());

        let old_c = self.c.clone();
        let mut rank_mu = DMatrix::zeros(old_c.nrows(), old_c.ncols());
        for (x, w) in elite.iter().zip(s.weights.iter()) {
            let y = *x - &old_mean;
            rank_mu.ger(*w, &y, &y, 1.0);
        }
        rank_mu /= self.sigma * self.sigma;
        let mut rank_one = DMatrix::zeros(old_c.nrows(), old_c.ncols());
        rank_one.ger(1.0, &self.pc, &self.pc, 0.0);
        rank_one += &old_c * ((1.0 - hsig) * s.cc * (2.0 - s.cc));
        self.c = &old_c * (1.0 - s.c1 - s.cmu) + rank_mu * s.cmu + rank_one * s.c1;

        self.sigma *= libm::exp(f64::min(
            0.6,
            (s.cs / s.damps) * (self.ps.norm() / s.chi_n - 1.0),
        ));

        if (self.counteval - self.eigeneval) as f64 > lambda / (s.c1 + s.cmu) / n / 10.0 {
            self.eigeneval = self.counteval;
            self.c = (&self.c + self.c.transpose()) / 2.0;
            self.decompose();
        }
    }

    /// B and D from C (eigenvalues ascending, as Eigen gives them; each at least 1e-20) and
    /// C^-1/2 = B D^-1 B^T. A failed decomposition keeps the previous ones, as pagmo does.
    fn decompose(&mut self) {
        if !self.c.iter().all(|v| v.is_finite()) {
            return;
        }
        let Some(eigen) =
            SymmetricEigen::try_new(self.c.clone(), f64::EPSILON, EIGEN_MAX_ITERATIONS)
        else {
            return;
        };
        let dim = self.c.nrows();
        let mut order: Vec<usize> = (0..dim).collect();
        order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
        let mut inv_sqrt_c = DMatrix::zeros(dim, dim);
        for (k, &i) in order.iter().enumerate() {
            let column = eigen.eigenvectors.column(i);
            self.b.set_column(k, &column);
            self.d[k] = f64::max(1e-20, eigen.eigenvalues[i]).sqrt();
            inv_sqrt_c.ger(1.0 / self.d[k], &column, &column, 1.0);
        }
        self.inv_sqrt_c = inv_sqrt_c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(population: usize, generations: usize, seed: u64) -> CmaesSettings {
        CmaesSettings {
            population,
            generations,
            sigma0: 0.3,
            seed,
            ftol: 1e-6,
            xtol: 1e-6,
        }
    }

    /// Runs to the end, evaluating `f` here (every design feasible); returns the run and every
    /// design asked, in order.
    fn run(
        settings: CmaesSettings,
        lower: Vec<f64>,
        upper: Vec<f64>,
        f: impl Fn(&[f64]) -> f64,
    ) -> (Cmaes, Vec<Vec<f64>>) {
        run_penalised(settings, lower, upper, |x| (f(x), true))
    }

    /// Runs to the end, `f` giving each design's fitness and whether it was feasible.
    fn run_penalised(
        settings: CmaesSettings,
        lower: Vec<f64>,
        upper: Vec<f64>,
        f: impl Fn(&[f64]) -> (f64, bool),
    ) -> (Cmaes, Vec<Vec<f64>>) {
        let mut es = Cmaes::new(settings, lower, upper).unwrap();
        let mut asked = es.initial_population();
        let (fitness, feasible): (Vec<f64>, Vec<bool>) = asked.iter().map(|x| f(x)).unzip();
        es.tell_initial(&fitness, &feasible).unwrap();
        while let Some(designs) = es.ask() {
            let (fitness, feasible): (Vec<f64>, Vec<bool>) = designs.iter().map(|x| f(x)).unzip();
            es.tell(&fitness, &feasible).unwrap();
            asked.extend(designs);
        }
        (es, asked)
    }

    fn sphere(x: &[f64]) -> f64 {
        x.iter().map(|v| v * v).sum()
    }

    fn rosenbrock(x: &[f64]) -> f64 {
        x.windows(2)
            .map(|p| 100.0 * (p[1] - p[0] * p[0]).powi(2) + (1.0 - p[0]).powi(2))
            .sum()
    }

    #[test]
    fn strategy_constants_follow_pagmo() {
        // lambda = 5, N = 2, computed by hand from pagmo's formulas.
        let s = Strategy::new(5, 2);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert_eq!(s.mu, 2);
        assert!(
            close(s.weights[0], 0.8041628599327295) && close(s.weights[1], 0.19583714006727054)
        );
        assert!(close(s.mueff, 1.4597898888525862));
        assert!(close(s.cc, 0.6340520329526083));
        assert!(close(s.cs, 0.4089687727837697));
        assert!(close(s.c1, 0.16194607503446515));
        assert!(close(s.cmu, 0.016588971631321035));
        assert!(close(s.damps, 1.4089687727837696));
        assert!(close(s.chi_n, 1.254272742818995));
        // The paper's run: lambda = 100, N = 4.
        let s = Strategy::new(100, 4);
        assert_eq!(s.mu, 50);
        assert!((s.mueff - 26.96665506465105).abs() < 1e-12);
        assert!((s.cc - 0.5).abs() < 1e-15);
        assert!((s.cmu - 0.79418980961358).abs() < 1e-13);
        assert!((s.damps - 4.363151502582065).abs() < 1e-13);
    }

    #[test]
    fn first_generation_is_reproduced_by_hand() {
        let (lower, upper) = (vec![-1.0, 2.0, 0.0], vec![3.0, 2.5, 10.0]);
        let widths: Vec<f64> = lower.iter().zip(&upper).map(|(l, u)| u - l).collect();
        let mut es = Cmaes::new(settings(6, 10, 42), lower.clone(), upper.clone()).unwrap();

        // The same stream: 6 x 3 uniforms for the initial population, then normals.
        let mut rng = DesignRng::new(42);
        let initial: Vec<Vec<f64>> = (0..6)
            .map(|_| {
                (0..3)
                    .map(|j| lower[j] + rng.uniform() * widths[j])
                    .collect()
            })
            .collect();
        assert_eq!(es.initial_population(), initial);
        assert!(initial
            .iter()
            .all(|x| (0..3).all(|j| x[j] >= lower[j] && x[j] < upper[j])));

        let fitness: Vec<f64> = initial.iter().map(|x| sphere(x)).collect();
        es.tell_initial(&fitness, &[true; 6]).unwrap();
        let best = (0..6)
            .min_by(|&a, &b| fitness[a].partial_cmp(&fitness[b]).unwrap())
            .unwrap();
        assert_eq!(es.mean(), initial[best].as_slice());
        assert_eq!(es.best(), Some((initial[best].as_slice(), fitness[best])));

        // Generation 1: mean + sigma0 * D z with D = the bound widths and B = I.
        let asked = es.ask().unwrap();
        assert_eq!(asked.len(), 6);
        for x in &asked {
            for j in 0..3 {
                let expected = initial[best][j] + 0.3 * (widths[j] * rng.normal());
                assert!((x[j] - expected).abs() < 1e-14, "{} vs {expected}", x[j]);
            }
        }
        assert_eq!(es.ask().unwrap(), asked, "ask repeats until tell");
        assert_eq!(es.generation(), 0);
    }

    /// One tell of lambda = 5 in N = 2 from a path ps0, checked against pagmo's update written out
    /// by hand; returns hsig.
    fn check_one_tell(ps0: [f64; 2]) -> bool {
        // The constants of `strategy_constants_follow_pagmo`.
        let (w, mueff): ([f64; 2], f64) = (
            [0.8041628599327295, 0.19583714006727054],
            1.4597898888525862,
        );
        let (cc, cs, c1, cmu): (f64, f64, f64, f64) = (
            0.6340520329526083,
            0.4089687727837697,
            0.16194607503446515,
            0.016588971631321035,
        );
        let (damps, chi_n): (f64, f64) = (1.4089687727837696, 1.254272742818995);
        let (sigma0, widths) = (0.3, [2.0, 4.0]);
        let mut es = Cmaes::new(settings(5, 3, 9), vec![0.0, -2.0], vec![2.0, 2.0]).unwrap();
        es.tell_initial(&[5.0, 4.0, 3.0, 2.0, 1.0], &[true; 5])
            .unwrap();
        let m0 = es.initial_population()[4].clone();
        assert_eq!(es.mean(), m0.as_slice());
        es.ps = DVector::from_column_slice(&ps0);
        let x = es.ask().unwrap();
        // Ranks: sample 3 best, then sample 1.
        es.tell(&[9.0, 2.0, 7.0, 0.5, 8.0], &[true; 5]).unwrap();
        let m1: Vec<f64> = (0..2).map(|j| w[0] * x[3][j] + w[1] * x[1][j]).collect();
        for (got, want) in es.mean().iter().zip(&m1) {
            assert!((got - want).abs() < 1e-14);
        }
        // ps = (1 - cs) ps0 + sqrt(cs (2 - cs) mueff) C^-1/2 (m1 - m0) / sigma0, C^-1/2 = diag(1 / widths).
        let shift: Vec<f64> = (0..2).map(|j| (m1[j] - m0[j]) / sigma0).collect();
        let ps: Vec<f64> = (0..2)
            .map(|j| (1.0 - cs) * ps0[j] + (cs * (2.0 - cs) * mueff).sqrt() * shift[j] / widths[j])
            .collect();
        let ps_norm = (ps[0] * ps[0] + ps[1] * ps[1]).sqrt();
        for (got, want) in es.ps.iter().zip(&ps) {
            assert!((got - want).abs() < 1e-13);
        }
        // hsig: |ps|^2 / N / (1 - (1 - cs)^(2 * 5 / 5)) < 2 + 4 / 3.
        let hsig = ps_norm.powi(2) / 2.0 / (1.0 - (1.0 - cs).powi(2)) < 2.0 + 4.0 / 3.0;
        let h = if hsig { 1.0 } else { 0.0 };
        let pc: Vec<f64> = (0..2)
            .map(|j| h * (cc * (2.0 - cc) * mueff).sqrt() * shift[j])
            .collect();
        for (got, want) in es.pc.iter().zip(&pc) {
            assert!((got - want).abs() < 1e-13);
        }
        // C = (1 - c1 - cmu) C0 + cmu sum w_i y_i y_i^T + c1 (pc pc^T + (1 - hsig) cc (2 - cc) C0).
        let y = |i: usize, j: usize| (x[i][j] - m0[j]) / sigma0;
        for r in 0..2 {
            for c in 0..2 {
                let c0 = if r == c { widths[r] * widths[r] } else { 0.0 };
                let rank_mu = w[0] * y(3, r) * y(3, c) + w[1] * y(1, r) * y(1, c);
                let expected = (1.0 - c1 - cmu) * c0
                    + cmu * rank_mu
                    + c1 * (pc[r] * pc[c] + (1.0 - h) * cc * (2.0 - cc) * c0);
                assert!((es.c[(r, c)] - expected).abs() < 1e-12 * expected.abs().max(1.0));
            }
        }
        // sigma = sigma0 exp(min(0.6, cs / damps (|ps| / chiN - 1))).
        let sigma = sigma0 * f64::exp(f64::min(0.6, cs / damps * (ps_norm / chi_n - 1.0)));
        assert!((es.sigma() - sigma).abs() < 1e-15);
        // lambda / (c1 + cmu) / N / 10 = 1.4 < 5 evaluations: B and D were recomputed from C.
        assert_eq!(es.eigeneval, 5);
        let rebuilt = &es.b * DMatrix::from_diagonal(&es.d.map(|v| v * v)) * es.b.transpose();
        assert!((rebuilt - &es.c).norm() < 1e-12 * es.c.norm());
        assert!(es.d[0] <= es.d[1], "eigenvalues ascending");
        let identity = &es.inv_sqrt_c * &es.c * &es.inv_sqrt_c;
        assert!((identity - DMatrix::identity(2, 2)).norm() < 1e-12);
        assert_eq!(es.generation(), 1);
        hsig
    }

    #[test]
    fn one_tell_adapts_as_computed_by_hand() {
        assert!(check_one_tell([0.0, 0.0]), "a short path keeps hsig = 1");
        assert!(!check_one_tell([4.0, -3.0]), "a long path sets hsig = 0");
    }

    #[test]
    fn minimises_the_sphere() {
        let mut s = settings(12, 400, 1);
        (s.ftol, s.xtol) = (1e-14, 1e-10);
        let (es, _) = run(s, vec![-5.0; 4], vec![5.0; 4], sphere);
        let (x, f) = es.best().unwrap();
        assert!(f < 1e-8, "f = {f} at {x:?}, {:?}", es.stop_reason());
    }

    #[test]
    fn minimises_rosenbrock() {
        let mut s = settings(16, 1000, 2);
        (s.ftol, s.xtol) = (1e-14, 1e-10);
        let (es, _) = run(s, vec![-2.0; 4], vec![2.0; 4], rosenbrock);
        let (x, f) = es.best().unwrap();
        assert!(f < 1e-6, "f = {f} at {x:?}, {:?}", es.stop_reason());
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-2), "{x:?}");
    }

    #[test]
    fn seeds_fix_the_designs() {
        let go = |seed| {
            run(
                settings(10, 15, seed),
                vec![1.0, 1.0],
                vec![9.0, 3.0],
                rosenbrock,
            )
        };
        let (a, designs_a) = go(3);
        let (b, designs_b) = go(3);
        let (_, designs_c) = go(4);
        assert_eq!(designs_a.len(), 10 * 16);
        assert_eq!(designs_a, designs_b);
        assert_eq!(a.best(), b.best());
        assert_ne!(designs_a[..10], designs_c[..10]);
        assert_ne!(designs_a[10..20], designs_c[10..20]);
    }

    #[test]
    fn stops_after_the_generations() {
        let (es, designs) = run(settings(5, 3, 0), vec![0.0], vec![1.0], |x| {
            (x[0] - 0.3).abs()
        });
        assert_eq!(es.stop_reason(), Some(StopReason::Generations));
        assert_eq!((es.generation(), designs.len()), (3, 20));
        let (es, designs) = run(settings(5, 0, 0), vec![0.0], vec![1.0], |x| x[0]);
        assert_eq!(es.stop_reason(), Some(StopReason::Generations));
        assert_eq!((es.generation(), designs.len()), (0, 5));
    }

    #[test]
    fn stops_on_a_flat_fitness_and_on_small_steps() {
        // Every design feasible and scored alike: the initial population is flat and the run
        // ends at once.
        let (es, designs) = run(settings(8, 30, 0), vec![1.0; 4], vec![9.0; 4], |_| 1e6);
        assert_eq!(es.stop_reason(), Some(StopReason::Ftol { spread: 0.0 }));
        assert_eq!(designs.len(), 8);
        // Steps are sigma0 * 1e-6 wide when the box is a point: under xtol = 1e-6.
        let (es, _) = run(settings(8, 30, 0), vec![2.0; 2], vec![2.0; 2], sphere);
        assert!(matches!(es.stop_reason(), Some(StopReason::Xtol { step }) if step < 1e-6));
        // On the sphere the spread shrinks until ftol stops the run before the generation limit.
        let (es, _) = run(settings(10, 10_000, 0), vec![-1.0; 2], vec![1.0; 2], sphere);
        assert!(matches!(es.stop_reason(), Some(StopReason::Ftol { spread }) if spread < 1e-6));
        assert!(es.generation() < 10_000);
    }

    #[test]
    fn generations_penalised_alike_never_stop_the_run() {
        // Every design penalised alike: spread 0 every generation, yet the run goes to its limit.
        let (es, designs) = run_penalised(settings(8, 30, 0), vec![1.0; 4], vec![9.0; 4], |_| {
            (1e6, false)
        });
        assert_eq!(es.stop_reason(), Some(StopReason::Generations));
        assert_eq!((es.generation(), designs.len()), (30, 8 * 31));
        // A point box gives steps under xtol; with no feasible design that stops nothing either.
        let (es, _) = run_penalised(settings(8, 5, 0), vec![2.0; 2], vec![2.0; 2], |_| {
            (1e6, false)
        });
        assert_eq!(es.stop_reason(), Some(StopReason::Generations));
        // The initial population and the first two generations penalised alike, then the
        // sphere: the run goes on through them and then converges and stops as before.
        let evaluations = std::cell::Cell::new(0);
        let f = |x: &[f64]| {
            evaluations.set(evaluations.get() + 1);
            if evaluations.get() <= 30 {
                (1e6, false)
            } else {
                (sphere(x), true)
            }
        };
        let mut s = settings(10, 2000, 3);
        s.xtol = 1e-10;
        let (es, _) = run_penalised(s, vec![-5.0; 2], vec![5.0; 2], f);
        let (x, best) = es.best().unwrap();
        assert!(best < 1e-6, "{best} at {x:?}");
        assert!(matches!(es.stop_reason(), Some(StopReason::Ftol { .. })));
        assert!(es.generation() > 3 && es.generation() < 2000);
    }

    #[test]
    fn one_feasible_design_lets_the_tests_run() {
        // Flat penalties with one feasible design at the same value: the spread is 0 and ftol
        // stops the run, as pagmo's would.
        let mut es = Cmaes::new(settings(5, 10, 0), vec![0.0], vec![1.0]).unwrap();
        es.tell_initial(&[1e6; 5], &[false, false, true, false, false])
            .unwrap();
        assert_eq!(es.stop_reason(), Some(StopReason::Ftol { spread: 0.0 }));
        let mut es = Cmaes::new(settings(5, 10, 0), vec![0.0], vec![1.0]).unwrap();
        es.tell_initial(&[1e6; 5], &[false; 5]).unwrap();
        assert_eq!(es.stop_reason(), None);
        es.tell(&[1e6; 5], &[false; 5]).unwrap();
        assert_eq!((es.stop_reason(), es.generation()), (None, 1));
        es.tell(&[1e6; 5], &[true; 5]).unwrap();
        assert_eq!(es.stop_reason(), Some(StopReason::Ftol { spread: 0.0 }));
    }

    #[test]
    fn samples_are_not_clipped_to_the_bounds() {
        let (_, designs) = run(settings(10, 20, 5), vec![0.0; 2], vec![1.0; 2], |x| {
            (x[0] - 5.0).powi(2) + (x[1] + 5.0).powi(2)
        });
        assert!(designs.iter().any(|x| x[0] > 1.0 || x[1] < 0.0));
    }

    #[test]
    fn nan_fitness_ranks_last() {
        let f = |x: &[f64]| if x[0] > 0.5 { f64::NAN } else { sphere(x) };
        let mut s = settings(12, 300, 8);
        (s.ftol, s.xtol) = (0.0, 1e-9);
        let (es, _) = run(s, vec![-3.0; 3], vec![3.0; 3], f);
        let (_, best) = es.best().unwrap();
        assert!(best < 1e-8, "{best}");
        assert!(spread(&[1.0, f64::NAN, 2.0]).is_nan());
        assert_eq!(best_index(&[f64::NAN, 3.0, 1.0, 1.0]), 2);
    }

    /// Issue 57, item 10: a search that runs away (a fitness falling without end along a line)
    /// grows sigma past any number; it stops before it asks for a design that is not finite.
    #[test]
    fn a_search_whose_step_size_overflows_stops_before_a_design_that_is_not_finite() {
        let mut s = settings(5, MAX_GENERATIONS, 0);
        s.sigma0 = 1.0;
        let (es, asked) = run(s, vec![0.0], vec![1.0], |x| -x[0]);
        let infinite = asked.iter().find(|x| !x.iter().all(|v| v.is_finite()));
        assert_eq!(infinite, None, "after {} designs", asked.len());
        let reason = es.stop_reason();
        assert!(
            matches!(reason, Some(StopReason::Diverged { .. })),
            "{reason:?}"
        );
        assert!(es.generation() < MAX_GENERATIONS);
    }

    #[test]
    fn bad_settings_and_calls_are_errors() {
        let new = |s: CmaesSettings, lo: Vec<f64>, hi: Vec<f64>| {
            Cmaes::new(s, lo, hi).unwrap_err().to_string()
        };
        assert!(new(settings(4, 1, 0), vec![0.0], vec![1.0]).contains("at least 5"));
        let mut s = settings(5, 1, 0);
        s.sigma0 = 0.0;
        assert!(new(s, vec![0.0], vec![1.0]).contains("sigma0"));
        let mut s = settings(5, 1, 0);
        s.ftol = f64::NAN;
        assert!(new(s, vec![0.0], vec![1.0]).contains("ftol"));
        assert!(new(settings(5, 1, 0), vec![0.0, 1.0], vec![1.0]).contains("must agree"));
        assert!(new(settings(5, 1, 0), vec![], vec![]).contains("not be empty"));
        assert!(new(settings(5, 1, 0), vec![2.0], vec![1.0]).contains("x[0]"));
        assert!(new(settings(5, 1, 0), vec![0.0], vec![f64::INFINITY]).contains("x[0]"));

        let mut es = Cmaes::new(settings(5, 1, 0), vec![0.0], vec![1.0]).unwrap();
        assert_eq!(es.ask(), None);
        assert_eq!(es.best(), None);
        assert!(es
            .tell(&[1.0; 5], &[true; 5])
            .unwrap_err()
            .to_string()
            .contains("tell_initial"));
        assert!(es
            .tell_initial(&[1.0; 4], &[true; 4])
            .unwrap_err()
            .to_string()
            .contains("expected 5"));
        assert!(es
            .tell_initial(&[1.0; 5], &[true; 4])
            .unwrap_err()
            .to_string()
            .contains("expected 5 values"));
        es.tell_initial(&[1.0, 2.0, 3.0, 4.0, 5.0], &[true; 5])
            .unwrap();
        assert!(es
            .tell_initial(&[1.0; 5], &[true; 5])
            .unwrap_err()
            .to_string()
            .contains("already"));
        assert!(es
            .tell(&[1.0; 6], &[true; 6])
            .unwrap_err()
            .to_string()
            .contains("expected 5"));
        es.tell(&[1.0, 2.0, 3.0, 4.0, 5.0], &[true; 5]).unwrap();
        assert_eq!(es.stop_reason(), Some(StopReason::Generations));
        assert!(es
            .tell(&[1.0; 5], &[true; 5])
            .unwrap_err()
            .to_string()
            .contains("stopped"));
    }

    #[test]
    fn a_short_run_gives_the_pinned_values() {
        // Values of this implementation, kept to catch any change of the stream or the arithmetic:
        // a machine or a dependency version that gives other values breaks reproducibility.
        let (es, designs) = run(
            settings(10, 5, 0),
            vec![1.0, 1.0, 1.0, 1.0],
            vec![9.0, 9.0, 3.0, 3.0],
            rosenbrock,
        );
        assert_eq!(designs.len(), 60);
        let (x, f) = es.best().unwrap();
        assert_eq!(
            x,
            [
                -0.9035039119317126,
                0.975672043395648,
                1.354153497332409,
                2.7441353433253544
            ]
        );
        assert_eq!(f, 105.35004982528876);
        assert_eq!(
            es.mean(),
            [
                0.5878344390117509,
                1.1031474790779494,
                1.1546803079662917,
                2.1146383983058
            ]
        );
        assert_eq!(es.sigma(), 0.22466498605633176);
    }
}
