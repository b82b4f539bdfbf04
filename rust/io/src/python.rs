//! Running one of sssbake's usd-core scripts in the Python named by
//! `$SSSBAKE_PYTHON` (default `python3`): the script goes in on standard
//! input, its answer comes back on standard output.

use std::ffi::OsStr;
use std::io::Write;
use std::process::{Command, Stdio};

/// Runs `script` with `args`; its standard output, or why it failed (the
/// last line the script printed to standard error, after "usd-core could
/// not `doing`", or why Python did not start).
pub fn run_script<I, S>(script: &str, args: I, doing: &str) -> Result<Vec<u8>, String>
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let python = std::env::var("SSSBAKE_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut child = Command::new(&python)
        .arg("-")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "USD needs Python with usd-core; `{python}` did not start ({e}); set SSSBAKE_PYTHON"
            )
        })?;
    // A Python that stops early (no usd-core) closes its input: what it
    // says on exit explains more than the broken pipe would.
    let fed = child
        .stdin
        .take()
        .map(|mut stdin| stdin.write_all(script.as_bytes()));
    let output = child
        .wait_with_output()
        .map_err(|e| format!("the usd-core script failed: {e}"))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let reason = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("no message");
        return Err(format!("usd-core could not {doing}: {reason}"));
    }
    if let Some(Err(e)) = fed {
        return Err(format!("cannot hand usd-core its script: {e}"));
    }
    Ok(output.stdout)
}
