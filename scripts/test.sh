#!/usr/bin/env bash
# Installs what the tests need (first run only) and runs every check: style
# (rustfmt, clippy, ruff), the Rust workspace's tests, then the Python tests
# against the release binary and library and the Python package.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-test-deps.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --locked -- -D warnings
.venv/bin/ruff format --check --quiet tests usd examples blender_addon python scripts
.venv/bin/ruff check --quiet tests usd examples blender_addon python scripts
cargo build --release --locked -p sssbake-cli -p sssbake-ffi
# The Python package (pyproject.toml) into the venv, as the wheel the Blender extension carries:
# built once by maturin (scripts/build-addon.sh, linked for glibc 2.28), for the package's
# tests and the extension's, whose packaging then finds it built. `pip install .` would build
# the library a second time (its dependencies' features differ from the binary's: 3.6 minutes
# on two cores). Reinstalled whole: the version does not change from build to build.
scripts/build-addon.sh
.venv/bin/python -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps \
    target/addon-wheels/sssbake-*-abi3-*.whl
# The Rust tests build with the release profile, so they reuse the release build above
# (the test profile would build every dependency again, minutes on two cores); only the
# workspace's own crates are built again, the dev-dependencies changing shared features. Where the
# machine has cargo-nextest, the test binaries run side by side, not one after another:
# one binary's slowest test then no longer holds up the rest.
if command -v cargo-nextest >/dev/null; then
    cargo nextest run --workspace --release --locked --no-fail-fast
    cargo test --doc --workspace --release --locked
else
    cargo test --workspace --release --locked
fi
# Two test files at a time, each whole in one worker (its module fixtures made once): much of
# a test is one core's work (Blender, Python, a browser, a bake's serial stretches), which the
# other file's test overlaps. Two, not one per core: each worker holds its own bpy.
SSSBAKE_BIN="$PWD/target/release/sssbake" .venv/bin/python -m pytest tests -q -n 2 --dist loadfile --durations=15
