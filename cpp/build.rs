//! Generates the C++ half of the bridge (`cooperation-cpp/src/bridge.rs.h` and `rust/cxx.h`,
//! under the target directory's `cxxbridge/`) and compiles it, with the lock annotations
//! (`lib/annotate.cpp`), into this crate's static library.

fn main() {
    cxx_build::bridge("src/bridge.rs")
        .file("lib/annotate.cpp")
        .include("include")
        .std("c++17")
        .compile("cooperation-cpp-bridge");
    println!("cargo:rerun-if-changed=src/bridge.rs");
    println!("cargo:rerun-if-changed=lib/annotate.cpp");
    println!("cargo:rerun-if-changed=include/cooperation/rtc/annotate.hpp");
}
