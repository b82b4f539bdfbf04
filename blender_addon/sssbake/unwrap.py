"""The UV map `sssbake` the bake unwraps into: made once, by the library's xatlas (as
`sssbake bake` unwraps) or by Smart UV Project, and then kept, so the artist's fixes to it
survive later bakes unless they ask to unwrap again. Charts are kept apart by twice the
bake's margin. The active UV map and the mesh's selection stay the artist's."""

import bpy
import numpy as np

from . import binding

UV_MAP = "sssbake"


def padding(margin):
    """Texels between charts: each grows by the margin, so twice the margin."""
    return 2 * margin


def ensure_map(context, obj, method, redo, margin, resolution, changes):
    """Makes the map `sssbake` of `obj` by `method` (XATLAS or SMART) when it is missing
    or `redo`; an existing map is otherwise used as it is. Every change is recorded in
    `changes`. Returns None when the map was kept, else what the artist should know
    about the new map ("" when nothing)."""
    layers = obj.data.uv_layers
    existing = layers.get(UV_MAP)
    if existing is not None and not redo:
        return None
    active = layers.active.name if layers.active is not None else None
    render = next((layer.name for layer in layers if layer.active_render), None)
    if existing is None:
        layers.new(name=UV_MAP, do_init=False)
        changes.record(lambda: _remove_map(obj, active, render))
    else:
        saved = np.empty(2 * len(existing.data), dtype=np.float32)
        existing.data.foreach_get("uv", saved)
        changes.record(lambda: obj.data.uv_layers[UV_MAP].data.foreach_set("uv", saved))
    note, cut = _xatlas(obj, layers[UV_MAP], margin, resolution) if method == "XATLAS" else ("", False)
    if method == "XATLAS" and not cut:
        return note
    # Blender's operators write into the active map; the artist's active one comes back after.
    layers.active = layers[UV_MAP]
    flags = _selection(obj.data)
    gap = padding(margin) / max(resolution, 1)
    try:
        with context.temp_override(
            active_object=obj, object=obj, selected_objects=[obj], selected_editable_objects=[obj]
        ):
            bpy.ops.object.mode_set(mode="EDIT")
            try:
                # Every face, hidden or not; the artist's selection comes back after.
                bpy.ops.mesh.reveal(select=True)
                bpy.ops.mesh.select_all(action="SELECT")
                if method == "XATLAS":
                    # Faces xatlas cut in two were made whole beside their chart, where
                    # they may reach the next one: the charts are packed again (by their
                    # bounds: the other shapes take seconds on a 1000-face mesh).
                    bpy.ops.uv.pack_islands(
                        margin=gap, margin_method="ADD", rotate=False, shape_method="AABB"
                    )
                else:
                    bpy.ops.uv.smart_project(island_margin=gap, margin_method="ADD")
            finally:
                bpy.ops.object.mode_set(mode="OBJECT")
    finally:
        _set_selection(obj.data, flags)
        _activate(obj, active, render)
    return note


