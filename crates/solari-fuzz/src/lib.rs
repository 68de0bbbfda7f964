//! # solari-fuzz
//!
//! Mutation fuzzing on stable Rust (cargo-fuzz needs a nightly compiler, which this project
//! cannot install) for what reads untrusted input: the glTF/GLB importer and the `solari`
//! command line's argument and file handling.
//!
//! - **Seeds** ([`seeds`]): the repository's test scenes and reproducers (or any folder,
//!   `../shared/scenes` on the project's machines), each also with its external buffers and
//!   images embedded as data URIs and packed as a GLB.
//! - **Mutators** ([`mutate`]): byte flips, insertions, deletions, truncation; structural JSON
//!   changes (huge, negative, overflowing and out-of-range numbers, hostile URIs, wrong types,
//!   dropped or duplicated entries, misplaced glTF keys); corrupted binary payloads (NaN,
//!   infinities, 1e38 in vertex data).
//! - **Targets** ([`targets`]): import, then what the tool does with a scene before the GPU
//!   (validation, statistics, camera, light list, BVH); or parse + check + load for a
//!   generated command line.
//! - **Running** ([`run`]): case `i` is a pure function of the run's seed and `i`; panics are
//!   caught and counted, a watchdog ends a case that runs past the hang limit, and the binary
//!   runs cases in worker processes with a memory limit so an abort or exhausted memory is
//!   found too, not just a panic.
//!
//! ```no_run
//! // What the CI test does: a bounded run in this process.
//! use solari_fuzz::run::{Harness, Progress, Target, run_range};
//! let seeds = solari_fuzz::seeds::load(&solari_fuzz::seeds::default_dirs());
//! let work = std::env::temp_dir().join("solari-fuzz-doc");
//! let h = Harness::new(1, vec![Target::Import, Target::Cli], seeds, &work);
//! let tally = run_range(&h, 0..100, &Progress::default(), std::time::Instant::now(), |_, _, _, _| {});
//! assert!(tally.panics.is_empty());
//! ```
//!
//! On demand, for hours: `cargo run --release -p solari-fuzz -- --cases 10000000 --jobs 2`
//! (see the crate README).

pub mod mutate;
pub mod run;
pub mod seeds;
pub mod targets;
