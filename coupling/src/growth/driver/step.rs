//! The record of one completed try at a load step, shared by the step loop
//! ([`super::run`]), the back-off ([`super::backoff`]) and the crack-to-hole joins
//! ([`super::join`]).

/// What one completed try at a load step did.
#[derive(Debug, Clone, Default)]
pub(super) struct StepRun {
    /// The load it ended at.
    pub load: f64,
    /// Converged (interface residual below psi, no bond breaking).
    pub converged: bool,
    /// Last interface residual (NaN when the coupling broke down).
    pub residual: f64,
    /// The tip that ended the run (structural failure).
    pub cut: Option<usize>,
    /// The PD ligament gave way (the coupling broke down).
    pub gave_way: bool,
    /// Algorithm 1 iterations.
    pub iterations: usize,
    /// PD seconds.
    pub pd_s: f64,
    /// Relocations.
    pub relocations: usize,
    /// The accelerator reported a restart or hand-over.
    pub noted: bool,
}
