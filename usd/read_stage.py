"""Reads a USD stage with usd-core and prints what sssbake bakes from it as JSON.

Run as `python read_stage.py STAGE UV_PRIMVARS`. Every UsdGeomMesh becomes an
object with world-space points (in stage units), fan-triangulated faces and,
per triangle corner, the first of the comma-separated UV_PRIMVARS it has and normals expanded from any
interpolation, and the bound material's surface shader: its id and the
values of its inputs. UsdLux lights come with their world transforms. The stage's
metersPerUnit and upAxis come along; sssbake converts to millimetres.
"""

import json
import math
import sys


class StageError(Exception):
    """What is wrong with the stage, said for the person who made it."""


def fail(message: str) -> None:
    raise StageError(message)


try:
    from pxr import Gf, Tf, Usd, UsdGeom, UsdLux, UsdShade
except ImportError:
    print("this Python has no usd-core (pip install usd-core), which reading USD needs", file=sys.stderr)
    sys.exit(2)


def finite_or_zero(value):
    """A primvar value with each non-finite component 0, as the bake repairs them."""
    return [x if math.isfinite(x) else 0.0 for x in value]


def per_corner(values, interpolation, counts, indices, what="a primvar"):
    """Values of any interpolation expanded to every face corner, in face order."""
    needed = {
        UsdGeom.Tokens.faceVarying: len(indices),
        UsdGeom.Tokens.vertex: max(indices, default=-1) + 1,
        UsdGeom.Tokens.varying: max(indices, default=-1) + 1,
        UsdGeom.Tokens.uniform: len(counts),
    }.get(interpolation, 1 if counts else 0)
    if len(values) < needed:
        raise BadMesh(f"{what} has {len(values)} values, its {interpolation} interpolation needs {needed}")
    corners = []
    corner = 0
    for face, count in enumerate(counts):
        for k in range(count):
            if interpolation == UsdGeom.Tokens.faceVarying:
                value = values[corner + k]
            elif interpolation in (UsdGeom.Tokens.vertex, UsdGeom.Tokens.varying):
                value = values[indices[corner + k]]
            elif interpolation == UsdGeom.Tokens.uniform:
                value = values[face]
            else:
                value = values[0]
            corners.append(finite_or_zero(value))
        corner += count
    return corners


def primvar_corners(primvar, counts, indices):
    """The primvar's (flattened) values per face corner, or None."""
    if not primvar or not primvar.HasValue():
        return None
    values = primvar.ComputeFlattened()
    if values is None:
        return None
    return per_corner(values, primvar.GetInterpolation(), counts, indices, primvar.GetName())


class BadMesh(ValueError):
    """A mesh that cannot be read, and why."""


def check_faces(points, counts, indices):
    """Faces that can be triangulated, over corners and points that exist: checked
    before anything the size of a face count is built."""
    for face, count in enumerate(counts):
        if count < 3:
            raise BadMesh(f"faceVertexCounts[{face}] is {count}; a face needs at least 3 vertices")
    if sum(counts) != len(indices):
        raise BadMesh(
            f"faceVertexCounts add up to {sum(counts)} corners, but faceVertexIndices has {len(indices)}"
        )
    for corner, index in enumerate(indices):
        if not 0 <= index < len(points):
            raise BadMesh(f"faceVertexIndices[{corner}] is {index}, but there are {len(points)} points")


def read_mesh(prim, cache, uv_primvars):
    try:
        return read_checked_mesh(prim, cache, uv_primvars)
    except BadMesh as e:
        fail(f"mesh {prim.GetPath()}: {e}")


