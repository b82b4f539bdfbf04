"""The sssbake library through ctypes: loading it, checking its ABI version, and the
structures and calls of `rust/ffi/include/sssbake.h`, wrapped for Python."""

import ctypes
import os
import pathlib
import sys

ABI_VERSION = 7

LIGHT_SUN, LIGHT_POINT, LIGHT_SPOT, LIGHT_RECTANGLE, LIGHT_DISK = range(5)
MATERIAL_PRESET, MATERIAL_PRINCIPLED, MATERIAL_TOML, MATERIAL_SCENE, MATERIAL_SIDECAR, MATERIAL_NONE = range(
    6
)
# Blender's Image Texture extension in the library's numbering (SSSBAKE_EXTENSION_*).
EXTENSIONS = {"REPEAT": 0, "EXTEND": 1, "CLIP": 2, "MIRROR": 3}
# Blender's subsurface_method enum in the library's numbering (SSSBAKE_SUBSURFACE_*).
SUBSURFACE_METHODS = {"BURLEY": 0, "RANDOM_WALK": 1, "RANDOM_WALK_SKIN": 2}
ALBEDO_CYCLES, ALBEDO_PHYSICAL = range(2)
NAMES_OUTPUTS, NAMES_METHODS, NAMES_PRESETS = range(3)
STATUS = {1: "invalid argument", 2: "bad input", 3: "cancelled", 4: "internal error", 5: "cannot write"}
INVALID_ARGUMENT, BAD_INPUT, CANCELLED, INTERNAL, CANNOT_WRITE = range(1, 6)


