//! Generates the C++ half of the bridge (`cooperation-cpp/src/bridge.rs.h` and `rust/cxx.h`) and
//! compiles it, with the lock annotations (`lib/annotate.cpp`), into this crate's static library.
//!
//! The headers are also copied, as files, into the profile's own folder of the target directory
//! (`target/release/cxxbridge/` for a release build): the C++ side includes them from there, so it
//! always compiles against the headers of the library it links. `cxx-build`'s shared
//! `target/cxxbridge/` holds links to whichever profile built last, which a debug build made
//! after the release one would point at its own output.

use std::path::{Path, PathBuf};

fn main() {
    cxx_build::bridge("src/bridge.rs")
        .file("lib/annotate.cpp")
        .include("include")
        .std("c++17")
        .compile("cooperation-cpp-bridge");
    println!("cargo:rerun-if-changed=src/bridge.rs");
    println!("cargo:rerun-if-changed=lib/annotate.cpp");
    println!("cargo:rerun-if-changed=include/cooperation/rtc/annotate.hpp");
    if let Err(error) = copy_headers() {
        println!("cargo:warning=the bridge's headers were not copied for the C++ build: {error}");
    }
}

/// Copies the generated headers from `OUT_DIR` into `<profile>/cxxbridge/`, rewriting a file
/// only when its contents changed (so a C++ build does not recompile for nothing).
fn copy_headers() -> std::io::Result<()> {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    let generated = out.join("cxxbridge").join("include");
    // OUT_DIR is <profile>/build/<package>-<hash>/out.
    let profile = out
        .ancestors()
        .nth(3)
        .ok_or_else(|| std::io::Error::other(format!("OUT_DIR {} is too short", out.display())))?;
    let into = profile.join("cxxbridge");
    for header in ["cooperation-cpp/src/bridge.rs.h", "rust/cxx.h"] {
        copy_if_changed(&generated.join(header), &into.join(header))?;
    }
    Ok(())
}

fn copy_if_changed(from: &Path, to: &Path) -> std::io::Result<()> {
    // Read through the link cxx-build may have made.
    let contents = std::fs::read(from)?;
    if std::fs::read(to).ok().as_deref() == Some(contents.as_slice()) {
        return Ok(());
    }
    if let Some(folder) = to.parent() {
        std::fs::create_dir_all(folder)?;
    }
    // A link left at `to` is replaced by a file, not written through.
    let _ = std::fs::remove_file(to);
    std::fs::write(to, contents)
}
