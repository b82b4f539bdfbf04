"""Results saved into a folder as a whole: each file is first written under a hidden
temporary name, then all are moved into place together, the files they replace kept
aside until the bake has succeeded, so a failure at any stage puts the folder back."""

import os

import bpy

from .binding import OutputError, SettingError


def resolve(folder):
    """The absolute path of the folder setting; `//` is relative to the saved .blend file,
    and refused while the file has never been saved (it would mean the process's folder)."""
    if folder.startswith("//") and not bpy.data.filepath:
        raise SettingError(
            f"the folder `{folder}` is relative to the .blend file (`//`), which is not saved yet: "
            "save the file first or choose an absolute folder",
        )
    return os.path.normpath(bpy.path.abspath(folder))


class Staging:
    """Files of one bake in `folder` (absolute): `path_for(name)` gives where to write a
    file first; `commit(changes)` moves them all into place; `finish()` drops the files
    they replaced; `discard()` removes what was written but not committed."""

    def __init__(self, folder):
        self.folder = folder
        self.names = []

    def prepare(self, changes):
        """Makes the folder (and its missing parents), recorded so a failure removes them."""
        missing = []
        path = self.folder
        while path and not os.path.isdir(path):
            missing.append(path)
            parent = os.path.dirname(path)
            if parent == path:
                break
            path = parent
        try:
            os.makedirs(self.folder, exist_ok=True)
        except OSError as error:
            raise OutputError(
                f"cannot make the folder {self.folder}: {error.strerror or error}", file=self.folder
            ) from error
        for made in missing:  # deepest first, so each is empty when its turn comes
            changes.record(lambda made=made: _remove_empty(made))

    def path_for(self, name):
        """Where file `name` is written before it is committed."""
        self.names.append(name)
        return os.path.join(self.folder, f".{name}.sssbake-new")

    def commit(self, changes):
        """Moves every written file into place, keeping any file it replaces aside."""
        for name in self.names:
            final = os.path.join(self.folder, name)
            kept = os.path.join(self.folder, f".{name}.sssbake-old")
            if os.path.exists(final):
                os.replace(final, kept)
                changes.record(lambda final=final, kept=kept: os.replace(kept, final))
            else:
                changes.record(lambda final=final: _remove_file(final))
            os.replace(os.path.join(self.folder, f".{name}.sssbake-new"), final)

    def finish(self):
        """Drops the replaced files: the bake succeeded."""
        for name in self.names:
            _remove_file(os.path.join(self.folder, f".{name}.sssbake-old"))

    def discard(self):
        """Removes files written but not committed."""
        for name in self.names:
            _remove_file(os.path.join(self.folder, f".{name}.sssbake-new"))


def _remove_file(path):
    if os.path.exists(path):
        os.remove(path)


def _remove_empty(path):
    if os.path.isdir(path) and not os.listdir(path):
        os.rmdir(path)