class NativeError(Exception):
    """A call into the library failed; `status` is its SssbakeStatus."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


Vec3 = ctypes.c_float * 3


class Mesh(ctypes.Structure):
    _fields_ = [
        ("name", ctypes.c_char_p),
        ("positions", ctypes.POINTER(ctypes.c_float)),
        ("normals", ctypes.POINTER(ctypes.c_float)),
        ("uvs", ctypes.POINTER(ctypes.c_float)),
        ("vertex_count", ctypes.c_size_t),
        ("indices", ctypes.POINTER(ctypes.c_uint32)),
        ("index_count", ctypes.c_size_t),
        ("material_indices", ctypes.POINTER(ctypes.c_uint32)),
        ("texture_uvs", ctypes.POINTER(ctypes.c_float)),
        ("texture_uv_count", ctypes.c_size_t),
    ]


class Light(ctypes.Structure):
    _fields_ = [
        ("kind", ctypes.c_uint32),
        ("colour", Vec3),
        ("power", ctypes.c_float),
        ("position", Vec3),
        ("direction", Vec3),
        ("tangent", Vec3),
        ("size", ctypes.c_float),
        ("size_y", ctypes.c_float),
        ("angle", ctypes.c_float),
        ("spot_size", ctypes.c_float),
        ("spot_blend", ctypes.c_float),
        ("exposure", ctypes.c_float),
        ("temperature_colour", Vec3),
        ("diffuse_factor", ctypes.c_float),
        ("spread", ctypes.c_float),
        ("normalize", ctypes.c_uint32),
        ("casts_shadow", ctypes.c_uint32),
    ]


class Material(ctypes.Structure):
    _fields_ = [
        ("kind", ctypes.c_uint32),
        ("name", ctypes.c_char_p),
        ("toml", ctypes.c_char_p),
        ("base_colour", Vec3),
        ("subsurface_weight", ctypes.c_float),
        ("radius", Vec3),
        ("scale", ctypes.c_float),
        ("ior", ctypes.c_float),
        ("anisotropy", ctypes.c_float),
        ("subsurface_method", ctypes.c_uint32),
        ("subsurface_ior", ctypes.c_float),
        ("specular_ior_level", ctypes.c_float),
        ("albedo_mapping", ctypes.c_uint32),
        ("image_pixels", ctypes.POINTER(ctypes.c_float)),
        ("image_width", ctypes.c_uint32),
        ("image_height", ctypes.c_uint32),
        ("image_channels", ctypes.c_uint32),
        ("image_uv_set", ctypes.c_uint32),
        ("image_extension", ctypes.c_uint32),
        ("image_nearest", ctypes.c_uint32),
        ("image_name", ctypes.c_char_p),
        ("roughness", ctypes.c_float),
    ]


class Settings(ctypes.Structure):
    _fields_ = [
        ("resolution", ctypes.c_uint32),
        ("method", ctypes.c_uint32),
        ("margin", ctypes.c_uint32),
        ("light_samples", ctypes.c_uint32),
        ("seed", ctypes.c_uint64),
        ("octree_epsilon", ctypes.c_float),
        ("gaussians", ctypes.c_uint32),
        ("samples", ctypes.c_uint32),
        ("outputs", ctypes.c_uint32),
        ("tolerance", ctypes.c_float),
        ("max_memory_bytes", ctypes.c_uint64),
        ("max_evaluations", ctypes.c_double),
    ]


PROGRESS = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_float)


def library_path():
    """$SSSBAKE_LIBRARY, else the library packaged beside this file."""
    override = os.environ.get("SSSBAKE_LIBRARY")
    if override:
        return pathlib.Path(override)
    name = {"win32": "sssbake.dll", "darwin": "libsssbake.dylib"}.get(sys.platform, "libsssbake.so")
    return pathlib.Path(__file__).resolve().parent / "lib" / name


_library = None


def library():
    """The loaded library; raises NativeError when it is missing or of another version."""
    global _library
    if _library is not None:
        return _library
    path = library_path()
    if not path.exists():
        raise NativeError(0, f"the sssbake library is missing: {path} (build it with scripts/build-addon.sh)")
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as error:
        raise NativeError(0, f"cannot load the sssbake library {path}: {error}") from error
    lib.sssbake_abi_version.restype = ctypes.c_uint32
    version = lib.sssbake_abi_version()
    if version != ABI_VERSION:
        raise NativeError(
            0,
            f"the sssbake library {path} speaks ABI version {version}, but this add-on needs "
            f"{ABI_VERSION}: install the add-on and library of one release",
        )
    status = ctypes.c_int
    lib.sssbake_last_error.restype = ctypes.c_char_p
    lib.sssbake_scene_new.argtypes = [ctypes.c_double, ctypes.POINTER(ctypes.c_void_p)]
    lib.sssbake_scene_new.restype = status
    lib.sssbake_scene_free.argtypes = [ctypes.c_void_p]
    lib.sssbake_scene_free.restype = status
    lib.sssbake_scene_add_mesh.argtypes = [ctypes.c_void_p, ctypes.POINTER(Mesh)]
    lib.sssbake_scene_add_mesh.restype = status
    lib.sssbake_scene_add_light.argtypes = [ctypes.c_void_p, ctypes.POINTER(Light)]
    lib.sssbake_scene_add_light.restype = status
    lib.sssbake_scene_set_world.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_float), ctypes.c_float]
    lib.sssbake_scene_set_world.restype = status
    lib.sssbake_settings_default.argtypes = [ctypes.POINTER(Settings)]
    lib.sssbake_settings_default.restype = status
    lib.sssbake_bake.argtypes = [
        ctypes.c_void_p,
        ctypes.c_char_p,
        ctypes.POINTER(Material),
        ctypes.POINTER(Settings),
        PROGRESS,
        ctypes.c_void_p,
        ctypes.POINTER(ctypes.c_int32),
        ctypes.POINTER(ctypes.c_void_p),
    ]
    lib.sssbake_bake.restype = status
    lib.sssbake_bake_materials.argtypes = [
        ctypes.c_void_p,
        ctypes.c_char_p,
        ctypes.POINTER(Material),
        ctypes.c_size_t,
        ctypes.POINTER(Settings),
        PROGRESS,
        ctypes.c_void_p,
        ctypes.POINTER(ctypes.c_int32),
        ctypes.POINTER(ctypes.c_void_p),
    ]
    lib.sssbake_bake_materials.restype = status
    lib.sssbake_result_free.argtypes = [ctypes.c_void_p]
    lib.sssbake_result_free.restype = status
    lib.sssbake_result_resolution.argtypes = [ctypes.c_void_p]
    lib.sssbake_result_resolution.restype = ctypes.c_uint32
    lib.sssbake_result_summary.argtypes = [ctypes.c_void_p]
    lib.sssbake_result_summary.restype = ctypes.c_char_p
    lib.sssbake_result_image.argtypes = [
        ctypes.c_void_p,
        ctypes.c_uint32,
        ctypes.POINTER(ctypes.c_float),
        ctypes.c_size_t,
    ]
    lib.sssbake_result_image.restype = status
    lib.sssbake_result_write_exr.argtypes = [
        ctypes.c_void_p,
        ctypes.c_uint32,
        ctypes.c_char_p,
        ctypes.c_uint32,
    ]
    lib.sssbake_result_write_exr.restype = status
    lib.sssbake_unwrap.argtypes = [
        ctypes.POINTER(Mesh),
        ctypes.c_uint32,
        ctypes.c_uint32,
        ctypes.POINTER(ctypes.c_float),
        ctypes.c_size_t,
        ctypes.POINTER(ctypes.c_uint32),
    ]
    lib.sssbake_unwrap.restype = status
    lib.sssbake_names.argtypes = [ctypes.c_uint32, ctypes.POINTER(ctypes.c_void_p)]
    lib.sssbake_names.restype = status
    lib.sssbake_string_free.argtypes = [ctypes.c_void_p]
    lib.sssbake_string_free.restype = status
    _names.clear()
    _library = lib
    return lib


_names = {}


def names(kind):
    """The library's name table of `kind` (NAMES_*), parsed from its JSON; read once."""
    if kind not in _names:
        import json

        text = ctypes.c_void_p()
        check(library().sssbake_names(kind, ctypes.byref(text)))
        try:
            _names[kind] = json.loads(ctypes.string_at(text).decode("utf-8"))
        finally:
            check(library().sssbake_string_free(text))
    return _names[kind]


