#!/usr/bin/env bash
# Builds the native library and packages the Blender extension:
# target/sssbake-<version>-<platform>.zip, installable with Blender's
# "Install from Disk" (Blender 4.2 or later), with the licenses and the
# notices of the third-party code compiled into the library.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release -p sssbake-ffi
case "$(uname -s)-$(uname -m)" in
    Linux-x86_64) platform=linux-x64 library=libsssbake_ffi.so packaged=libsssbake.so ;;
    Linux-aarch64) platform=linux-arm64 library=libsssbake_ffi.so packaged=libsssbake.so ;;
    Darwin-arm64) platform=macos-arm64 library=libsssbake_ffi.dylib packaged=libsssbake.dylib ;;
    Darwin-x86_64) platform=macos-x64 library=libsssbake_ffi.dylib packaged=libsssbake.dylib ;;
    *) echo "error: no packaging rule for $(uname -s)-$(uname -m)" >&2; exit 1 ;;
esac
version=$(sed -n 's/^version = "\(.*\)"/\1/p' blender_addon/sssbake/blender_manifest.toml)
out="target/sssbake-$version-$platform.zip"
python3 - "$out" "$platform" "target/release/$library" "$packaged" <<'PY'
import pathlib, re, sys, zipfile
out, platform, library, packaged = sys.argv[1:]
source = pathlib.Path("blender_addon/sssbake")
partial = pathlib.Path(out + ".partial")
with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
    for path in sorted(source.glob("*.py")):
        archive.write(path, path.name)
    manifest = (source / "blender_manifest.toml").read_text()
    manifest = re.sub(r'platforms = \[.*\]', f'platforms = ["{platform}"]', manifest)
    archive.writestr("blender_manifest.toml", manifest)
    archive.write(library, f"lib/{packaged}")
    for notice in ("LICENSE-MIT", "LICENSE-APACHE", "THIRD-PARTY-NOTICES"):
        archive.write(notice, notice)
partial.replace(out)
print(f"wrote {out}")
PY
