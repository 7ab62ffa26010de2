//! Links the `rocking` binary as a position-dependent executable on Linux
//! with the GNU toolchain: the loader then has no relative relocations to
//! apply (about 33,500 in a PIE build) and fewer pages to copy at start,
//! which takes about 0.5 ms off every command (1.9 → 1.4 ms for
//! `rocking --version` on the project's machine; docs/BENCHMARKS.md).
//! Scripts call `rocking capacity` in loops, so start-up counts. The
//! library, the tests and every dependency are compiled as before (this
//! is a link argument of the binaries only, so nothing is rebuilt).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let env = std::env::var("CARGO_CFG_TARGET_ENV").unwrap_or_default();
    if os == "linux" && env == "gnu" {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
}
