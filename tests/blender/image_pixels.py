"""Reads a rendered or saved image through Blender, for tests that assert on
its pixels."""
import bpy
import numpy as np


def image_rgb(path):
    """(height, width, 3) float64 RGB of the image at `path`, bottom row first
    (Blender's order); the image is removed from the .blend again."""
    image = bpy.data.images.load(str(path))
    try:
        width, height = image.size
        pixels = np.empty(4 * width * height, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[:, :, :3].astype(np.float64)
