"""One press of Bake: checked and prepared on the main thread (the scene sent to the
library, the `sssbake` UV map made), baked on any thread, and finished on the main thread
(files, images, Show in Material). Every change to the artist's scene is logged, so a
failure at any stage, or Esc, leaves the scene exactly as it was."""

import os
import threading

import bpy

from . import binding, changes, folder, images, report, scene_export, unwrap, wiring
from .binding import SettingError
from .properties import GIB, QUALITY_SAMPLES, advanced_settings


class Job:
    """One bake of the selected objects with `settings` (the panel's, or the operator's)."""

    def __init__(self, context, settings):
        self.settings = settings
        self.targets = _targets(context, settings)
        # Read here: the bakes may run on another thread, which must not touch Blender data.
        self.names = [o.name for o in self.targets]
        self.folder = folder.resolve(settings.folder) if settings.destination == "FOLDER" else None
        self.uv_map = unwrap.UV_MAP if settings.unwrap else settings.uv_map
        self.cancel = threading.Event()
        self.progress = 0.0
        self.current = ""
        self.results = []
        self.error = None
        self.scene = None
        self.changes = changes.Changes()
        self.unwrapped = set()
        self.unwrap_notes = []
        self.failures = []
        self.mode = EditorMode(context)
        self.options = _options(settings)
        try:
            self.mode.leave()
            # The objects whose `sssbake` map this bake made (the others keep theirs),
            # with what the artist should know about each new map.
            for obj in self.targets if settings.unwrap else ():
                made = unwrap.ensure_map(
                    context,
                    obj,
                    settings.unwrap_method,
                    settings.redo_unwrap,
                    settings.margin,
                    settings.resolution,
                    self.changes,
                )
                if made is not None:
                    self.unwrapped.add(obj.name)
                    self.unwrap_notes += [made] if made else []
            self.scene = scene_export.build_scene(context, self.uv_map)
            self.materials = [scene_export.materials_of(settings, o) for o in self.targets]
            self.colour_warnings = [w for o in self.targets for w in scene_export.material_notes(settings, o)]
        except BaseException:
            self.abandon(context)
            raise

    def run(self, progress_lines=None):
        """Bakes every target; may run on another thread (it touches no Blender data).
        `progress_lines`, when given, is told each object's progress to print it."""
        count = len(self.names)
        try:
            for i, (obj_name, material) in enumerate(zip(self.names, self.materials, strict=True)):
                self.current = obj_name

                def progress(fraction, _stage="", i=i, obj_name=obj_name):
                    self.progress = (i + min(max(fraction, 0.0), 1.0)) / count
                    if progress_lines is not None:
                        progress_lines(obj_name, fraction)

                self.results.append(
                    binding.bake(self.scene, obj_name, material, self.options, progress, self.cancel)
                )
        except Exception as error:  # noqa: BLE001 (the main thread reports it)
            self.error = error

    def finish(self, context):
        """Writes the files and makes the images (main thread). Returns the names of the
        images and one line per object, and what the artist should know. On failure the
        scene and the folder are put back before the error goes on."""
        made, lines, notes = [], [], self.unwrap_notes + self.colour_warnings
        staging = folder.Staging(self.folder) if self.folder else None
        try:
            planned = [_planned(result, name) for result, name in zip(self.results, self.names, strict=True)]
            outputs = [o for o in binding.outputs() if o.upper() in self.settings.outputs]
            if staging:
                staging.prepare(self.changes)
                for result, plan in zip(self.results, planned, strict=True):
                    for output in outputs:
                        result.write_exr(output, staging.path_for(f"{plan['file_stem']}_{output}.exr"))
                staging.commit(self.changes)
            for obj, result, plan in zip(self.targets, self.results, planned, strict=True):
                lines.append(report.object_line(plan))
                warning = plan["uvs"]["warning"]
                if warning:
                    notes.append(self._uv_note(obj, warning))
                diffuse = None
                for output in outputs:
                    name = images.image_name(obj.name, output)
                    if staging:
                        path = os.path.join(self.settings.folder, f"{plan['file_stem']}_{output}.exr")
                        image = images.store_file(name, output, path, result.resolution, self.changes)
                    else:
                        pixels = result.image(output).reshape(-1)
                        image = images.store_packed(name, output, pixels, result.resolution, self.changes)
                    made.append(image.name)
                    diffuse = image if output == "diffuse" else diffuse
                if self.settings.wire_material:
                    if diffuse is None:
                        notes.append(
                            f"{obj.name}: Show in Material shows the Diffuse output, which was not baked"
                        )
                    else:
                        uv_map = self.uv_map or obj.data.uv_layers.active.name
                        notes += wiring.show_in_material(
                            obj, diffuse, uv_map, self.settings.copy_shared_materials, self.changes
                        )
        except BaseException:
            if staging:
                staging.discard()
            self.abandon(context)
            raise
        self.changes.forget()
        if staging:
            staging.finish()
        self.mode.restore(context)
        self.close()
        return made, lines, notes

    def _uv_note(self, obj, warning):
        # The library speaks of an object's own UVs; say which map and what the artist can do.
        problems = warning.split(": ", 1)[-1]
        if self.settings.unwrap:
            remedy = (
                "it was just made; fix it in the UV Editor if those texels matter (later bakes keep it)"
                if obj.name in self.unwrapped
                else "it was kept from an earlier bake: fix it in the UV Editor, or tick Unwrap Again"
            )
            return f"{obj.name}: UV map `{unwrap.UV_MAP}` has {problems}; {remedy}"
        uv_map = self.uv_map or obj.data.uv_layers.active.name
        return f"{obj.name}: baked into UV map `{uv_map}` as it is ({problems}); tick Unwrap for a map of its own"

    def close(self):
        # The maps and the scene are the library's memory until dropped here.
        self.results = []
        self.scene = None

    def abandon(self, context):
        """Puts back everything the job changed and drops the library's data; returns the
        changes that could not be put back (empty when the scene is as it was)."""
        self.close()
        self.failures = self.changes.rollback()
        self.mode.restore(context)
        return self.failures