def read_checked_mesh(prim, cache, uv_primvars):
    mesh = UsdGeom.Mesh(prim)
    points = mesh.GetPointsAttr().Get() or []
    counts = list(mesh.GetFaceVertexCountsAttr().Get() or [])
    indices = list(mesh.GetFaceVertexIndicesAttr().Get() or [])
    check_faces(points, counts, indices)
    world = cache.GetLocalToWorldTransform(prim)
    world_points = [list(world.Transform(Gf.Vec3d(*p))) for p in points]
    for k, p in enumerate(world_points):
        if not all(math.isfinite(x) for x in p):
            raise BadMesh(f"points[{k}] is {list(points[k])}, not finite in world space")
    normal_matrix = world.GetInverse().GetTranspose()
    mirrored = world.GetDeterminant() < 0
    if mesh.GetOrientationAttr().Get() == UsdGeom.Tokens.leftHanded:
        mirrored = not mirrored
    api = UsdGeom.PrimvarsAPI(prim)
    st = next((api.GetPrimvar(n) for n in uv_primvars if api.HasPrimvar(n)), None)
    uvs = primvar_corners(st, counts, indices) if st else None
    normals_primvar = api.GetPrimvar("normals") if api.HasPrimvar("normals") else None
    normals = primvar_corners(normals_primvar, counts, indices) if normals_primvar else None
    if normals is None and mesh.GetNormalsAttr().HasValue():
        normals = per_corner(
            mesh.GetNormalsAttr().Get(), mesh.GetNormalsInterpolation(), counts, indices, "normals"
        )
    if normals is not None:
        normals = [finite_or_zero(normal_matrix.TransformDir(Gf.Vec3d(*n)).GetNormalized()) for n in normals]
    # Fan-triangulate every face over its corners.
    triangles = []
    corner = 0
    for count in counts:
        for k in range(1, count - 1):
            tri = [corner, corner + k, corner + k + 1]
            triangles.append([tri[0], tri[2], tri[1]] if mirrored else tri)
        corner += count
    subsets = [s.GetPrim().GetName() for s in UsdGeom.Subset.GetAllGeomSubsets(mesh)]
    # Exporters such as Blender's put each mesh under an Xform named after
    # the object; that is the name people select by.
    parent = prim.GetParent()
    siblings = [c for c in parent.GetChildren() if c.IsA(UsdGeom.Mesh)] if parent else []
    named_by_parent = parent and parent.IsA(UsdGeom.Xform) and len(siblings) == 1
    return {
        "name": parent.GetName() if named_by_parent else prim.GetName(),
        "path": str(prim.GetPath()),
        "points": world_points,
        "corner_vertices": indices,
        "triangles": triangles,
        "uvs": uvs,
        "normals": normals,
        "faces": len(counts),
        "subsets": subsets,
        "material": read_material(prim, counts, indices, st),
    }


def connected_shader(shader_input):
    """The shader (through any node graphs) and output name an input's value
    comes from, or (None, None)."""
    if not shader_input.HasConnectedSource():
        return None, None
    for attribute in shader_input.GetValueProducingAttributes():
        name, kind = UsdShade.Utils.GetBaseNameAndType(attribute.GetName())
        if kind == UsdShade.AttributeType.Output:
            return UsdShade.Shader(attribute.GetPrim()), str(name)
    return None, None


def input_value(shader, name, default):
    shader_input = shader.GetInput(name)
    value = shader_input.Get() if shader_input else None
    return default if value is None else value


