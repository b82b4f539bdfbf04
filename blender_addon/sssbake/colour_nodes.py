"""Colour nodes Cycles applies to a texture's colour texel by texel with constant settings,
as functions of n × 3 linear RGB, so the add-on can apply them to the image's texels before
the library samples them."""

import numpy as np


def socket_by_id(node, identifier):
    """The input of `node` with `identifier` (the Mix node has several inputs per name)."""
    return next((s for s in node.inputs if s.identifier == identifier), None)


def colour_step(node):
    """For a node that changes a colour texel by texel with constant settings, the input the
    colour comes from and the change as a function of n × 3 linear RGB (Cycles' own formulas:
    svm_brightness_contrast, svm_math_gamma_color, invert, svm_mix_color); None for any other
    node or one whose settings are linked."""
    inputs = node.inputs

    def constant(*names):
        sockets = [inputs[n] for n in names]
        if any(s.is_linked for s in sockets):
            return None
        return [np.array(s.default_value[:3]) if s.type == "RGBA" else s.default_value for s in sockets]

    if node.type == "BRIGHTCONTRAST" and (values := constant("Bright", "Contrast")):
        bright, contrast = values
        return inputs["Color"], lambda rgb: np.maximum((1 + contrast) * rgb + bright - contrast / 2, 0)
    if node.type == "GAMMA" and (values := constant("Gamma")):
        (gamma,) = values
        return inputs["Color"], lambda rgb: np.where(rgb > 0, np.abs(rgb) ** gamma, rgb)
    if node.type == "INVERT" and (values := constant("Fac")):
        (factor,) = values
        return inputs["Color"], lambda rgb: (1 - factor) * rgb + factor * (1 - rgb)
    if node.type == "MIX" and node.data_type == "RGBA":
        factor, a, b = (socket_by_id(node, i) for i in ("Factor_Float", "A_Color", "B_Color"))
        return mix_step(node, factor, a, b, node.clamp_factor, node.clamp_result)
    if node.type == "MIX_RGB":
        return mix_step(node, inputs["Fac"], inputs["Color1"], inputs["Color2"], True, node.use_clamp)
    return None


def mix_step(node, factor, a, b, clamp_factor, clamp_result):
    """A Mix of blend Mix, Multiply, Add or Subtract whose factor and one colour are constant."""
    if factor.is_linked or a.is_linked == b.is_linked or node.blend_type not in BLENDS:
        return None
    f = min(max(factor.default_value, 0.0), 1.0) if clamp_factor else factor.default_value
    blend = BLENDS[node.blend_type]
    if a.is_linked:
        other = np.array(b.default_value[:3])
        change = lambda rgb: blend(rgb, other, f)
    else:
        other = np.array(a.default_value[:3])
        change = lambda rgb: blend(other, rgb, f)
    if clamp_result:
        return (a if a.is_linked else b), lambda rgb: np.clip(change(rgb), 0, 1)
    return (a if a.is_linked else b), change


# Cycles' svm_mix_color for the blends a texel-by-texel change can carry.
BLENDS = {
    "MIX": lambda a, b, f: (1 - f) * a + f * b,
    "MULTIPLY": lambda a, b, f: a * ((1 - f) + f * b),
    "ADD": lambda a, b, f: a + f * b,
    "SUBTRACT": lambda a, b, f: a - f * b,
}
