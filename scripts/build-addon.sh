#!/usr/bin/env bash
# Packages the Blender extension: target/sssbake-<version>-<platform>.zip, installable
# with Blender's "Install from Disk" (Blender 4.2 or later). The add-on bakes through the
# sssbake Python package, which travels inside as its abi3 wheel (built here with
# maturin; `wheels` in the packaged manifest lists it, and Blender installs it), with the
# licenses and the notices of the third-party code compiled into it.
set -euo pipefail
cd "$(dirname "$0")/.."

# On Linux the wheel is linked against glibc 2.28 with zig (the `ziglang` package), not this
# machine's glibc: Blender's Linux builds need only 2.28, and studios run it on distributions
# that old (Rocky/RHEL 8 has 2.28, RHEL 9 2.34). maturin checks the library against the
# manylinux_2_28 policy and refuses a newer symbol.
case "$(uname -s)-$(uname -m)" in
    Linux-x86_64) platform=linux-x64 portable=(--zig --compatibility manylinux_2_28) ;;
    Linux-aarch64) platform=linux-arm64 portable=(--zig --compatibility manylinux_2_28) ;;
    Darwin-arm64) platform=macos-arm64 portable=() ;;
    Darwin-x86_64) platform=macos-x64 portable=() ;;
    *) echo "error: no packaging rule for $(uname -s)-$(uname -m)" >&2; exit 1 ;;
esac
[ -d .venv/bin ] && PATH="$PWD/.venv/bin:$PATH"
maturin=${MATURIN:-$(command -v maturin || echo .venv/bin/maturin)}
wheels=target/addon-wheels
rm -rf "$wheels"
"$maturin" build --release --locked --quiet ${portable[@]+"${portable[@]}"} -o "$wheels" >&2
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