def _targets(context, settings):
    """The selected mesh objects that render, after checking the settings; nothing is
    changed before this passes."""
    selected = [o for o in context.selected_objects if o.type == "MESH"]
    # An object hidden from renders is neither baked nor a shadow caster.
    collections = scene_export.rendered_collections(context.view_layer)
    targets = [o for o in selected if scene_export.renders(o, collections)]
    if not selected:
        raise SettingError("select the mesh objects to bake")
    if not targets:
        raise SettingError("the selected objects are hidden from renders; nothing to bake")
    if not settings.outputs:
        raise SettingError("choose at least one output")
    if not 1 <= settings.resolution <= 16384:
        raise SettingError(f"resolution {settings.resolution} must be between 1 and 16384")
    if settings.destination == "FOLDER" and not settings.folder:
        raise SettingError("choose a folder for the results")
    if (
        settings.material_source == "LAYERS"
        and settings.layers_file.startswith("//")
        and not bpy.data.filepath
    ):
        raise SettingError(
            f"the layers file `{settings.layers_file}` is relative to the .blend file (`//`), which is "
            "not saved yet: save the file first or choose an absolute path",
        )
    if not settings.unwrap:
        for obj in targets:
            layers = obj.data.uv_layers
            if (layers.get(settings.uv_map) if settings.uv_map else layers.active) is None:
                missing = f"UV map `{settings.uv_map}`" if settings.uv_map else "UV map"
                raise SettingError(
                    f"object `{obj.name}`: has no {missing}; choose one, or tick Unwrap",
                )
    return targets


def _options(settings):
    """The bake's options (`sssbake.bake`'s names) for the panel's settings; the object's
    own UVs are kept as they are (the add-on made the `sssbake` map when asked)."""
    return {
        "resolution": settings.resolution,
        "method": settings.method.lower(),
        "margin": settings.margin,
        "light_samples": QUALITY_SAMPLES[settings.quality],
        "outputs": [o for o in binding.outputs() if o.upper() in settings.outputs],
        "max_memory": str(round(settings.max_memory * GIB)),
        "uvs": "keep",
        **{s["name"]: _value(s, getattr(settings, s["name"])) for s in advanced_settings(binding.settings())},
    }


def _value(setting, value):
    """A panel value as the library takes it: a choice's name in its own case, a number
    to the seven digits a Blender float holds (0.01, not 0.0099999998)."""
    if setting["kind"] == "choice":
        return value.lower()
    return float(f"{value:.7g}") if setting["kind"] == "number" else value


def _planned(result, name):
    summary = result.summary
    return next((o for o in summary["objects"] if o["name"] == name), summary["objects"][0])


class EditorMode:
    """The mode the artist was in (Edit Mode and the objects in it, or another mode of the
    active object): left for Object Mode while the bake reads the meshes, entered again
    after, whatever the outcome."""

    def __init__(self, context):
        active = context.view_layer.objects.active
        self.active = active.name if active is not None else None
        self.mode = active.mode if active is not None else "OBJECT"
        self.objects = [o.name for o in context.view_layer.objects if o.mode == self.mode]
        self.left = False

    def leave(self):
        if self.mode != "OBJECT":
            # Leaving Edit Mode writes the edit mesh back, so the bake sees the latest edits.
            bpy.ops.object.mode_set(mode="OBJECT")
            self.left = True

    def restore(self, context):
        if not self.left:
            return
        self.left = False
        active = bpy.data.objects.get(self.active)
        objects = [bpy.data.objects[n] for n in self.objects if n in bpy.data.objects]
        if active is None:
            return
        with context.temp_override(
            active_object=active, object=active, selected_objects=objects, selected_editable_objects=objects
        ):
            bpy.ops.object.mode_set(mode=self.mode)
