"""The UV map `sssbake` the bake unwraps into: made once by Smart UV Project and then
kept, so the artist's fixes to it survive later bakes unless they ask to unwrap again.
The active UV map stays the artist's."""

import bpy
import numpy as np

UV_MAP = "sssbake"


def island_margin(margin, resolution):
    """Smart UV Project's gap between islands, as a fraction of the map, wide enough that
    the bake's margin (texels grown around each island) never reaches the next island."""
    return min(2.0 * margin / max(resolution, 1), 0.25)


def ensure_map(context, obj, redo, margin, resolution, changes):
    """Makes the map `sssbake` of `obj` by Smart UV Project when it is missing or `redo`;
    an existing map is otherwise used as it is. Every change is recorded in `changes`.
    True when the map was made now."""
    layers = obj.data.uv_layers
    existing = layers.get(UV_MAP)
    if existing is not None and not redo:
        return False
    active = layers.active.name if layers.active is not None else None
    render = next((layer.name for layer in layers if layer.active_render), None)
    if existing is None:
        layers.new(name=UV_MAP, do_init=False)
        changes.record(lambda: _remove_map(obj, active, render))
    else:
        saved = np.empty(2 * len(existing.data), dtype=np.float32)
        existing.data.foreach_get("uv", saved)
        changes.record(lambda: obj.data.uv_layers[UV_MAP].data.foreach_set("uv", saved))
    # Smart UV Project writes into the active map; the artist's active one comes back after.
    layers.active = layers[UV_MAP]
    flags = _selection(obj.data)
    try:
        with context.temp_override(
            active_object=obj, object=obj, selected_objects=[obj], selected_editable_objects=[obj]
        ):
            bpy.ops.object.mode_set(mode="EDIT")
            try:
                # Every face, hidden or not; the artist's selection comes back after.
                bpy.ops.mesh.reveal(select=True)
                bpy.ops.mesh.select_all(action="SELECT")
                bpy.ops.uv.smart_project(
                    island_margin=island_margin(margin, resolution), margin_method="FRACTION"
                )
            finally:
                bpy.ops.object.mode_set(mode="OBJECT")
    finally:
        _set_selection(obj.data, flags)
        _activate(obj, active, render)
    return True


def _selection(mesh):
    """The select and hide flags of every vertex, edge and face."""
    flags = {}
    for name in ("vertices", "edges", "polygons"):
        items = getattr(mesh, name)
        for flag in ("select", "hide"):
            values = np.empty(len(items), dtype=bool)
            items.foreach_get(flag, values)
            flags[name, flag] = values
    return flags


def _set_selection(mesh, flags):
    for (name, flag), values in flags.items():
        getattr(mesh, name).foreach_set(flag, values)
    mesh.update()


def _activate(obj, active, render):
    layers = obj.data.uv_layers
    if active is not None and active in layers:
        layers.active = layers[active]
    if render is not None and render in layers:
        layers[render].active_render = True


def _remove_map(obj, active, render):
    layers = obj.data.uv_layers
    if UV_MAP in layers:
        layers.remove(layers[UV_MAP])
    _activate(obj, active, render)
