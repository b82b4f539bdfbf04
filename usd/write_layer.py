"""Writes the USD layer of a bake with usd-core and prints it (usda) on standard output.

Run as `python write_layer.py REQUEST_FILE`. The request (JSON) names the input
stage, the path from the new layer's folder to it, the primvars texture coordinates
are read from (the first a mesh has), and per baked object its mesh prim, its maps
and, for an object that was unwrapped, its UVs per face corner. The layer sublayers
the input and overrides only what the bake adds. Each baked mesh gets a variant set
`sssbakeLook` with the variants `original` (the asset as it was) and `baked`
(selected). In `baked` the mesh carries a collection-based binding, stronger than
descendants, to a material that shows the look's linear EXR as emission: a
UsdPreviewSurface with `emissiveColor` from a UsdUVTexture (`sourceColorSpace` raw)
reading the mesh's UVs, `diffuseColor` black and the specular workflow with a black
`specularColor`, so nothing lights it again. A variant is weaker than the input's own
(local) direct binding, which a sublayer keeps local; a collection binding authored
on the prim itself is resolved before its direct binding, so it wins, and the
`original` variant, authoring nothing, leaves the asset's binding as it was. An
unwrapped object's UVs (`primvars:sssbake_st`, face varying) are authored in `baked`
too. The material carries `sssbake:` attributes recording how it was baked. The
input is never written.
"""

import json
import sys


class LayerError(Exception):
    """Why the layer cannot be written, said for the person who asked."""


def fail(message: str) -> None:
    raise LayerError(message)


try:
    from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdShade
except ImportError:
    print("this Python has no usd-core (pip install usd-core), which writing USD needs", file=sys.stderr)
    sys.exit(2)

LOOK = "sssbakeLook"
BLACK = Gf.Vec3f(0.0, 0.0, 0.0)


def material_for(stage, root, baked, settings, varname):
    name = Tf.MakeValidIdentifier(baked["object"])
    path = root.AppendPath(f"SssbakeMaterials/{name}")
    material = UsdShade.Material.Define(stage, path)
    reader = UsdShade.Shader.Define(stage, path.AppendChild("st"))
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set(varname)
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    texture = UsdShade.Shader.Define(stage, path.AppendChild("emission"))
    texture.CreateIdAttr("UsdUVTexture")
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(baked["emission"])
    # The EXR holds linear values: read as they are.
    texture.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("raw")
    texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    surface = UsdShade.Shader.Define(stage, path.AppendChild("surface"))
    surface.CreateIdAttr("UsdPreviewSurface")
    surface.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        texture.ConnectableAPI(), "rgb"
    )
    surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(BLACK)
    surface.CreateInput("useSpecularWorkflow", Sdf.ValueTypeNames.Int).Set(1)
    surface.CreateInput("specularColor", Sdf.ValueTypeNames.Color3f).Set(BLACK)
    surface.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(1.0)
    material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    prim = material.GetPrim()
    for key, value in {**settings, **baked["attributes"], "maps": baked["maps"]}.items():
        kind = Sdf.ValueTypeNames.StringArray if isinstance(value, list) else Sdf.ValueTypeNames.String
        prim.CreateAttribute(f"sssbake:{key}", kind, custom=True).Set(
            value if isinstance(value, list) else str(value)
        )
    return material


def uv_primvar(mesh, baked, candidates):
    """The primvar the bake's UVs are in: the unwrap's, or the first candidate the mesh has."""
    if baked.get("st"):
        return "sssbake_st"
    api = UsdGeom.PrimvarsAPI(mesh)
    return next((n for n in candidates if api.HasPrimvar(n)), candidates[0])


def add_look(stage, mesh, material, baked):
    """The variant set on `mesh` whose selected `baked` variant binds `material`."""
    override = stage.OverridePrim(mesh.GetPath())
    looks = override.GetVariantSets().AddVariantSet(LOOK)
    for variant in ("original", "baked"):
        looks.AddVariant(variant)
    looks.SetVariantSelection("baked")
    # The schemas are applied outside the variant: an input with an explicit (not
    # prepended) apiSchemas list, as a flattened or exported stage has, is a stronger
    # opinion than a variant and would drop them; a prepend in this layer adds to it.
    # Applied with nothing authored, they change nothing in `original`.
    Usd.CollectionAPI.Apply(override, LOOK)
    UsdShade.MaterialBindingAPI.Apply(override)
    with looks.GetVariantEditContext():
        collection = Usd.CollectionAPI(override, LOOK)
        collection.CreateIncludesRel().AddTarget(mesh.GetPath())
        binding = UsdShade.MaterialBindingAPI(override)
        binding.Bind(collection, material, LOOK, UsdShade.Tokens.strongerThanDescendants)
        if baked.get("st"):
            # An unwrapped object's UVs, one per face corner, beside its own.
            primvar = UsdGeom.PrimvarsAPI(override).CreatePrimvar(
                "sssbake_st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying
            )
            primvar.Set([Gf.Vec2f(*uv) for uv in baked["st"]])


def layer_text(source, request):
    """The layer (usda text) that shows the bake in `request` over the open stage
    `source`; it sublayers request["input_from_layer"] when that is given (the input's
    file, from where the layer will live) and nothing otherwise (a stage only in memory,
    onto which the caller sublayers it)."""
    # Compose over the source by its root layer's identifier: the file by its absolute
    # path (an anonymous layer would resolve a relative one against the working folder),
    # or the stage in memory as it is, unsaved edits included.
    layer = Sdf.Layer.CreateAnonymous(".usda")
    layer.subLayerPaths.append(source.GetRootLayer().identifier)
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
        varname = uv_primvar(mesh, baked, request["uv_primvars"])
        material = material_for(stage, root, baked, request["settings"], varname)
        add_look(stage, mesh, material, baked)
    layer.subLayerPaths.clear()
    if request.get("input_from_layer"):
        layer.subLayerPaths.append(request["input_from_layer"])
    return layer.ExportToString()


def main():
    if len(sys.argv) < 2:
        fail("usage: write_layer.py REQUEST_FILE")
    with open(sys.argv[1], encoding="utf-8") as file:
        request = json.load(file)
    source = Usd.Stage.Open(request["input"])
    if source is None:
        fail("cannot open the stage")
    sys.stdout.write(layer_text(source, request))


if __name__ == "__main__":
    try:
        main()
    except LayerError as e:
        print(e, file=sys.stderr)
        sys.exit(2)
