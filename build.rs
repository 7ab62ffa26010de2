//! The library's source identity: a hash of every file under `src/`, of
//! `Cargo.lock` (the dependencies' versions) and of the compiler's
//! version, so that a study's stages are fresh, and the rows a sweep wrote
//! are taken again (a rerun after records were added), only for a build
//! of the same sources: the crate's version is raised with a table's
//! schema, not with every change of the physics.

use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=src");
    let mut files = Vec::new();
    walk(Path::new("src"), &mut files);
    files.sort();
    // The dependencies' versions (rustfft, statrs, nalgebra compute too),
    // where the build has a lock file.
    // (A path that does not exist would rerun this script on every build.)
    if Path::new("Cargo.lock").is_file() {
        println!("cargo:rerun-if-changed=Cargo.lock");
        files.push(PathBuf::from("Cargo.lock"));
    }
    // FNV-1a over each file's path and bytes: an identity, not a seal.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for f in &files {
        let bytes = std::fs::read(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        fnv(&mut h, f.to_string_lossy().as_bytes());
        fnv(&mut h, &[0]);
        fnv(&mut h, &bytes);
    }
    // The compiler too: another one may round a loop differently.
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = std::process::Command::new(rustc)
        .arg("-vV")
        .output()
        .map(|o| o.stdout)
        .unwrap_or_default();
    fnv(&mut h, &version);
    println!("cargo:rustc-env=ROCKING_SOURCE_HASH={h:016x}");
}

/// FNV-1a's step over `bytes`.
fn fnv(h: &mut u64, bytes: &[u8]) {
    for &b in bytes {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x0100_0000_01b3);
    }
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            walk(&path, out);
        } else {
            out.push(path);
        }
    }
}
