"""A rendered view of a baked object compared with its map, pixel by pixel. A second
render of the same view gives each pixel's texture coordinates; the map, filtered as a
GPU samples it, is then what the pixel should show where the map is smooth at the scale
the pixel sees it."""

import numpy as np


def bilinear(image: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`image` (rows top to bottom) at texture coordinates with the origin at the top left
    (glTF's; flip v for Blender's), filtered bilinearly between texel centres."""
    height, width, _ = image.shape
    x = np.clip(u * width - 0.5, 0, width - 1)
    y = np.clip(v * height - 0.5, 0, height - 1)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, width - 1), np.minimum(y0 + 1, height - 1)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    top = image[y0, x0] * (1 - fx) + image[y0, x1] * fx
    bottom = image[y1, x0] * (1 - fx) + image[y1, x1] * fx
    return top * (1 - fy) + bottom * fy


def window_spread(image: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray]:
    """Per pixel and channel, the largest and smallest value in the size × size window
    whose top left is `size // 2` pixels up and left (edges repeated)."""
    before = size // 2
    padded = np.pad(image, ((before, size - 1 - before), (before, size - 1 - before), (0, 0)), mode="edge")
    rows, columns = image.shape[:2]
    windows = np.stack([padded[y : y + rows, x : x + columns] for y in range(size) for x in range(size)])
    return windows.max(axis=0), windows.min(axis=0)


def radiance_at(diffuse: np.ndarray, uv: np.ndarray, covered: np.ndarray) -> np.ndarray:
    """The map's radiance at each covered pixel's texture coordinates; 0 elsewhere."""
    radiance = np.zeros(covered.shape + (3,))
    radiance[covered] = bilinear(diffuse, uv[covered, 0], uv[covered, 1])
    return radiance


def smooth_pixels(
    expected: np.ndarray, covered: np.ndarray, uv: np.ndarray, diffuse: np.ndarray
) -> np.ndarray:
    """Pixel channels where the comparison is fair: the pixel's 3 × 3 neighbours all on the
    object and within 5% of each other; the texels around the 2 × 2 it filters (a 4 × 4
    window) within 5% (not a chart edge, where a coarser mip level mixes in the margin);
    and the pixel spanning at most 2 texels, so the mip level it reads stays in that
    window (not where a sphere's texture coordinates meet at its pole)."""
    inside = window_spread(covered[..., None].astype(float), 3)[1][..., 0] > 0.5
    high, low = window_spread(expected, 3)
    texel_high, texel_low = window_spread(diffuse, 4)
    height, width, _ = diffuse.shape
    # The 4 × 4 window at (tx + 1, ty + 1) starts one texel before the filtered pair.
    tx = np.clip((uv[..., 0] * width - 0.5).astype(int) + 1, 0, width - 1)
    ty = np.clip((uv[..., 1] * height - 0.5).astype(int) + 1, 0, height - 1)
    texel_smooth = texel_high[ty, tx] <= 1.05 * texel_low[ty, tx]
    texels = uv * np.array([width, height])
    step = np.maximum(
        np.abs(np.diff(texels, axis=0, append=texels[-1:])).max(axis=2),
        np.abs(np.diff(texels, axis=1, append=texels[:, -1:])).max(axis=2),
    )
    return (inside & (step <= 2.0))[..., None] & (high <= 1.05 * low) & texel_smooth


def assert_shows(look: np.ndarray, expected: np.ndarray, chosen: np.ndarray, tolerance: float = 0.02) -> str:
    """The view shows what is expected on the chosen pixel channels: at most `tolerance`
    apart anywhere, a median under 0.6%, and on average neither brighter (a second
    lighting) nor darker (a clip or a lost strength) by 0.3%. Returns those figures."""
    assert chosen.sum() > 2000, chosen.sum()
    relative = np.abs(look[chosen] - expected[chosen]) / expected[chosen]
    mean = np.mean(look[chosen] / expected[chosen])
    assert np.median(relative) < 0.006, np.median(relative)
    assert relative.max() < tolerance, relative.max()
    assert abs(mean - 1) < 0.003, mean
    return (
        f"{chosen.sum()} pixel channels: median {100 * np.median(relative):.2f}%, "
        f"largest {100 * relative.max():.2f}%, mean ratio {mean:.4f}"
    )


def nothing_outside(look: np.ndarray, covered: np.ndarray) -> bool:
    """Nothing drawn where the object is not, away from its antialiased silhouette."""
    near_object = window_spread(covered[..., None].astype(float), 5)[0][..., 0] > 0.5
    return bool(look[~near_object].max() == 0)
