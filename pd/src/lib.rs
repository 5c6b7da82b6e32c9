//! Bond-based peridynamics (seed 002 section 2.1, seed 000 sections 2-4).
