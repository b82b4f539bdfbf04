"""The bake operator: modal with progress in the status bar and Esc to cancel when run
from the interface, synchronous in background mode and when called from a script."""

import ctypes
import threading
import types

import bpy

from . import images, native, scene_export
from .properties import QUALITY_SAMPLES, SETTING_NAMES, bake_properties

_running = []


def cancel_running():
    """Asks every bake in progress to stop (Esc does this for the modal one)."""
    for job in _running:
        job.cancel.value = 1


class Job:
    """One press of Bake: the native scene and materials made on the main thread, the
    bakes run on any thread, and the images made on the main thread at the end."""

    def __init__(self, context, settings):
        self.settings = settings
        selected = [o for o in context.selected_objects if o.type == "MESH"]
        # An object hidden from renders is neither baked nor a shadow caster.
        collections = scene_export.rendered_collections(context.view_layer)
        self.targets = [o for o in selected if scene_export.renders(o, collections)]
        # Read here: the bakes may run on another thread, which must not touch Blender data.
        self.names = [o.name for o in self.targets]
        if not selected:
            raise native.NativeError(1, "select the mesh objects to bake")
        if not self.targets:
            raise native.NativeError(1, "the selected objects are hidden from renders; nothing to bake")
        if not settings.outputs:
            raise native.NativeError(1, "choose at least one output")
        if not 1 <= settings.resolution <= 16384:
            raise native.NativeError(1, f"resolution {settings.resolution} must be between 1 and 16384")
        if settings.destination == "FOLDER" and not settings.folder:
            raise native.NativeError(1, "choose a folder for the results")
        self.created_uv_maps = []
        self.uv_map = "sssbake" if settings.unwrap else settings.uv_map
        for obj in self.targets:
            layers = obj.data.uv_layers
            if not settings.unwrap and (layers.get(self.uv_map) if self.uv_map else layers.active) is None:
                raise native.NativeError(
                    1,
                    f"object `{obj.name}`: has no UV map {self.uv_map or '(none active)'}; choose one or Unwrap",
                )
        self.cancel = ctypes.c_int32(0)
        self.progress = 0.0
        self.current = ""
        self.results = []
        self.error = None
        self.keep = []
        try:
            if settings.unwrap:
                self._unwrap(context)
            self.scene = scene_export.build_scene(context, self.uv_map)
            self.materials = [scene_export.material_struct(settings, o, self.keep) for o in self.targets]
            self.colour_warnings = [w for o in self.targets for w in scene_export.material_notes(settings, o)]
        except Exception:
            self.abandon()
            raise
        native_settings = native.default_settings()
        native_settings.resolution = settings.resolution
        native_settings.method = native.METHODS.index(settings.method.lower())
        native_settings.margin = settings.margin
        native_settings.light_samples = QUALITY_SAMPLES[settings.quality]
        native_settings.outputs = sum(
            1 << i for i, output in enumerate(native.OUTPUTS) if output.upper() in settings.outputs
        )
        self.native_settings = native_settings

    def _unwrap(self, context):
        for obj in self.targets:
            layers = obj.data.uv_layers
            if layers.get("sssbake") is None:
                previous = layers.active.name if layers.active else None
                layers.new(name="sssbake")
                self.created_uv_maps.append((obj, previous))
            layers.active = layers["sssbake"]
            with context.temp_override(
                active_object=obj, object=obj, selected_objects=[obj], selected_editable_objects=[obj]
            ):
                bpy.ops.object.mode_set(mode="EDIT")
                try:
                    bpy.ops.mesh.select_all(action="SELECT")
                    bpy.ops.uv.smart_project(island_margin=0.01)
                finally:
                    bpy.ops.object.mode_set(mode="OBJECT")

    def run(self):
        """Bakes every target; may run on another thread (it touches no Blender data)."""
        count = len(self.names)
        try:
            for i, (obj_name, material) in enumerate(zip(self.names, self.materials, strict=True)):
                self.current = obj_name

                def report(fraction, i=i):
                    self.progress = (i + min(max(fraction, 0.0), 1.0)) / count

                self.results.append(
                    native.bake(self.scene, obj_name, material, self.native_settings, self.cancel, report)
                )
        except native.NativeError as error:
            self.error = error

    def finish(self):
        """Makes the images (main thread); the names of those made, and warnings."""
        made, warnings = [], list(self.colour_warnings)
        folder = bpy.path.abspath(self.settings.folder)
        try:
            for obj, result in zip(self.targets, self.results, strict=True):
                for planned in result.summary["objects"]:
                    if planned["uvs"]["warning"]:
                        warnings.append(f"{obj.name}: {planned['uvs']['warning']}")
                for output in native.OUTPUTS:
                    if output.upper() not in self.settings.outputs:
                        continue
                    image = images.store(obj, output, result, self.settings.destination, folder)
                    made.append(image.name)
                    if output == "diffuse" and self.settings.wire_material:
                        uv_map = self.uv_map or obj.data.uv_layers.active.name
                        images.show_in_material(obj, image, uv_map)
        finally:
            self.close()
        return made, warnings

    def close(self):
        for result in self.results:
            result.close()
        self.results = []
        self.scene.close()

    def abandon(self):
        """Undoes what the job changed (the UV maps it made) and frees the native data."""
        if hasattr(self, "scene"):
            self.close()
        for obj, previous in self.created_uv_maps:
            layers = obj.data.uv_layers
            if layers.get("sssbake") is not None:
                layers.remove(layers["sssbake"])
            if previous in layers:
                layers.active = layers[previous]
        self.created_uv_maps = []


