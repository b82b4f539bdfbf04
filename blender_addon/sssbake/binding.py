"""The sssbake Python package as the add-on uses it. Blender installs it from the wheel
this extension lists in blender_manifest.toml (`wheels`), so `import sssbake` here is the
package, not this add-on (which Blender loads as `bl_ext.<repository>.sssbake`). The add-on
imports without it and says so when a bake needs it; a package of another release is
refused."""

import functools
import pathlib
import tomllib

try:
    import sssbake as _package
    from sssbake.errors import Cancelled, Error, InputError, OutputError, SettingError
except ImportError as _error:
    _package, _missing = None, _error

    class Error(Exception):
        """Something sssbake could not do."""

    class Cancelled(Error):
        """The bake stopped because it was asked to."""

    class InputError(Error):
        """Input the bake cannot use."""

    class OutputError(Error):
        """An output that cannot be written."""

    class SettingError(Error):
        """A setting out of its range."""


__all__ = ["Cancelled", "Error", "InputError", "OutputError", "SettingError", "package"]

VERSION = tomllib.loads((pathlib.Path(__file__).parent / "blender_manifest.toml").read_text())["version"]


def package():
    """The sssbake package; raises Error when it is missing or of another release."""
    if _package is None:
        raise Error(
            f"the sssbake package is missing ({_missing}): install the extension built by "
            "scripts/build-addon.sh, which carries it as a wheel"
        )
    if _package.__version__ != VERSION:
        raise Error(
            f"the sssbake package {_package.__file__} is version {_package.__version__}, but this "
            f"add-on is {VERSION}: install the add-on and package of one release"
        )
    return _package


@functools.cache
def defaults():
    """The library's defaults and names (`sssbake.defaults()`), read once."""
    return package().defaults()


@functools.cache
def settings():
    """Every bake setting of the library (`sssbake.settings()`) by name, read once."""
    return {setting["name"]: setting for setting in package().settings()}


def outputs():
    """The outputs' names in the library's order."""
    return tuple(defaults()["all_outputs"])


def presets():
    """The presets a bake can use, as (name, description) pairs."""
    return tuple((name, description) for name, description in defaults()["presets"])


# The package names a work limit it refuses by its keyword argument ("raise the limit (the
# max_memory argument)"); the artist raises it with the panel's setting, so say that one.
LIMIT_SETTINGS = {"max_memory": "the Memory Limit (GiB) of the sssbake panel"}


def bake(scene, name, materials, options, progress, cancel):
    """Bakes object `name` of `scene` (an `sssbake.Scene`) with `materials` and `options`:
    the one call into the library that bakes (`sssbake.Scene.bake_object`)."""
    try:
        return scene.bake_object(name, materials, progress=progress, cancel=cancel, **options)
    except SettingError as error:
        setting = LIMIT_SETTINGS.get(error.field)
        if setting is None:
            raise
        message = error.message.replace(f"(the {error.field} argument)", f"({setting})")
        raise SettingError(message, field=error.field) from error