def read_texture(shader_input, prim, counts, indices, st):
    """A UsdUVTexture driving `shader_input`: its file, colour space, wrap,
    scale and bias, the primvar its st reads (through a UsdTransform2d, if
    one is there) and that primvar per face corner when it is not the one
    the mesh's `uvs` came from. Another kind of source is named by its id."""
    source, output = connected_shader(shader_input)
    if source is None:
        return None
    shader_id = str(source.GetIdAttr().Get() or "")
    if shader_id != "UsdUVTexture":
        return {"shader": shader_id or str(source.GetPrim().GetPath())}
    asset = input_value(source, "file", None)
    file = (asset.resolvedPath or asset.path) if asset else ""
    texture = {
        "shader": shader_id,
        "output": output,
        "file": file,
        "source_colour_space": str(input_value(source, "sourceColorSpace", "auto")),
        "wrap_s": str(input_value(source, "wrapS", "useMetadata")),
        "wrap_t": str(input_value(source, "wrapT", "useMetadata")),
        "scale": list(input_value(source, "scale", (1.0, 1.0, 1.0, 1.0)))[:3],
        "bias": list(input_value(source, "bias", (0.0, 0.0, 0.0, 0.0)))[:3],
    }
    st_input = source.GetInput("st")
    reader, _ = connected_shader(st_input) if st_input else (None, None)
    if reader is not None and str(reader.GetIdAttr().Get() or "") == "UsdTransform2d":
        texture["transform"] = {
            "rotation": float(input_value(reader, "rotation", 0.0)),
            "scale": list(input_value(reader, "scale", (1.0, 1.0))),
            "translation": list(input_value(reader, "translation", (0.0, 0.0))),
        }
        in_input = reader.GetInput("in")
        reader, _ = connected_shader(in_input) if in_input else (None, None)
    varname = None
    if reader is not None and str(reader.GetIdAttr().Get() or "").startswith("UsdPrimvarReader"):
        varname = str(input_value(reader, "varname", "") or "")
    api = UsdGeom.PrimvarsAPI(prim)
    if varname is None:
        texture["primvar"] = st.GetPrimvarName() if st else None
    else:
        texture["primvar"] = varname
        if not (st and st.GetPrimvarName() == varname):
            primvar = api.GetPrimvar(varname) if varname and api.HasPrimvar(varname) else None
            texture["uvs"] = primvar_corners(primvar, counts, indices) if primvar else None
            texture["missing"] = primvar is None
    return texture


def read_material(prim, counts=(), indices=(), st=None):
    """The bound material's surface shader (UsdPreviewSurface, or OpenPBR in
    MaterialX's context): its id, the values of its unconnected inputs, the
    names of the inputs a texture drives, and for each of those the texture
    (`read_texture`)."""
    material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()
    if not material:
        return None
    shader = None
    for context in ("mtlx", ""):
        source = material.ComputeSurfaceSource(context)
        candidate = source[0] if isinstance(source, tuple) else source
        if candidate:
            shader = candidate
            break
    if shader is None:
        return {"name": material.GetPrim().GetName(), "shader": "", "inputs": {}, "connected": []}
    inputs, connected, textures = {}, [], {}
    for shader_input in shader.GetInputs():
        name = shader_input.GetBaseName()
        if shader_input.HasConnectedSource():
            connected.append(name)
            texture = read_texture(shader_input, prim, counts, indices, st)
            if texture is not None:
                textures[name] = texture
            continue
        value = shader_input.Get()
        if value is None:
            continue
        inputs[name] = list(value) if hasattr(value, "__len__") else float(value)
    return {
        "name": material.GetPrim().GetName(),
        "shader": str(shader.GetIdAttr().Get() or ""),
        "inputs": inputs,
        "connected": connected,
        "textures": textures,
    }


def read_light(prim, cache):
    world = cache.GetLocalToWorldTransform(prim)
    light = UsdLux.LightAPI(prim)
    kind = prim.GetTypeName()
    return {
        "name": prim.GetName(),
        "type": kind,
        "intensity": light.GetIntensityAttr().Get() or 0.0,
        "exposure": light.GetExposureAttr().Get() or 0.0,
        "color": list(light.GetColorAttr().Get() or (1.0, 1.0, 1.0)),
        "position": list(world.Transform(Gf.Vec3d(0, 0, 0))),
        "direction": list(world.TransformDir(Gf.Vec3d(0, 0, -1)).GetNormalized()),
        "tangent": list(world.TransformDir(Gf.Vec3d(1, 0, 0)).GetNormalized()),
        "normalize": bool(light.GetNormalizeAttr().Get()),
        "diffuse": float(light.GetDiffuseAttr().Get() if light.GetDiffuseAttr().Get() is not None else 1.0),
        "scale": world.TransformDir(Gf.Vec3d(1, 0, 0)).GetLength(),
        "color_temperature": (
            float(light.GetColorTemperatureAttr().Get() or 6500.0)
            if light.GetEnableColorTemperatureAttr().Get()
            else None
        ),
        **shape_of(prim, kind),
        **shaping_of(prim),
    }


