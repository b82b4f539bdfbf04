//! Compiles the C shim through which the unwrap calls xatlas (built by the
//! xatlas-rs crate from its own sources; nothing is downloaded).

fn main() {
    println!("cargo:rerun-if-changed=cpp/xatlas_shim.cpp");
    cc::Build::new()
        .cpp(true)
        .file("cpp/xatlas_shim.cpp")
        .flag_if_supported("-std=c++11")
        .warnings(true)
        .compile("sssbake_xatlas_shim");
}