def outputs():
    """The outputs' names in the order of their numbers (bit i of Settings.outputs)."""
    return tuple(names(NAMES_OUTPUTS))


def methods():
    """The methods' names in the order of Settings.method."""
    return tuple(names(NAMES_METHODS))


def presets():
    """The presets as (name, description) pairs."""
    return tuple((p["name"], p["description"]) for p in names(NAMES_PRESETS))


def __getattr__(name):
    # OUTPUTS and METHODS are read from the library when first used, not at import, so
    # the add-on imports (and reports a missing library) without it.
    if name == "OUTPUTS":
        return outputs()
    if name == "METHODS":
        return methods()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def check(status):
    """Raises NativeError with the library's message unless `status` is OK."""
    if status != 0:
        message = (library().sssbake_last_error() or b"").decode("utf-8", "replace")
        raise NativeError(status, message or STATUS.get(status, f"status {status}"))


def floats(array):
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_float))


class Scene:
    """A scene in the library; free it with close() (or use `with`)."""

    def __init__(self, millimetres_per_unit):
        self.handle = ctypes.c_void_p()
        check(library().sssbake_scene_new(millimetres_per_unit, ctypes.byref(self.handle)))

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()

    def close(self):
        if self.handle:
            handle, self.handle = self.handle, ctypes.c_void_p()
            check(library().sssbake_scene_free(handle))

    def add_mesh(self, name, positions, normals, uvs, indices, material_indices=None, texture_uvs=()):
        """Flat float32 arrays (3 per vertex; normals and uvs may be None), uint32 indices,
        optionally a uint32 material index per triangle and further float32 UV sets (2 per
        vertex each) that base-colour images read as UV sets 1, 2, ..."""
        import numpy as np

        extra = np.ascontiguousarray(np.concatenate(texture_uvs), dtype=np.float32) if texture_uvs else None
        if material_indices is not None:
            material_indices = np.ascontiguousarray(material_indices, dtype=np.uint32)
        mesh = Mesh(
            name.encode("utf-8"),
            floats(positions),
            floats(normals) if normals is not None else None,
            floats(uvs) if uvs is not None else None,
            len(positions) // 3,
            indices.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
            len(indices),
            None
            if material_indices is None
            else material_indices.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
            None if extra is None else floats(extra),
            len(texture_uvs),
        )
        check(library().sssbake_scene_add_mesh(self.handle, ctypes.byref(mesh)))

    def add_light(self, light):
        check(library().sssbake_scene_add_light(self.handle, ctypes.byref(light)))

    def set_world(self, colour, strength):
        check(library().sssbake_scene_set_world(self.handle, Vec3(*colour), strength))