class SSSBAKE_OT_bake(bpy.types.Operator):
    """Bake subsurface scattering of the selected objects into images"""

    bl_idname = "sssbake.bake"
    bl_label = "Bake Subsurface"
    bl_options = {"REGISTER", "UNDO"}  # noqa: RUF012 (Blender reads a set)
    __annotations__ = bake_properties()

    def settings(self, context):
        """The operator's properties where given, the panel's otherwise; a preset or a
        layers file given without a material source picks that source."""
        panel = context.scene.sssbake
        given = self.properties.is_property_set
        settings = types.SimpleNamespace(
            **{name: getattr(self, name) if given(name) else getattr(panel, name) for name in SETTING_NAMES}
        )
        if not given("material_source"):
            if given("preset"):
                settings.material_source = "PRESET"
            elif given("layers_file"):
                settings.material_source = "LAYERS"
        return settings

    def start(self, context, level):
        try:
            return Job(context, self.settings(context))
        except (native.NativeError, RuntimeError, OSError, ValueError) as error:
            # RuntimeError: an operator Blender refused (such as unwrapping a
            # mesh it cannot edit); the others: bad data on the way across.
            self.report({level}, f"sssbake: {error}")
            return None

    def conclude(self, job, level):
        _running.remove(job)
        if job.error is not None:
            job.abandon()
            if job.error.status == native.CANCELLED:
                self.report({"WARNING"}, "sssbake: cancelled; nothing was changed")
            else:
                self.report({level}, f"sssbake: {job.error}")
            return {"CANCELLED"}
        try:
            made, warnings = job.finish()
        except (ReferenceError, RuntimeError, OSError, native.NativeError) as error:
            # An object deleted while the bake ran, or a folder that cannot be written.
            self.report({level}, f"sssbake: the bake finished but its images could not be made: {error}")
            return {"CANCELLED"}
        for warning in warnings:
            self.report({"WARNING"}, f"sssbake: {warning}")
        self.report({"INFO"}, f"sssbake: made {', '.join(made)}")
        return {"FINISHED"}

    def execute(self, context):
        # From scripts and in background mode problems are warnings, so a script
        # sees a report and {'CANCELLED'} rather than an exception.
        job = self.start(context, "WARNING")
        if job is None:
            return {"CANCELLED"}
        _running.append(job)
        job.run()
        return self.conclude(job, "WARNING")

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        job = self.start(context, "ERROR")
        if job is None:
            return {"CANCELLED"}
        _running.append(job)
        self.job = job
        self.thread = threading.Thread(target=job.run, daemon=True)
        self.thread.start()
        manager = context.window_manager
        self.timer = manager.event_timer_add(0.2, window=context.window)
        manager.modal_handler_add(self)
        manager.progress_begin(0, 100)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self.job.cancel.value = 1
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}
        manager = context.window_manager
        percent = int(100 * self.job.progress)
        manager.progress_update(percent)
        context.workspace.status_text_set(f"sssbake: {self.job.current} {percent}% (Esc to cancel)")
        if self.thread.is_alive():
            return {"RUNNING_MODAL"}
        manager.event_timer_remove(self.timer)
        manager.progress_end()
        context.workspace.status_text_set(None)
        return self.conclude(self.job, "ERROR")
