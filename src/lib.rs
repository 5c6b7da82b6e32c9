//! pdbem library: scenes, runner, outputs, plots and the command line.
//!
//! Map:
//! - [`scene`]: RON scene types, loading, the one `validate()`, dotted paths for sweeps;
//! - [`geometry`]: plane geometry helpers (the `pdbem-geometry` crate, re-exported);
//! - [`setup`]: the one scene-to-model layer (sizing rule, BEM / PD / coupled models,
//!   run footprint) that validation, `check` and `run` share;
//! - [`runner`]: [`runner::RunContext`], [`runner::RunSummary`], dispatch to the solvers,
//!   summary/CSV/plot writing, reference errors;
//! - [`run_bem`], [`run_pd`], [`run_coupled`]: the solver entry points the runner calls;
//! - [`output`]: atomic files, CSV tables, `summary.json`;
//! - [`provenance`]: version, commit, threads, command line, start time, resolved `scene.ron`;
//! - [`plot`]: report plots (geometry, value vs parameter, error vs time, scatter fields);
//! - [`sweep`]: `pdbem sweep` (grid of dotted-path overrides);
//! - [`vtk`]: ParaView files (`outputs.vtk`); [`load_displacement`]: boundary forces and
//!   displacements of PD and coupled runs;
//! - [`bench`](mod@bench): `pdbem bench`; [`bench_trade`]: `pdbem bench trade`;
//! - [`cli`]: the `pdbem` command line; [`console`]: its printed run summaries.

pub mod bench;
pub mod bench_seed001;
pub mod bench_trade;
pub mod cases;
pub mod cli;
pub mod console;
pub mod dynamic_notes;
pub use pdbem_geometry as geometry;
pub mod growth;
pub mod load_displacement;
pub mod output;
pub mod pd_fields;
pub mod pd_loads;
pub mod plot;
pub mod provenance;
pub mod ramp_progress;
pub mod refine;
pub mod run_adaptive;
pub mod run_bem;
pub mod run_coupled;
pub mod run_dynamic;
pub mod run_pd;
pub mod run_refined;
pub mod runner;
pub mod scene;
pub mod setup;
pub mod sweep;
pub mod vtk;
