"""A bake killed at any moment leaves the previous outputs as they were (or, once it has
put them in place, all of the new ones): never a mix, never a partial file under an output's
name. What a killed process could not remove, its hidden temporary names, the next bake into
the folder removes."""

import resource
import shutil
import signal
import subprocess
import time

import pytest
from conftest import ROOT, run

SCENE = ROOT / "examples" / "head" / "head.gltf"


def outputs(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if not p.name.startswith(".")}


def hidden(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


@pytest.fixture(scope="module")
def whole(sssbake, tmp_path_factory):
    """The 256² bake the tests kill, run whole once: its maps and how long it took (s)."""
    out = tmp_path_factory.mktemp("whole") / "maps"
    start = time.monotonic()
    assert run(sssbake, "bake", str(SCENE), "--out", str(out), "--resolution", "256").returncode == 0
    return outputs(out), time.monotonic() - start


@pytest.mark.parametrize("share", [0.5, 0.9, 0.98])
def test_a_killed_bake_leaves_the_old_maps_or_the_new_and_the_next_removes_its_leftovers(
    sssbake, tmp_path, whole, share
):
    """Killed at a share of a whole bake's time, late shares landing while it writes (when
    the kill lands is up to the machine; what must hold, holds at any moment). Removing a
    killed bake's hidden names is checked deterministically in `rust/io/src/staging.rs`."""
    out = tmp_path / "maps"
    bake = ["bake", str(SCENE), "--out", str(out), "--force"]
    assert run(sssbake, *bake, "--resolution", "64").returncode == 0
    before = outputs(out)
    new, seconds = whole
    process = subprocess.Popen([str(sssbake), *bake, "--resolution", "256"], stderr=subprocess.DEVNULL)
    time.sleep(share * seconds)
    process.send_signal(signal.SIGKILL)
    process.wait()
    now = outputs(out)
    assert now in (before, new), "a mix of old and new maps, or a partial one"
    # The next bake puts its maps in place and removes what the killed one left.
    assert run(sssbake, *bake, "--resolution", "64").returncode == 0
    assert outputs(out) == before
    assert hidden(out) == []


def test_a_disk_that_fills_mid_write_leaves_the_old_maps_and_nothing_hidden(sssbake, tmp_path):
    """A file-size limit (RLIMIT_FSIZE) makes the writes past it fail as a full disk does
    (EFBIG for ENOSPC): the small maps fit, the large ones do not."""
    out = tmp_path / "maps"
    bake = [str(sssbake), "bake", str(SCENE), "--out", str(out), "--force"]
    assert subprocess.run([*bake, "--resolution", "32"], check=False, capture_output=True).returncode == 0
    before = outputs(out)

    def small_disk():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (64 << 10, 64 << 10))

    result = subprocess.run(
        [*bake, "--resolution", "512"], check=False, capture_output=True, text=True, preexec_fn=small_disk
    )
    assert result.returncode == 3, result.stderr
    assert "cannot write" in result.stderr and str(out) in result.stderr
    assert outputs(out) == before
    assert hidden(out) == []


@pytest.mark.parametrize("share", [0.3, 0.9])
def test_an_output_folder_removed_mid_bake_is_an_output_error_not_a_crash(sssbake, tmp_path, whole, share):
    out = tmp_path / "maps"
    bake = [str(sssbake), "bake", str(SCENE), "--out", str(out), "--resolution", "256"]
    reference, seconds = whole
    process = subprocess.Popen(bake, stderr=subprocess.PIPE, text=True)
    time.sleep(share * seconds)
    shutil.rmtree(out, ignore_errors=True)
    _, stderr = process.communicate(timeout=300)
    # Removed before the maps were staged, the bake makes the folder again; after, it cannot
    # put them in place and says where.
    assert process.returncode in (0, 3), stderr
    if process.returncode == 3:
        assert str(out) in stderr and "panicked" not in stderr
    elif out.exists():
        # (Gone altogether when removed after the bake put its maps in place.)
        assert outputs(out) == reference
    if out.exists():
        assert hidden(out) == []
