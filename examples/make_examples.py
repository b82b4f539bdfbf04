"""Builds the example scenes with Blender (bpy) and exports each as glTF and USD.

Run from the repository root with the test environment's Python:

    .venv/bin/python examples/make_examples.py

It writes examples/<name>/<name>.gltf (+ .bin) and examples/<name>/<name>.usda for
`head` (Suzanne, subdivided, skin), `marble` (a sphere of marble) and `ear` (a thin
curved shell lit from behind, for light crossing thin parts). Everything is built
from Blender's own primitives, so the files are the same on every run.

Blender's exporters leave out the Principled BSDF's subsurface inputs, so each file
gets them afterwards, stated by each format's own definition of what Cycles renders
(docs/materials.md "Materials from Blender"): Cycles' Random Walk uses Radius × Scale / 4π as the
mean free path. glTF gets KHR_materials_volume (attenuation distance = Scale / 4π,
attenuation colour = e^(-1/Radius), so the mean free path is Radius × Scale / 4π) and
KHR_materials_volume_scatter's multiscatterColor = Base Color and KHR_materials_ior (kept
when Blender writes it, added when it does not); USD an OpenPBR shader in the `mtlx` render context
(subsurface_color = Base Color, subsurface_radius = Scale / 4π, subsurface_radius_scale
= Radius, specular_ior = IOR) beside Blender's UsdPreviewSurface.
"""

import json
import math
import pathlib
import sys

import bpy
from pxr import Gf, Sdf, Usd, UsdShade

HERE = pathlib.Path(__file__).resolve().parent


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.unit_settings.system = "METRIC"


SUBSURFACE = {}

# Blender's default Subsurface Scale, with the default skin's Radius: the reach of real skin
# (mean free path 4 mm in red, 1.4 mm in green, 0.8 mm in blue under Cycles' Random Walk).
SKIN_SCALE = 0.05
# Jensen et al. 2001's marble (σs' = 2.19, 2.62, 3.00 /mm, σa = 0.0021, 0.0041, 0.0071 /mm,
# η 1.5): its mean free path 1/σt' × 4π as Radius × Scale, Radius normalised to red's.
MARBLE_MEAN_FREE_PATH_MM = [1.0 / (s + a) for s, a in ((2.19, 0.0021), (2.62, 0.0041), (3.00, 0.0071))]
MARBLE_SCALE = 4 * math.pi * MARBLE_MEAN_FREE_PATH_MM[0] / 1000
MARBLE_RADIUS = tuple(round(m / MARBLE_MEAN_FREE_PATH_MM[0], 4) for m in MARBLE_MEAN_FREE_PATH_MM)


def translucent_material(name, colour, radius, scale, ior=1.4):
    """A Principled BSDF with Random Walk subsurface scattering (Blender's own parameters)."""
    SUBSURFACE[name] = (colour, radius, scale, ior)
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    bsdf.inputs["Subsurface Radius"].default_value = radius
    bsdf.inputs["Subsurface Scale"].default_value = scale
    bsdf.inputs["IOR"].default_value = ior
    bsdf.subsurface_method = "RANDOM_WALK"
    bsdf.inputs["Roughness"].default_value = 0.4
    return material


def finish(obj, material):
    obj.data.materials.append(material)
    for modifier in list(obj.modifiers):
        bpy.context.view_layer.objects.active = obj
        bpy.ops.object.modifier_apply(modifier=modifier.name)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.transform_apply(location=False, rotation=True, scale=True)
    bpy.ops.object.shade_smooth()


def sun(name, rotation, strength, angle_degrees=0.53):
    bpy.ops.object.light_add(type="SUN", rotation=rotation)
    light = bpy.context.active_object
    light.name = name
    light.data.energy = strength
    light.data.angle = math.radians(angle_degrees)
    return light


def point(name, location, power, radius):
    bpy.ops.object.light_add(type="POINT", location=location)
    light = bpy.context.active_object
    light.name = name
    light.data.energy = power
    light.data.shadow_soft_size = radius
    return light


def export(name):
    folder = HERE / name
    folder.mkdir(exist_ok=True)
    bpy.ops.export_scene.gltf(
        filepath=str(folder / f"{name}.gltf"),
        export_format="GLTF_SEPARATE",
        export_lights=True,
        export_yup=True,
    )
    bpy.ops.wm.usd_export(filepath=str(folder / f"{name}.usda"))
    add_gltf_subsurface(folder / f"{name}.gltf")
    add_usd_subsurface(folder / f"{name}.usda")