def unwrap(name, positions, indices, resolution, padding):
    """UVs from the library's xatlas for a mesh of flat float32 `positions` and uint32
    `indices`: charts for a `resolution`² map, `padding` texels apart. Returns the UVs
    (2 floats per index) and each triangle's chart number."""
    import numpy as np

    uvs = np.empty(2 * len(indices), dtype=np.float32)
    charts = np.empty(len(indices) // 3, dtype=np.uint32)
    mesh = Mesh(
        name.encode("utf-8"),
        floats(positions),
        None,
        None,
        len(positions) // 3,
        indices.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
        len(indices),
    )
    check(
        library().sssbake_unwrap(
            ctypes.byref(mesh),
            resolution,
            padding,
            floats(uvs),
            uvs.size,
            charts.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
        )
    )
    return uvs, charts


def default_settings():
    settings = Settings()
    check(library().sssbake_settings_default(ctypes.byref(settings)))
    return settings


class Result:
    """One object's bake; its maps come out as float32 RGBA arrays, rows from v = 0 up."""

    def __init__(self, handle):
        self.handle = handle

    def close(self):
        if self.handle:
            handle, self.handle = self.handle, None
            check(library().sssbake_result_free(handle))

    @property
    def resolution(self):
        return library().sssbake_result_resolution(self.handle)

    @property
    def summary(self):
        import json

        return json.loads(library().sssbake_result_summary(self.handle).decode("utf-8"))

    def image(self, output):
        import numpy as np

        n = self.resolution
        pixels = np.empty(4 * n * n, dtype=np.float32)
        check(
            library().sssbake_result_image(self.handle, outputs().index(output), floats(pixels), pixels.size)
        )
        return pixels

    def write_exr(self, output, path):
        """Writes the map as a linear 32-bit OpenEXR file, whole or not at all."""
        check(
            library().sssbake_result_write_exr(
                self.handle, outputs().index(output), str(path).encode("utf-8"), 0
            )
        )


def bake(scene, obj, material, settings, cancel, progress=None):
    """Bakes object `obj` with `material`, or with a list of materials that its faces'
    material indices choose from; `cancel` is a ctypes.c_int32 another thread may set to 1;
    `progress(fraction)` is called from a library thread."""
    materials = list(material) if isinstance(material, (list, tuple)) else [material]
    array = (Material * len(materials))(*materials)
    callback = PROGRESS(
        (lambda _user, fraction: progress(fraction)) if progress else (lambda _user, _fraction: None)
    )
    handle = ctypes.c_void_p()
    check(
        library().sssbake_bake_materials(
            scene.handle,
            obj.encode("utf-8"),
            array,
            len(materials),
            ctypes.byref(settings),
            callback,
            None,
            ctypes.byref(cancel),
            ctypes.byref(handle),
        )
    )
    return Result(handle)
