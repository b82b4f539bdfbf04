"""Writes the USD layer of a bake with usd-core and prints it (usda) on standard output.

Run as `python write_layer.py REQUEST_FILE`. The request (JSON) names the input
stage, the path from the new layer's folder to it, and per baked object its mesh prim,
its maps and, for an object that was unwrapped, its UVs per face corner (written as
`primvars:sssbake_st`, which its material reads instead of `st`). The layer sublayers the input and overrides only what the bake adds: one
material per object (UsdPreviewSurface whose diffuse colour is a UsdUVTexture reading
the `diffuse` map through the `st` primvar), bound to the object's mesh, with
`sssbake:` attributes recording how it was baked. The input is never written.
"""

import json
import sys


def fail(message: str) -> None:
    print(message, file=sys.stderr)
    sys.exit(2)


try:
    from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdShade
except ImportError:
    fail("this Python has no usd-core (pip install usd-core), which writing USD needs")


def material_for(stage, root, baked, settings):
    name = Tf.MakeValidIdentifier(baked["object"])
    path = root.AppendPath(f"SssbakeMaterials/{name}")
    material = UsdShade.Material.Define(stage, path)
    reader = UsdShade.Shader.Define(stage, path.AppendChild("st"))
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    varname = "sssbake_st" if baked.get("st") else "st"
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set(varname)
    texture = UsdShade.Shader.Define(stage, path.AppendChild("diffuse"))
    texture.CreateIdAttr("UsdUVTexture")
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(baked["diffuse"])
    texture.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("sRGB")
    texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    surface = UsdShade.Shader.Define(stage, path.AppendChild("surface"))
    surface.CreateIdAttr("UsdPreviewSurface")
    surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        texture.ConnectableAPI(), "rgb"
    )
    surface.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(1.0)
    material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    prim = material.GetPrim()
    for key, value in {**settings, **baked["attributes"], "maps": baked["maps"]}.items():
        kind = Sdf.ValueTypeNames.StringArray if isinstance(value, list) else Sdf.ValueTypeNames.String
        prim.CreateAttribute(f"sssbake:{key}", kind, custom=True).Set(
            value if isinstance(value, list) else str(value)
        )
    return material


def main():
    if len(sys.argv) < 2:
        fail("usage: write_layer.py REQUEST_FILE")
    with open(sys.argv[1], encoding="utf-8") as file:
        request = json.load(file)
    source = Usd.Stage.Open(request["input"])
    if source is None:
        fail("cannot open the stage")
    # Compose over the input by its absolute path (an anonymous layer would
    # resolve a relative one against the working folder); the written layer
    # names it relative to where it will live.
    layer = Sdf.Layer.CreateAnonymous(".usda")
    layer.subLayerPaths.append(request["input"])
    stage = Usd.Stage.Open(layer)
    UsdGeom.SetStageMetersPerUnit(stage, UsdGeom.GetStageMetersPerUnit(source))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.GetStageUpAxis(source))
    default = source.GetDefaultPrim()
    root = default.GetPath() if default else Sdf.Path("/")
    if default:
        stage.SetDefaultPrim(stage.GetPrimAtPath(root))
    for baked in request["objects"]:
        mesh = stage.GetPrimAtPath(baked["prim"])
        if not mesh:
            fail(f"object `{baked['object']}`: no prim at {baked['prim']}")
        material = material_for(stage, root, baked, request["settings"])
        override = stage.OverridePrim(mesh.GetPath())
        binding = UsdShade.MaterialBindingAPI.Apply(override)
        binding.Bind(material)
        if baked.get("st"):
            # An unwrapped object's UVs, one per face corner, beside its own.
            primvar = UsdGeom.PrimvarsAPI(override).CreatePrimvar(
                "sssbake_st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying
            )
            primvar.Set([Gf.Vec2f(*uv) for uv in baked["st"]])
    layer.subLayerPaths.clear()
    layer.subLayerPaths.append(request["input_from_layer"])
    sys.stdout.write(layer.ExportToString())


main()