def shaping_of(prim):
    """The ShapingAPI cone (half-angle in degrees, softness), when one is authored."""
    cone = prim.GetAttribute("inputs:shaping:cone:angle")
    if not (cone and cone.HasAuthoredValue()):
        return {}
    softness = prim.GetAttribute("inputs:shaping:cone:softness")
    return {
        "cone_angle": float(cone.Get()),
        "cone_softness": float(softness.Get() or 0.0) if softness and softness.HasAuthoredValue() else 0.0,
    }


def shape_of(prim, kind):
    """The light's size attributes, in stage units and degrees, by kind."""

    def value(name, default):
        attribute = prim.GetAttribute(name)
        got = attribute.Get() if attribute and attribute.HasAuthoredValue() else None
        return default if got is None else got

    if kind == "DistantLight":
        return {"angle": float(value("inputs:angle", 0.53))}
    if kind == "SphereLight":
        return {
            "radius": float(value("inputs:radius", 0.5)),
            "treat_as_point": bool(value("treatAsPoint", False)),
        }
    if kind == "CylinderLight":
        return {
            "length": float(value("inputs:length", 1.0)),
            "radius": float(value("inputs:radius", 0.5)),
            "treat_as_line": bool(value("treatAsLine", False)),
        }
    if kind == "DiskLight":
        return {"radius": float(value("inputs:radius", 0.5))}
    if kind == "RectLight":
        return {
            "width": float(value("inputs:width", 1.0)),
            "height": float(value("inputs:height", 1.0)),
        }
    if kind == "DomeLight":
        texture = value("inputs:texture:file", None)
        path = texture.resolvedPath or texture.path if texture else ""
        return {"texture": path, "texture_format": str(value("inputs:texture:format", "automatic"))}
    return {}


def stage_contents(stage, uv_primvars):
    """What sssbake bakes from an open stage, as the JSON contract's dict; raises
    StageError when the stage cannot be baked as it is."""
    # A reference, payload or sublayer that cannot be found leaves prims out: refused, not
    # baked without them.
    errors = stage.GetCompositionErrors()
    if errors:
        fail(f"the stage does not compose: {str(errors[0]).split(' (')[0]}")
    cache = UsdGeom.XformCache(Usd.TimeCode.Default())
    meshes, lights = [], []
    for prim in stage.Traverse():
        if (
            UsdGeom.Imageable(prim)
            and UsdGeom.Imageable(prim).ComputeVisibility() == UsdGeom.Tokens.invisible
        ):
            continue
        if prim.IsA(UsdGeom.Mesh):
            meshes.append(read_mesh(prim, cache, uv_primvars))
        elif prim.HasAPI(UsdLux.LightAPI) or "Light" in prim.GetTypeName():
            lights.append(read_light(prim, cache))
    return {
        "meters_per_unit": UsdGeom.GetStageMetersPerUnit(stage),
        "documentation": stage.GetRootLayer().documentation,
        "up_axis": str(UsdGeom.GetStageUpAxis(stage)),
        "meshes": meshes,
        "lights": lights,
    }


def stage_json(stage, uv_primvars):
    """`stage_contents` as JSON text; NaN and infinities are refused, not written."""
    try:
        return json.dumps(stage_contents(stage, uv_primvars), allow_nan=False)
    except ValueError:
        fail("a value that is not finite (NaN or infinite) where the bake needs a number")


def open_stage(path):
    try:
        stage = Usd.Stage.Open(path)
    except Tf.ErrorException as e:  # each of usd-core's errors with its message quoted
        text = " ".join(str(e).split())
        reasons = [
            part.split(" : '", 1)[1].rstrip(" '") for part in text.split("Error in '")[1:] if " : '" in part
        ]
        fail(f"cannot open the stage: {'; '.join(reasons) or text}")
    if stage is None:
        fail("cannot open the stage")
    return stage


def main():
    if len(sys.argv) < 3:
        fail("usage: read_stage.py STAGE UV_PRIMVARS")
    sys.stdout.write(stage_json(open_stage(sys.argv[1]), sys.argv[2].split(",")))


if __name__ == "__main__":
    try:
        main()
    except StageError as e:
        print(e, file=sys.stderr)
        sys.exit(2)
