//! Gives the shared library (the cdylib) its SONAME on ELF platforms: `libmeshmove.so.0.2` for
//! the 0.x versions, whose every minor version may change the ABI, `libmeshmove.so.N` from
//! 1.0 on. CMake installs the file as `libmeshmove.so.<version>` with the `libmeshmove.so.0.2`
//! and `libmeshmove.so` links (CMakeLists.txt).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let elf = ["linux", "android", "freebsd", "netbsd", "openbsd", "dragonfly", "solaris", "illumos"];
    if !elf.contains(&os.as_str()) {
        return;
    }
    // Compile-time: a version bump rebuilds (and so reruns) this script.
    let (major, minor) = (env!("CARGO_PKG_VERSION_MAJOR"), env!("CARGO_PKG_VERSION_MINOR"));
    let soname = if major == "0" { format!("libmeshmove.so.0.{minor}") } else { format!("libmeshmove.so.{major}") };
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,{soname}");
}
