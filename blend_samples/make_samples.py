"""Builds the sample scenes (run inside Blender):

    blender -b --factory-startup --python blend_samples/make_samples.py -- [OUT_DIR]

Each builder returns the new object so scripts and tests can import them."""
import os
import sys

import bpy
import numpy as np


def _apply_all_modifiers(obj):
    bpy.context.view_layer.objects.active = obj
    for modifier in list(obj.modifiers):
        bpy.ops.object.modifier_apply(modifier=modifier.name)


def build_suzanne_closed(name="SuzanneClosed", voxel_size=0.045):
    """Suzanne made closed and genus 0: voxel remesh (fills the eye holes and
    welds the parts into one surface), then triangulated."""
    bpy.ops.mesh.primitive_monkey_add(size=2.0)
    obj = bpy.context.active_object
    obj.name = name
    remesh = obj.modifiers.new("Remesh", "REMESH")
    remesh.mode = "VOXEL"
    remesh.voxel_size = voxel_size
    obj.modifiers.new("Triangulate", "TRIANGULATE")
    _apply_all_modifiers(obj)
    return obj


def build_blob(name="Blob", subdivisions=5):
    """A generated closed genus-0 blob: an icosphere with a smooth radial bump field."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    obj = bpy.context.active_object
    obj.name = name
    mesh = obj.data
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    P = co.reshape(-1, 3).astype(np.float64)
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    r = 1.0 + 0.25 * np.sin(3 * P[:, 0]) * np.cos(2 * P[:, 1]) + 0.35 * P[:, 2] ** 2
    mesh.vertices.foreach_set("co", (P * r[:, None] * [1.0, 1.4, 0.9]).astype(np.float32).ravel())
    mesh.update()
    return obj


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_suzanne_closed()
    path = os.path.join(out_dir, "suzanne_closed.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    print(f"wrote {path}")


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    main(os.path.abspath(args[0] if args else os.path.dirname(os.path.abspath(__file__))))
