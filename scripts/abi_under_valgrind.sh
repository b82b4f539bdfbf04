#!/usr/bin/env bash
# Runs the C ABI's tests (misuse, hostile arrays, cancellation, bakes) under Valgrind's
# memcheck: any invalid read or write, use of uninitialised memory or definite leak across
# the boundary fails the run. Miri and the sanitizers need a nightly toolchain; Valgrind
# checks the stable build as it ships. Takes a few minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "error: valgrind is not installed" >&2; exit 1; }
for test in abi folder; do
    binary=$(cargo test --release --locked -p sssbake-ffi --test "$test" --no-run --message-format=json 2>/dev/null |
        .venv/bin/python -c 'import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["kind"] == ["test"]:
        print(m["executable"])')
    valgrind --quiet --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite \
        "$binary" --test-threads 1
done