def _xatlas(obj, layer, margin, resolution):
    """Charts by the library's xatlas of the object's own mesh (the modifiers then
    interpolate the map, as they do any UV map), in world proportions. xatlas charts
    triangles; a face whose triangles it put in different charts keeps the chart of its
    largest triangle, its other triangles unfolded beside it. Returns what the artist
    should know ("" when nothing) and whether a face was cut."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    count = len(mesh.loop_triangles)
    loops = np.empty(3 * count, dtype=np.int32)
    vertices = np.empty(3 * count, dtype=np.int32)
    faces = np.empty(count, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    mesh.loop_triangles.foreach_get("vertices", vertices)
    mesh.loop_triangles.foreach_get("polygon_index", faces)
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    linear = np.array(obj.matrix_world, dtype=np.float64)[:3, :3]
    corners = co.reshape(-1, 3)[vertices] @ linear.T
    positions = np.ascontiguousarray(corners, dtype=np.float32).reshape(-1)
    indices = np.arange(3 * count, dtype=np.uint32)
    # Charts that do not fit the map this far apart are packed closer, and the artist told.
    wanted = gap = padding(margin)
    while True:
        try:
            uvs, charts = binding.package().unwrap(obj.name, positions, indices, resolution, gap)
            break
        except binding.Error:
            if gap == 0:
                raise
            gap //= 2
    note = (
        f"{obj.name}: the charts of UV map `{UV_MAP}` fit a {resolution}² map only {gap} texels "
        f"apart, not {wanted} (twice the margin), so margins may meet; raise Resolution and "
        "tick Unwrap Again"
        if gap < wanted
        else ""
    )
    uvs, corners = uvs.reshape(-1, 3, 2).astype(np.float64), corners.reshape(-1, 3, 3)
    areas = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    # Each face's largest triangle (the last written wins, in order of area).
    largest = np.empty(len(mesh.polygons), dtype=np.int64)
    order = np.argsort(areas, kind="stable")
    largest[faces[order]] = order
    home = charts[largest[faces]] == charts
    data = np.zeros((len(mesh.loops), 2), dtype=np.float64)
    placed = np.zeros(len(mesh.loops), dtype=bool)
    data[loops.reshape(-1, 3)[home]] = uvs[home]
    placed[loops.reshape(-1, 3)[home].reshape(-1)] = True
    # The rest of a face cut in two, triangle by triangle across an edge already placed,
    # each unfolded flat beside it: its shape kept and not mirrored.
    waiting = list(np.flatnonzero(~home))
    while waiting:
        left = []
        for t in waiting:
            corner_loops = loops[3 * t : 3 * t + 3]
            missing = [c for c in range(3) if not placed[corner_loops[c]]]
            if len(missing) == 1:
                k = missing[0]
                p, q = (k + 1) % 3, (k + 2) % 3
                data[corner_loops[k]] = _unfold(
                    corners[t, p], corners[t, q], corners[t, k], data[corner_loops[p]], data[corner_loops[q]]
                )
                placed[corner_loops[k]] = True
            elif missing:
                left.append(t)
        if len(left) == len(waiting):
            # Corners reached by no placed edge: by the largest triangle's affine map.
            for t in left:
                for c in range(3):
                    if not placed[loops[3 * t + c]]:
                        big = largest[faces[t]]
                        data[loops[3 * t + c]] = _extend(corners[big], uvs[big], corners[t, c])
                        placed[loops[3 * t + c]] = True
            break
        waiting = left
    layer.data.foreach_set("uv", data.astype(np.float32).reshape(-1))
    return note, not home.all()


def _unfold(p, q, r, p_uv, q_uv):
    """The UV of corner `r` of the triangle (p, q, r), counter-clockwise, given the UVs of
    `p` and `q`: the triangle laid flat on its edge pq at the scale of that edge."""
    edge = q - p
    length = np.linalg.norm(edge)
    uv_edge = q_uv - p_uv
    uv_length = np.linalg.norm(uv_edge)
    if length <= 0 or uv_length <= 0:
        return (p_uv + q_uv) / 2
    along = np.dot(r - p, edge) / length
    across = np.linalg.norm(r - p - along * edge / length)
    direction = uv_edge / uv_length
    normal = np.array([-direction[1], direction[0]])
    scale = uv_length / length
    return p_uv + scale * (along * direction + across * normal)


def _extend(triangle, uvs, point):
    """The UV of `point` by the affine map that takes `triangle`'s corners to `uvs`
    (the point projected onto the triangle's plane)."""
    edges = np.stack([triangle[1] - triangle[0], triangle[2] - triangle[0]], axis=1)
    weights, *_ = np.linalg.lstsq(edges, point - triangle[0], rcond=None)
    return uvs[0] + weights[0] * (uvs[1] - uvs[0]) + weights[1] * (uvs[2] - uvs[0])


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
