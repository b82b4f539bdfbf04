"""Makes the pictures of docs/blender.md in a headless bpy: a head in a Principled skin
under a sun and a point light, rendered by Cycles with its own subsurface scattering, and
the same head baked by the add-on and shown through Show in Material, rendered in EEVEE.

    PATH=$PWD/.venv/bin:$PATH .venv/bin/python -m pip install --no-build-isolation .
    .venv/bin/python scripts/blender_pictures.py   # writes docs/blender_cycles.png, docs/blender_eevee.png

EEVEE compiles its shaders in software without a GPU; the whole script took about a minute
on two cores."""

import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SIZE = 320


def head_scene(bpy):
    """Suzanne as a 20 cm head in skin (mean free path about 1 mm in red), lit from the side."""
    from skin_material import principled_skin  # tests/, on the path main() sets

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(size=0.2, rotation=(0.0, 0.0, 0.0))
    head = bpy.context.active_object
    head.name = "Head"
    head.modifiers.new("smooth", "SUBSURF").levels = 2
    bpy.ops.object.shade_smooth()
    material = principled_skin(0.004, roughness=0.6)
    head.data.materials.append(material)
    bpy.ops.object.light_add(type="SUN", rotation=(1.1, 0.0, 0.9))
    bpy.context.active_object.data.energy = 1.2
    bpy.ops.object.light_add(type="POINT", location=(-0.25, -0.3, 0.1))
    bpy.context.active_object.data.energy = 6.0
    bpy.ops.object.camera_add(location=(0.0, -0.5, 0.02), rotation=(1.5708, 0.0, 0.0))
    scene = bpy.context.scene
    scene.camera = bpy.context.active_object
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.view_settings.view_transform = "Standard"
    # A black world: the lights are the only light, in the render and in the bake.
    world = bpy.data.worlds.new("Black")
    world.color = (0.0, 0.0, 0.0)
    if world.node_tree is not None:
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    scene.world = world
    bpy.ops.object.select_all(action="DESELECT")
    head.select_set(True)
    bpy.context.view_layer.objects.active = head
    return head


def render(bpy, engine, path):
    scene = bpy.context.scene
    scene.render.engine = engine
    if engine == "CYCLES":
        scene.cycles.samples = 128
        scene.cycles.use_denoising = False
    scene.render.filepath = str(path)
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    print(f"{engine}: {path.name} in {time.monotonic() - start:.0f} s", flush=True)


def main():
    # The add-on loaded as Blender loads the extension, baking through the installed
    # `sssbake` package (`pip install .`).
    sys.path.insert(0, str(ROOT / "tests"))
    import bpy
    from conftest import load_extension

    head_scene(bpy)
    render(bpy, "CYCLES", ROOT / "docs" / "blender_cycles.png")
    load_extension("sssbake", ROOT / "blender_addon").register()
    result = bpy.ops.sssbake.bake(
        resolution=1024, margin=8, unwrap=True, outputs={"DIFFUSE"}, wire_material=True
    )
    if result != {"FINISHED"}:
        sys.exit("the bake failed; its report is above")
    render(bpy, "BLENDER_EEVEE", ROOT / "docs" / "blender_eevee.png")


if __name__ == "__main__":
    main()
