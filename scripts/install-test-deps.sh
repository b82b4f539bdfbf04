#!/usr/bin/env bash
# Installs what the tests need, once: the Debian libraries bpy loads when
# headless, and a repository-local Python venv (.venv) with the pinned
# packages of tests/requirements.txt. Re-running reuses what is there.
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

# The Khronos glTF validator, from the npm registry, into .node/ (git-ignored).
validator_version=2.0.0-dev.3.10
if [ ! -f .node/node_modules/gltf-validator/package.json ] ||
    ! grep -q "\"version\": \"$validator_version\"" .node/node_modules/gltf-validator/package.json; then
    command -v npm >/dev/null || { echo "error: the glTF validator needs Node.js and npm" >&2; exit 1; }
    echo "installing gltf-validator $validator_version into .node"
    npm install --silent --no-audit --no-fund --prefix .node "gltf-validator@$validator_version" >/dev/null
fi
