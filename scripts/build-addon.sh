#!/usr/bin/env bash
# Packages the Blender extension: target/sssbake-<version>-<platform>.zip, installable
# with Blender's "Install from Disk" (Blender 4.2 or later). The add-on bakes through the
# sssbake Python package, which travels inside as its abi3 wheel (built here with
# maturin; `wheels` in the packaged manifest lists it, and Blender installs it), with the
# licenses and the notices of the third-party code compiled into it.
set -euo pipefail
cd "$(dirname "$0")/.."

case "$(uname -s)-$(uname -m)" in
    Linux-x86_64) platform=linux-x64 ;;
    Linux-aarch64) platform=linux-arm64 ;;
    Darwin-arm64) platform=macos-arm64 ;;
    Darwin-x86_64) platform=macos-x64 ;;
    *) echo "error: no packaging rule for $(uname -s)-$(uname -m)" >&2; exit 1 ;;
esac
maturin=${MATURIN:-$(command -v maturin || echo .venv/bin/maturin)}
wheels=target/addon-wheels
rm -rf "$wheels"
"$maturin" build --release --locked --quiet -o "$wheels" >&2
wheel=$(ls "$wheels"/sssbake-*-abi3-*.whl)
version=$(sed -n 's/^version = "\(.*\)"/\1/p' blender_addon/sssbake/blender_manifest.toml)
out="target/sssbake-$version-$platform.zip"
python3 - "$out" "$platform" "$wheel" <<'PY'
import pathlib, re, sys, zipfile
out, platform, wheel = sys.argv[1:]
source = pathlib.Path("blender_addon/sssbake")
wheel = pathlib.Path(wheel)
partial = pathlib.Path(out + ".partial")
with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
    for path in sorted(source.glob("*.py")):
        archive.write(path, path.name)
    manifest = (source / "blender_manifest.toml").read_text()
    listed = f'platforms = ["{platform}"]\nwheels = ["./wheels/{wheel.name}"]'
    manifest = re.sub(r'platforms = \[.*\]', listed, manifest)
    archive.writestr("blender_manifest.toml", manifest)
    archive.write(wheel, f"wheels/{wheel.name}")
    for notice in ("LICENSE-MIT", "LICENSE-APACHE", "THIRD-PARTY-NOTICES"):
        archive.write(notice, notice)
partial.replace(out)
print(f"wrote {out}")
PY
