//! Progress reporting for long computations without printing from the library: the command line
//! supplies an implementation (a progress bar); library callers may ignore it.

/// Receiver of progress on long work (sweeps, basin maps, fits). Must be shareable across the
/// rayon worker threads.
pub trait Progress: Sync {
    /// Announce the total amount of work units.
    fn start(&self, _total: u64, _what: &str) {}
    /// Report `n` more units done.
    fn advance(&self, _n: u64) {}
    /// The work is finished.
    fn finish(&self) {}
}

/// A progress receiver that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}
