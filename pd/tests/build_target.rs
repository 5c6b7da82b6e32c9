//! The x86-64 build targets `x86-64-v3` (`.cargo/config.toml`). faer's AVX kernels return
//! with the upper halves of the vector registers dirty, and legacy-SSE code run after
//! them in the same thread was up to 3.4x slower: every force pass after a factorisation
//! (docs/architecture.md, "Build target"). A build without the VEX encoding (the file
//! missing, or `RUSTFLAGS` overriding it) fails here instead of running slowly.

#[test]
#[cfg(target_arch = "x86_64")]
// The value is a property of the build, constant by design: a failing test names the cause,
// where a compile-time assertion would stop every other test from building.
#[allow(clippy::assertions_on_constants)]
fn x86_64_builds_use_the_vex_encoding() {
    assert!(
        cfg!(target_feature = "avx") && cfg!(target_feature = "avx2"),
        "built without AVX: set -C target-cpu=x86-64-v3 (.cargo/config.toml) or expect \
         force passes up to 3.4x slower after every faer factorisation"
    );
}
