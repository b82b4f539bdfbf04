#!/usr/bin/env bash
# Installs what the tests need, once: the Debian libraries bpy loads when
# headless and Debian's Chromium, a repository-local Python venv (.venv) with
# the pinned packages of tests/requirements.txt, and the pinned Node.js
# packages of tests/node into .node. Re-running reuses what is there.
set -euo pipefail
cd "$(dirname "$0")/.."

bpy_libraries=(libx11-6 libxrender1 libxi6 libxfixes3 libxext6 libxkbcommon0 libsm6 libice6 libxt6 libgl1)
missing=()
for package in "${bpy_libraries[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "ok installed" || missing+=("$package")
done
if ((${#missing[@]})); then
    echo "installing Debian libraries for headless bpy: ${missing[*]}"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

python="${PYTHON:-python3.11}"
command -v "$python" >/dev/null || python=python3
if ! "$python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
    echo "error: bpy 5.0 needs CPython 3.11; $python is $("$python" --version 2>&1). Set PYTHON=/path/to/python3.11." >&2
    exit 1
fi
[ -x .venv/bin/python ] || "$python" -m venv .venv

stamp=.venv/.requirements.sha256
wanted=$(sha256sum tests/requirements.txt | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null)" != "$wanted" ]; then
    echo "installing Python test packages into .venv (bpy is about 375 MB)"
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt
    echo "$wanted" > "$stamp"
fi

# Chromium, from Debian's packages, for the web viewers' check (tests/test_web_viewers.py).
if ! command -v chromium >/dev/null; then
    echo "installing Debian's Chromium for the web viewers' check"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi

# From the npm registry, into .node/ (git-ignored), as tests/node/package-lock.json pins them:
# the Khronos glTF validator, three.js, model-viewer and playwright-core (which drives Chromium).
command -v npm >/dev/null || { echo "error: the glTF validator and the web viewers need Node.js and npm" >&2; exit 1; }
node_stamp=.node/.package-lock.sha256
node_wanted=$(cat tests/node/package.json tests/node/package-lock.json | sha256sum | cut -d' ' -f1)
if [ "$(cat "$node_stamp" 2>/dev/null)" != "$node_wanted" ]; then
    echo "installing the Node.js test packages into .node"
    mkdir -p .node
    cp tests/node/package.json tests/node/package-lock.json .node/
    (cd .node && npm ci --silent --no-audit --no-fund >/dev/null)
    echo "$node_wanted" > "$node_stamp"
fi
