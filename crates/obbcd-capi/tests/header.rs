//! include/obbcd.h is what cbindgen makes of the sources (as rtl-out/ is what gen-rtl emits),
//! and it compiles as C and as C++.

mod common;

use std::path::Path;

#[test]
fn header_is_generated_from_the_sources() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut builder = cbindgen::Builder::new().with_config(config);
    for file in ["lib.rs", "types.rs"] {
        builder = builder.with_src(dir.join("src").join(file));
    }
    let mut fresh = Vec::new();
    builder
        .generate()
        .expect("cbindgen cannot read the sources")
        .write(&mut fresh);
    let path = dir.join("include/obbcd.h");
    if std::env::var_os("OBBCD_WRITE_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("cannot write include/obbcd.h");
    }
    let committed = std::fs::read(&path).expect("include/obbcd.h is missing");
    assert!(
        committed == fresh,
        "include/obbcd.h is not what cbindgen makes of src/: regenerate it with \
         OBBCD_WRITE_HEADER=1 cargo test -p obbcd-capi --test header"
    );
}

#[test]
fn header_compiles_as_c_and_cpp() {
    let header = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/obbcd.h");
    for (compiler, lang) in [("cc", "c"), ("c++", "c++")] {
        common::run(
            std::process::Command::new(compiler)
                .args(["-Wall", "-Wextra", "-Werror", "-fsyntax-only", "-x", lang])
                .arg(&header),
        );
    }
}
