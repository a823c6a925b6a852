//! The model version (`raceway::MODEL_VERSION`): the package version and a hash of the sources
//! that compute a run's result (the library and the solver crate), so that a sweep's table
//! records which model made each row and refuses rows of another one.

use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs" || x == "toml") {
            out.push(p);
        }
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let dirs = [
        root.join("src"),
        root.join("solver/src"),
        root.join("presets"),
    ];
    let mut list = Vec::new();
    for d in &dirs {
        println!("cargo:rerun-if-changed={}", d.display());
        files(d, &mut list);
    }
    list.sort();
    // FNV-1a 64 over each file's path (relative) and contents.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in &list {
        let rel = p.strip_prefix(&root).unwrap_or(p);
        let bytes = std::fs::read(p).unwrap_or_default();
        for b in rel
            .to_string_lossy()
            .as_bytes()
            .iter()
            .chain(&[0u8])
            .chain(&bytes)
        {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    println!("cargo:rustc-env=RACEWAY_SOURCE_HASH={h:016x}");
}
