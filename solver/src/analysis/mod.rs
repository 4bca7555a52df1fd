//! (module under construction: static, modal and transient analyses)

/// Errors from an analysis (placeholder until the engine lands).
#[derive(Debug, thiserror::Error)]
#[error("solve error")]
pub struct SolveError;
