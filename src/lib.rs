//! pdbem library: scenes, runner, outputs.