def add_gltf_subsurface(path):
    document = json.loads(path.read_text())
    for material in document.get("materials", []):
        if material["name"] not in SUBSURFACE:
            continue
        colour, radius, scale, ior = SUBSURFACE[material["name"]]
        extensions = material.setdefault("extensions", {})
        # Blender writes KHR_materials_ior only beside transmission; keep it when it does.
        extensions.setdefault("KHR_materials_ior", {"ior": ior})
        extensions |= {
            "KHR_materials_diffuse_transmission": {
                "diffuseTransmissionFactor": 1.0,
                "diffuseTransmissionColorFactor": list(colour),
            },
            "KHR_materials_volume": {
                "thicknessFactor": scale,
                "attenuationDistance": scale / (4 * math.pi),
                "attenuationColor": [round(math.exp(-1.0 / r), 6) for r in radius],
            },
            "KHR_materials_volume_scatter": {"multiscatterColor": list(colour)},
        }
        used = document.setdefault("extensionsUsed", [])
        used += [e for e in extensions if e not in used]
    path.write_text(json.dumps(document, indent=2) + "\n")


def add_usd_subsurface(path):
    stage = Usd.Stage.Open(str(path))
    for prim in stage.Traverse():
        if not prim.IsA(UsdShade.Material) or prim.GetName() not in SUBSURFACE:
            continue
        colour, radius, scale, ior = SUBSURFACE[prim.GetName()]
        shader = UsdShade.Shader.Define(stage, prim.GetPath().AppendChild("OpenPBR"))
        shader.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
        for name, kind, value in [
            ("base_color", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*colour)),
            ("subsurface_weight", Sdf.ValueTypeNames.Float, 1.0),
            ("subsurface_color", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*colour)),
            ("subsurface_radius", Sdf.ValueTypeNames.Float, scale / (4 * math.pi)),
            ("subsurface_radius_scale", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*radius)),
            ("specular_ior", Sdf.ValueTypeNames.Float, ior),
        ]:
            shader.CreateInput(name, kind).Set(value)
        output = shader.CreateOutput("out", Sdf.ValueTypeNames.Token)
        UsdShade.Material(prim).CreateSurfaceOutput("mtlx").ConnectToSource(output)
    stage.Save()


def head():
    """Suzanne at the size of a head (about 20 cm across), twice subdivided, in skin."""
    reset()
    bpy.ops.mesh.primitive_monkey_add(size=0.2)
    obj = bpy.context.active_object
    obj.name = "Head"
    obj.rotation_euler = (math.radians(90), 0, 0)
    obj.modifiers.new("smooth", "SUBSURF").levels = 2
    finish(obj, translucent_material("Skin", (0.8, 0.55, 0.45), (1.0, 0.35, 0.2), SKIN_SCALE))
    sun("Key", (math.radians(50), 0, math.radians(30)), 1.0)
    point("Rim", (0.05, 0.4, 0.1), 40.0, 0.05)


def marble():
    """A 10 cm marble ball lit by a low sun."""
    reset()
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.05, segments=96, ring_count=48)
    obj = bpy.context.active_object
    obj.name = "Ball"
    finish(obj, translucent_material("Marble", (0.83, 0.79, 0.75), MARBLE_RADIUS, MARBLE_SCALE, ior=1.5))
    sun("Sun", (math.radians(60), 0, math.radians(-20)), 3.0)


def ear():
    """A bent shell 3 mm thick, 6 cm × 4 cm, with the light behind it."""
    reset()
    bpy.ops.mesh.primitive_plane_add(size=1.0)
    obj = bpy.context.active_object
    obj.name = "Ear"
    obj.scale = (0.06, 0.04, 1.0)
    bpy.ops.object.transform_apply(scale=True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=24)
    bpy.ops.object.mode_set(mode="OBJECT")
    bend = obj.modifiers.new("bend", "SIMPLE_DEFORM")
    bend.deform_method = "BEND"
    bend.deform_axis = "Y"
    bend.angle = math.radians(70)
    obj.modifiers.new("thickness", "SOLIDIFY").thickness = 0.003
    finish(obj, translucent_material("Skin", (0.8, 0.55, 0.45), (1.0, 0.35, 0.2), SKIN_SCALE))
    # Solidify repeats the UVs on both faces: give the shell its own layout.
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(island_margin=0.02)
    bpy.ops.object.mode_set(mode="OBJECT")
    sun("Back", (math.radians(180), 0, 0), 3.0)
    sun("Front", (0, 0, 0), 0.3)


# Each example's scene, built in the current Blender session (other scripts build them to
# render the original beside the bake).
SCENES = {"head": head, "marble": marble, "ear": ear}

if __name__ == "__main__":
    names = sys.argv[1:] or list(SCENES)
    for example in names:
        SCENES[example]()
        export(example)
        print(f"wrote examples/{example}")
