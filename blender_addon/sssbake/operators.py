"""The bake operator: modal with progress in the status bar and Esc to cancel when run
from the interface, synchronous with progress lines in background mode and from scripts.
One bake is one undo step; the redo panel is hidden (changing a setting there would
re-run the whole bake without progress or Esc): the panel holds the settings."""

import threading
import types

import bpy

from . import binding, properties, report
from .job import Job

_running = []


def cancel_running():
    """Asks every bake in progress to stop (Esc does this for the modal one)."""
    for job in _running:
        job.cancel.set()


# What a bake may raise on the way: the library's errors (binding.Error), bad data (ValueError),
# an operator Blender refused (RuntimeError), a file (OSError), an object deleted while
# the bake ran (ReferenceError). Anything else is a bug, still reported, never raised.
EXPECTED = (binding.Error, RuntimeError, OSError, ValueError, ReferenceError)


def _message(error):
    return str(error) if isinstance(error, EXPECTED) else f"internal error ({type(error).__name__}): {error}"


class SSSBAKE_OT_bake(bpy.types.Operator):
    """Bake subsurface scattering of the selected mesh objects into images"""

    bl_idname = "sssbake.bake"
    bl_label = "Bake Subsurface"
    bl_options = {"UNDO"}  # noqa: RUF012 (Blender reads a set)
    # Its properties are the panel's settings, given by register() from the library.

    @classmethod
    def poll(cls, context):
        if _running:
            cls.poll_message_set("a subsurface bake is running")
            return False
        if context.mode not in {"OBJECT", "EDIT_MESH"}:
            cls.poll_message_set("bake from Object Mode or Edit Mode")
            return False
        if not any(o.type == "MESH" for o in context.selected_objects):
            cls.poll_message_set("select the mesh objects to bake")
            return False
        return True

    def settings(self, context):
        """The operator's properties where given, the panel's otherwise; a preset or a
        layers file given without a material source picks that source."""
        panel = context.scene.sssbake
        given = self.properties.is_property_set
        settings = types.SimpleNamespace(
            **{
                name: getattr(self, name) if given(name) else getattr(panel, name)
                for name in properties.SETTING_NAMES
            }
        )
        if not given("material_source"):
            if given("preset"):
                settings.material_source = "PRESET"
            elif given("layers_file"):
                settings.material_source = "LAYERS"
        return settings

    def start(self, context, level):
        settings = self.settings(context)
        try:
            job = Job(context, settings)
        except Exception as error:  # noqa: BLE001 (reported: a bake never raises into Blender)
            self.report({level}, f"sssbake: {_message(error)}")
            return None
        _running.append(job)
        return job

    def conclude(self, context, job, level):
        _running.remove(job)
        if job.error is not None:
            failures = job.abandon(context)
            if isinstance(job.error, binding.Cancelled):
                self.report({"WARNING"}, "sssbake: cancelled; nothing was changed")
            else:
                self.report({level}, f"sssbake: {_message(job.error)}")
            self._report_failures(failures)
            return {"CANCELLED"}
        try:
            made, lines, notes = job.finish(context)
        except Exception as error:  # noqa: BLE001 (reported: a bake never raises into Blender)
            self.report(
                {level},
                f"sssbake: the bake finished but its images could not be made, so nothing was "
                f"changed: {_message(error)}",
            )
            self._report_failures(job.failures)
            return {"CANCELLED"}
        for line in lines:
            self.report({"INFO"}, f"sssbake: {line}")
        for note in notes:
            self.report({"WARNING"}, f"sssbake: {note}")
        self.report({"INFO"}, f"sssbake: made {', '.join(made)}")
        return {"FINISHED"}

    def _report_failures(self, failures):
        for failure in failures:
            self.report({"ERROR"}, f"sssbake: could not put back a change: {failure}")

    def execute(self, context):
        # From scripts and in background mode problems are warnings, so a script
        # sees a report and {'CANCELLED'} rather than an exception.
        job = self.start(context, "WARNING")
        if job is None:
            return {"CANCELLED"}
        job.run(report.ProgressLines() if bpy.app.background else None)
        return self.conclude(context, job, "WARNING")

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        job = self.start(context, "ERROR")
        if job is None:
            return {"CANCELLED"}
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
            self.job.cancel.set()
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
        return self.conclude(context, self.job, "ERROR")


def menu_entry(self, _context):
    """The operator in the 3-D view's Object menu (and so in F3 search)."""
    self.layout.separator()
    self.layout.operator(SSSBAKE_OT_bake.bl_idname, icon="RENDER_STILL")
