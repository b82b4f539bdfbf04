//! docs/cli.md's reference of every command and option is the one the
//! binary generates from its own definitions (`sssbake help-markdown`), so
//! the page cannot drift from the command line.

use std::path::Path;
use std::process::Command;

const BEGIN: &str = "<!-- BEGIN sssbake help-markdown: generated; SSSBAKE_UPDATE_DOCS=1 cargo test -p sssbake-cli --test docs_reference -->";
const END: &str = "<!-- END sssbake help-markdown -->";

#[test]
fn docs_cli_md_holds_the_binarys_own_reference() {
    let output = Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .arg("help-markdown")
        .output()
        .expect("sssbake runs");
    assert!(output.status.success(), "{output:?}");
    let generated = String::from_utf8(output.stdout).expect("the reference is UTF-8");

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md");
    let page = std::fs::read_to_string(&path).expect("docs/cli.md is readable");
    let (intro, rest) = page
        .split_once(BEGIN)
        .unwrap_or_else(|| panic!("docs/cli.md has no line\n{BEGIN}"));
    let (_, after) = rest
        .split_once(END)
        .unwrap_or_else(|| panic!("docs/cli.md has no line\n{END}"));
    let want = format!("{intro}{BEGIN}\n\n{generated}\n{END}{after}");
    if page == want {
        return;
    }
    if std::env::var_os("SSSBAKE_UPDATE_DOCS").is_some() {
        std::fs::write(&path, want).expect("docs/cli.md is writable");
        return;
    }
    panic!(
        "docs/cli.md's command reference differs from the command line's definitions; \
         rewrite it with\n    SSSBAKE_UPDATE_DOCS=1 cargo test -p sssbake-cli --test docs_reference"
    );
}
