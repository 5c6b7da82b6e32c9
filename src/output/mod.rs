//! Run outputs: atomic files ([`atomic`]), the staging writer that makes a run
//! folder all-or-nothing ([`writer`]), CSV tables ([`csv`]) and JSON
//! ([`writer::OutputWriter::write_json`]). The `summary.json` schema is
//! documented in `docs/outputs.md`.

pub mod atomic;
pub mod csv;
pub mod writer;

pub use atomic::write_atomic;
pub use csv::CsvTable;
pub use writer::OutputWriter;
