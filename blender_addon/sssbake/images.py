"""Baked maps into Blender images named `<object>_<output>`, updated in place: an image
that exists keeps its datablock (so every node using it keeps showing it) and takes the
new pixels, size and colour space, packed into the .blend or read from an OpenEXR file.
Each image is kept by a fake user, as the images Blender bakes into are, so a packed
result survives saving and reopening even when nothing uses it."""

import bpy
import numpy as np

DATA_OUTPUTS = {"thickness", "stretch", "area"}


def image_name(obj_name, output):
    """The image that holds map `output` of object `obj_name`."""
    return f"{obj_name}_{output}"


def colour_space(output):
    """Non-Color for data maps, linear for light; None when Blender has no linear space."""
    if output in DATA_OUTPUTS:
        return "Non-Color"
    names = {
        item.identifier
        for item in bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items
    }
    return next((n for n in ("Linear Rec.709", "Linear") if n in names), None)


def store_packed(name, output, pixels, resolution, changes):
    """Image `name` holding `pixels` (float RGBA, rows from v = 0 up), packed as OpenEXR."""
    image = _image_for(name, resolution, changes)
    if image.packed_file is not None:
        image.unpack(method="REMOVE")
    # A generated float image packs its own pixels; a file image would pack its file.
    image.source = "GENERATED"
    image.filepath = ""
    image.generated_width = image.generated_height = resolution
    image.use_generated_float = True
    image.pixels.foreach_set(pixels)
    image.file_format = "OPEN_EXR"
    image.pack()
    _finish(image, output)
    return image


def store_file(name, output, filepath, resolution, changes):
    """Image `name` reading the OpenEXR file `filepath` (kept blend-relative if given so)."""
    image = _image_for(name, resolution, changes)
    if image.packed_file is not None:
        image.unpack(method="REMOVE")
    image.filepath = filepath
    image.source = "FILE"
    image.reload()
    _finish(image, output)
    return image


def _finish(image, output):
    space = colour_space(output)
    if space:
        image.colorspace_settings.name = space
    image.use_fake_user = True
    image.update()


def _image_for(name, resolution, changes):
    image = bpy.data.images.get(name)
    if image is None:
        image = bpy.data.images.new(name, resolution, resolution, alpha=True, float_buffer=True)
        changes.record(lambda: _remove(name))
    else:
        state = ImageState(image)
        changes.record(state.restore)
    return image


def _remove(name):
    image = bpy.data.images.get(name)
    if image is not None:
        bpy.data.images.remove(image)


class ImageState:
    """What an image was before a bake touched it, enough to put it back in place (its
    file on disk is put back by the folder's own staging)."""

    def __init__(self, image):
        self.name = image.name
        self.source = image.source
        self.filepath = image.filepath
        self.packed = bytes(image.packed_file.data) if image.packed_file is not None else None
        self.colour_space = image.colorspace_settings.name
        self.fake_user = image.use_fake_user
        self.file_format = image.file_format
        self.alpha_mode = image.alpha_mode
        self.generated = (
            image.generated_width,
            image.generated_height,
            image.use_generated_float,
            image.generated_type,
            tuple(image.generated_color),
        )
        self.pixels = None
        if image.has_data and (image.is_dirty or (self.packed is None and self.source == "GENERATED")):
            # Pixels that live only in memory (a generated image, or unsaved painting).
            self.size = tuple(image.size)
            self.pixels = np.empty(len(image.pixels), dtype=np.float32)
            image.pixels.foreach_get(self.pixels)

    def restore(self):
        image = bpy.data.images[self.name]
        if image.packed_file is not None:
            image.unpack(method="REMOVE")
        if self.packed is not None:
            image.filepath = self.filepath
            image.source = "FILE"
            image.pack(data=self.packed, data_len=len(self.packed))
            if self.pixels is None:  # else the unsaved pixels are put back below
                image.reload()
        elif self.source == "GENERATED":
            image.source = "GENERATED"
            image.filepath = self.filepath
            width, height, use_float, kind, colour = self.generated
            image.generated_width, image.generated_height = width, height
            image.use_generated_float, image.generated_type = use_float, kind
            image.generated_color = colour
        else:
            # reload() only drops the cached pixels: they are read when next used, after
            # the folder's own rollback has put the old file back.
            image.filepath = self.filepath
            image.source = self.source
            image.reload()
        image.colorspace_settings.name = self.colour_space
        image.use_fake_user = self.fake_user
        image.file_format = self.file_format
        image.alpha_mode = self.alpha_mode
        if self.pixels is not None:
            # Last: a change of colour space reads the image again.
            if tuple(image.size) != self.size:
                image.scale(*self.size)
            image.pixels.foreach_set(self.pixels)
