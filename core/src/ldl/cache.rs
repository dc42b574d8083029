//! The analyses of the last few structures, shared by every factorisation in the process.
//!
//! IPOPT analyses its KKT structure when a solve starts, and this solver analyses it again when
//! a diagonal it took for non-zero turns out zero (see [`Symbolic::needs_reanalysis`]): twice per
//! trajectory solve. A worker solves many designs of one formulation, whose KKT matrices share
//! their structure and their zero diagonals, so each analysis is kept here and handed out again.
//! An analysis depends on nothing but the structure (`n`, row starts, columns) and what it
//! assumes of each row's diagonal, so a structure is looked up by comparing all of these in full,
//! and a reused analysis is the very one a new analysis would compute.

use super::ordering::RowKind;
use super::{LdlError, Symbolic, UpperCsr};
use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// How many analyses the process-wide cache keeps: enough for a worker that alternates between
/// both spaces and the hard and elastic problems, each with its two analyses.
pub const KEPT_ANALYSES: usize = 8;

/// The process-wide cache behind IPOPT's Pardiso handles.
static SHARED: AnalysisCache = AnalysisCache::new(KEPT_ANALYSES);

/// How often a cache analysed a structure and how often it handed out an analysis it kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheCounts {
    /// Analyses computed.
    pub analysed: usize,
    /// Analyses handed out again.
    pub reused: usize,
}

/// One kept analysis with the structure it was computed for.
#[derive(Debug)]
struct Kept {
    ia: Vec<i32>,
    ja: Vec<i32>,
    symbolic: Arc<Symbolic>,
}

impl Kept {
    /// Whether this is the analysis of `matrix` (with `entries` entries) under `kinds`.
    fn is_for(&self, matrix: UpperCsr<'_>, entries: usize, kinds: &[RowKind]) -> bool {
        self.ia == matrix.ia && self.ja == matrix.ja[..entries] && self.symbolic.kinds() == kinds
    }
}

/// The analyses of the last `capacity` structures (with their assumed diagonals), most recently
/// used first, and counts of analyses computed and reused.
#[derive(Debug)]
pub struct AnalysisCache {
    kept: Mutex<VecDeque<Kept>>,
    capacity: usize,
    analysed: AtomicUsize,
    reused: AtomicUsize,
}

impl AnalysisCache {
    /// An empty cache that keeps at most `capacity` analyses.
    pub const fn new(capacity: usize) -> AnalysisCache {
        AnalysisCache {
            kept: Mutex::new(VecDeque::new()),
            capacity,
            analysed: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
        }
    }

    /// The cache that IPOPT's factorisations with this solver share.
    pub fn shared() -> &'static AnalysisCache {
        &SHARED
    }

    /// [`Symbolic::analyse`], or the kept analysis of the same structure and zero diagonals.
    pub fn analyse(
        &self,
        n: usize,
        matrix: UpperCsr<'_>,
        values: &[f64],
    ) -> Result<Arc<Symbolic>, LdlError> {
        let (kinds, entries) = Symbolic::assumed_kinds(n, matrix, values)?;
        self.get_or_analyse(n, matrix, kinds, entries)
    }

    /// [`Symbolic::reanalyse`] of `previous`, or the kept analysis it would compute.
    pub fn reanalyse(
        &self,
        previous: &Symbolic,
        matrix: UpperCsr<'_>,
        values: &[f64],
    ) -> Result<Arc<Symbolic>, LdlError> {
        let kinds = previous.kinds_with_zeros_of(matrix, values)?;
        self.get_or_analyse(previous.n(), matrix, kinds, previous.entries())
    }

    /// The counts so far.
    pub fn counts(&self) -> CacheCounts {
        CacheCounts {
            analysed: self.analysed.load(Ordering::Relaxed),
            reused: self.reused.load(Ordering::Relaxed),
        }
    }

    /// The kept analysis of `matrix` under `kinds`, moved to the front; otherwise a new one,
    /// kept in front of the others (the least recently used one dropped beyond the capacity).
    /// The lock is not held while analysing, so solves on other threads never wait for it.
    fn get_or_analyse(
        &self,
        n: usize,
        matrix: UpperCsr<'_>,
        kinds: Vec<RowKind>,
        entries: usize,
    ) -> Result<Arc<Symbolic>, LdlError> {
        if let Some(symbolic) = self.lookup(matrix, entries, &kinds) {
            self.reused.fetch_add(1, Ordering::Relaxed);
            return Ok(symbolic);
        }
        let symbolic = Arc::new(Symbolic::analyse_as(n, matrix, kinds, entries)?);
        self.analysed.fetch_add(1, Ordering::Relaxed);
        let mut kept = self.lock();
        // Another thread may have kept the same analysis meanwhile: keep one copy.
        if !kept
            .iter()
            .any(|k| k.is_for(matrix, entries, symbolic.kinds()))
        {
            kept.push_front(Kept {
                ia: matrix.ia.to_vec(),
                ja: matrix.ja[..entries].to_vec(),
                symbolic: Arc::clone(&symbolic),
            });
            kept.truncate(self.capacity);
        }
        Ok(symbolic)
    }

    /// The kept analysis of `matrix` under `kinds`, moved to the front.
    fn lookup(
        &self,
        matrix: UpperCsr<'_>,
        entries: usize,
        kinds: &[RowKind],
    ) -> Option<Arc<Symbolic>> {
        let mut kept = self.lock();
        let index = kept.iter().position(|k| k.is_for(matrix, entries, kinds))?;
        let found = kept.remove(index)?;
        let symbolic = Arc::clone(&found.symbolic);
        kept.push_front(found);
        Some(symbolic)
    }

    /// The kept analyses; a panic elsewhere while holding the lock leaves them consistent (every
    /// change is a single push, remove or truncate), so a poisoned lock is taken over.
    fn lock(&self) -> std::sync::MutexGuard<'_, VecDeque<Kept>> {
        self.kept
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}
